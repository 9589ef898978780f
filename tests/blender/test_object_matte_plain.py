# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's object matte packing (object_matte.py), without bpy: Cryptomatte's
sub-layers (CryptoObject00, 01, ...: r, g, b, a = id, coverage, id, coverage of ranks 2k and
2k + 1) become per pixel 2 * ranks interleaved channels in rank order, every float's bits kept
(ids whose bits are a NaN's, a denormal's, a negative zero's or the largest exponent's are still
ids); sub-layers of another size are refused; the sub-layer count of a Cryptomatte depth is
capped at the library's 16 ranks.

    python3 test_object_matte_plain.py      (a python3 with numpy, or Blender's Python:
    blender -b --python test_object_matte_plain.py)
"""

import array
import os
import random
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plain_checks  # noqa: E402

plain_checks.import_from_addon()
import object_matte  # noqa: E402

checks = plain_checks.Checks("test_object_matte_plain")
check = checks.check

# Bits no arithmetic on Python floats would keep: a signalling NaN, denormals, -0, inf.
SPECIAL = [0x7f800001, 0xffa00000, 0x00000001, 0x807fffff, 0x80000000, 0x7f800000, 0x2c388f97]


def floats(bits):
    return array.array("f", array.array("I", bits).tobytes())


def bits_of(buf):
    return list(array.array("I", buf.tobytes()))


rng = random.Random(7)
for count, pixels in ((1, 5), (3, 7), (8, 4)):
    # layer k, pixel p, channel c: a known word; specials spread over ids.
    words = [[[rng.getrandbits(32) for _c in range(4)] for _p in range(pixels)]
             for _k in range(count)]
    for n, special in enumerate(SPECIAL):
        words[n % count][n % pixels][2 * (n % 2)] = special
    layers = [floats([w for px in layer for w in px]) for layer in words]
    buf, channels = object_matte.pack(layers, pixels)
    check(channels == 4 * count, "%d sub-layers: %d channels" % (count, channels))
    want = [words[k][p][c] for p in range(pixels) for k in range(count) for c in range(4)]
    got = bits_of(buf)
    check(got == want, "%d sub-layers: the packed bits differ at %d of %d values"
          % (count, sum(a != b for a, b in zip(got, want)), len(want)))
    # rank r of pixel p: (id, coverage) at channels 2r, 2r + 1 = sub-layer r // 2's r,g or b,a
    ok = all(got[p * channels + 2 * r + i] == words[r // 2][p][2 * (r % 2) + i]
             for p in range(pixels) for r in range(2 * count) for i in range(2))
    check(ok, "%d sub-layers: ranks are not in order" % count)

for bad, why in (([], "no sub-layer"), ([floats([0] * 8), floats([0] * 4)], "a short one")):
    try:
        object_matte.pack(bad, 2)
        check(False, "%s was accepted" % why)
    except ValueError:
        pass

check([object_matte.layer_count(d) for d in (0, 1, 2, 3, 6, 7, 16, 40)]
      == [0, 1, 1, 2, 3, 4, 8, 8], "layer counts of Cryptomatte depths")
check(object_matte.slots(3) == ["matte00_", "matte01_", "matte02_"],
      "slots: %r" % object_matte.slots(3))
checks.finish()
