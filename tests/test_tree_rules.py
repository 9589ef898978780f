#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""scripts/circles.py's rules for libddof/src's parts, on a copy of the tree with one break
planted at a time: each must be found, and the tree as it is must have none."""
import os
import shutil
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scripts"))
import circles  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")


def breaks_with(plant):
    """part_breaks on a copy of libddof/src after plant(src) has changed it."""
    with tempfile.TemporaryDirectory() as tmp:
        src = os.path.join(tmp, circles.PARTS_ROOT)
        shutil.copytree(os.path.join(ROOT, circles.PARTS_ROOT), src)
        plant(src)
        return circles.part_breaks(tmp)


def write(src, path, text):
    os.makedirs(os.path.dirname(os.path.join(src, path)), exist_ok=True)
    with open(os.path.join(src, path), "w", encoding="utf-8") as f:
        f.write(text)


def expect(name, found, fragment):
    if not any(fragment in message for message in found):
        sys.exit("%s: expected a break naming %r, got %r" % (name, fragment, found))
    print("%s: found (%s)" % (name, fragment))


def main():
    found = circles.part_breaks(ROOT)
    if found:
        sys.exit("the tree breaks its own rules: %r" % found)
    if not os.path.isdir(os.path.join(ROOT, circles.PARTS_ROOT, "layers", circles.GL_FOLDER)):
        sys.exit("layers/ has no gl/ folder: the planted GL cases below would test nothing")
    print("the tree: no break")

    expect("a part's GL code including its own part's header",
           breaks_with(lambda s: write(s, "layers/gl/planted.c", '#include "layers.h"\n')),
           'layers/gl/planted.c includes "layers.h"')
    expect("a part's GL code including a lower part's header by path",
           breaks_with(lambda s: write(s, "cards/gl/planted.h",
                                       '#include "runtime/internal.h"\n')),
           'cards/gl/planted.h includes "runtime/internal.h"')
    expect("a subfolder of a part other than gl/",
           breaks_with(lambda s: write(s, "layers/cpu/planted.c", "\n")),
           "layers/cpu/ is not a part's gl/ folder")
    expect("an include of a part above",
           breaks_with(lambda s: write(s, "passes/planted.c", '#include "layers/layers.h"\n')),
           "layers/ is above passes/")
    expect("a file outside the parts",
           breaks_with(lambda s: write(s, "planted.c", "\n")), "planted.c stands outside")
    # GL code may include the GL module's headers and its own folder's by bare name.
    ok = breaks_with(lambda s: write(s, "layers/gl/planted.c",
                                     '#include "gl_layers.h"\n#include "gl_solve.h"\n'))
    if ok:
        sys.exit("GL code including the module's headers was refused: %r" % ok)
    print("GL code including the module's headers: no break")


if __name__ == "__main__":
    main()
