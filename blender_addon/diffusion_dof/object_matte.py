# SPDX-License-Identifier: GPL-3.0-or-later
"""The object matte (Cryptomatte's CryptoObject pass) as the library takes it, without bpy.

Blender writes a view layer's CryptoObject pass as sub-layers CryptoObject00, 01, ... of RGBA:
sub-layer k holds ranks 2k and 2k + 1 as (r, g) = (id, coverage) and (b, a) = (id, coverage),
the id a float whose bits name the object (compared bit for bit), the ranks by coverage, most
first. ddof_render_frame_with_matte takes per pixel 2 * ranks channels, interleaved: so a
pixel's channels are its sub-layers' RGBA one after the other. The floats are copied as 32-bit
words (numpy, which Blender bundles, over uint32 views): never through a float operation.
"""

import numpy as np

if __package__:
    from . import ddof_abi as abi
else:  # loaded as a plain module by a python3 without the package (tests/blender): beside it
    import ddof_abi as abi

SOCKET = "CryptoObject%02d"  # the Render Layers node's outputs, 3.4 to 5.x
SLOT = "matte%02d_"          # the managed File Output node's file names (+ the frame number)
MAX_LAYERS = abi.MATTE_MAX_RANKS // 2  # two ranks per sub-layer


def layer_count(depth):
    """The sub-layers Blender writes for a Cryptomatte depth (ranks), capped at the library's
    most ranks: (depth + 1) // 2, at most MAX_LAYERS."""
    return max(0, min(MAX_LAYERS, (int(depth) + 1) // 2))


def slots(count):
    """The File Output slots of `count` sub-layers, in order."""
    return [SLOT % k for k in range(count)]


def pack(layers, pixel_count):
    """(buffer, channels): the sub-layers' RGBA buffers (float32 buffers of pixel_count * 4
    each, in order) interleaved per pixel into one float32 array of pixel_count * 4 *
    len(layers), so that pixel p's channels 4k .. 4k + 3 are sub-layer k's r, g, b, a (ranks 2k
    and 2k + 1 as (id, coverage)). The bits of every float are kept. Raises ValueError on a
    buffer of another size or without layers."""
    if not layers:
        raise ValueError("an object matte needs at least one sub-layer")
    words = []
    for k, layer in enumerate(layers):
        if len(layer) != 4 * pixel_count:
            raise ValueError("sub-layer %d of the object matte has %d values, not %d"
                             % (k, len(layer), 4 * pixel_count))
        words.append(np.frombuffer(layer, dtype=np.uint32).reshape(pixel_count, 4))
    out = np.concatenate(words, axis=1).view(np.float32).ravel()
    return out, 4 * len(layers)
