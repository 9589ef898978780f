#!/bin/sh
# SPDX-License-Identifier: MIT
# The installed ddof-farm: the package lives in ../share/ddof/farm (plugin/apps/CMakeLists.txt).
here=$(dirname "$(readlink -f "$0")")
exec python3 "$here/../share/ddof/farm/ddof-farm" "$@"
