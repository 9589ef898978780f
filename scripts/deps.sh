# SPDX-License-Identifier: MIT
# deps.sh - sourced by the other scripts: installs the Debian packages a step needs, if missing.
# On a fresh Debian 12 machine this is what makes `bash scripts/test.sh` work with no set-up.

# ensure_packages PKG...: apt-get installs whichever of PKG are not installed yet.
ensure_packages() {
    local missing=()
    local pkg
    for pkg in "$@"; do
        dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" ||
            missing+=("$pkg")
    done
    [ ${#missing[@]} -eq 0 ] && return 0
    echo "Installing missing packages: ${missing[*]}"
    local sudo=()
    if [ "$(id -u)" -ne 0 ]; then
        command -v sudo >/dev/null || { echo "error: need root or sudo to install ${missing[*]}" >&2; return 1; }
        sudo=(sudo)
    fi
    export DEBIAN_FRONTEND=noninteractive
    "${sudo[@]}" apt-get update -q
    "${sudo[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
}

# The packages every build needs.
BUILD_PACKAGES=(build-essential cmake ninja-build pkg-config libpng-dev libopenexr-dev libdeflate-dev zlib1g-dev libcjson-dev libgl-dev libegl-dev libegl1-mesa-dev libosmesa6-dev)

# Tools some tests use when present (they are skipped without): OpenEXR's exrheader reads the
# DWAA/DWAB files exrio writes (tests/exr, exr_dwa_exrheader).
TEST_TOOL_PACKAGES=(openexr)
