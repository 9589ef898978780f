#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Raw premultiplied float RGBA (cards_demo picture) -> an sRGB PNG over a mid grey.
    to_png.py IN.rgba WIDTH HEIGHT OUT.png"""
import struct
import sys
import zlib

import numpy as np


def main():
    src, w, h, dst = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
    img = np.fromfile(src, dtype=np.float32).reshape(h, w, 4).astype(np.float64)
    rgb = img[..., :3] + (1.0 - img[..., 3:4]) * 0.18  # premultiplied over grey
    rgb = np.clip(rgb, 0.0, 1.0)
    srgb = np.where(rgb <= 0.0031308, 12.92 * rgb, 1.055 * rgb ** (1 / 2.4) - 0.055)
    rows = (np.round(srgb * 255)).astype(np.uint8)
    raw = b"".join(b"\0" + rows[y].tobytes() for y in range(h))

    def chunk(kind, data):
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    open(dst, "wb").write(png)


if __name__ == "__main__":
    main()
