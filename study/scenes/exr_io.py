# SPDX-License-Identifier: MIT
"""A small OpenEXR reader for system python3 + numpy (no OpenEXR module needed).

Reads single-part scanline files with NONE, RLE, ZIPS or ZIP compression and HALF, FLOAT or
UINT channels - what Blender writes with the codecs the study's scripts choose (ZIP) and what
the `ddof` command writes by default (ZIP). Tiled, multi-part, deep and PIZ/PXR24/B44/DWA files
are refused with a message.

    from exr_io import read_exr, psnr_srgb
    ch = read_exr("truth.exr")          # {"R": 2-D float32 array, ...}, top row first
    rgb = rgb_of(ch)                     # (h, w, 3), from R/G/B or <layer>.Combined.R/G/B
    print(psnr_srgb(rgb_a, rgb_b))       # the metric of `ddof --compare`

Run as a script it prints a file's channels, or the PSNR between two files' RGB:

    python3 exr_io.py FILE.exr             # channels and their ranges
    python3 exr_io.py A.exr B.exr          # PSNR of B against A (sRGB, as ddof --compare)
    python3 exr_io.py --png FILE.exr OUT.png
"""

import struct
import sys
import zlib

import numpy as np

_PIXEL_TYPES = {0: (np.uint32, 4), 1: (np.float16, 2), 2: (np.float32, 4)}
_LINES_PER_CHUNK = {0: 1, 1: 1, 2: 1, 3: 16}
_COMPRESSION_NAMES = {0: "NONE", 1: "RLE", 2: "ZIPS", 3: "ZIP", 4: "PIZ", 5: "PXR24",
                      6: "B44", 7: "B44A", 8: "DWAA", 9: "DWAB"}


def _cstr(data, pos):
    end = data.index(b"\0", pos)
    return data[pos:end].decode("latin-1"), end + 1


def _read_header(data):
    if data[:4] != b"\x76\x2f\x31\x01":
        raise ValueError("not an OpenEXR file")
    flags = struct.unpack_from("<I", data, 4)[0]
    if flags & 0x200:
        raise ValueError("tiled EXR files are not supported by exr_io.py")
    if flags & 0x1000:
        raise ValueError("multi-part EXR files are not supported by exr_io.py")
    if flags & 0x800:
        raise ValueError("deep EXR files are not supported by exr_io.py")
    pos = 8
    header = {}
    while data[pos] != 0:
        name, pos = _cstr(data, pos)
        kind, pos = _cstr(data, pos)
        size = struct.unpack_from("<i", data, pos)[0]
        pos += 4
        value = data[pos:pos + size]
        pos += size
        if kind == "chlist":
            channels, p = [], 0
            while value[p] != 0:
                cname, p = _cstr(value, p)
                ptype, _plinear, xs, ys = struct.unpack_from("<iB3xii", value, p)
                p += 16
                if xs != 1 or ys != 1:
                    raise ValueError("subsampled channel %s is not supported" % cname)
                channels.append((cname, ptype))
            header[name] = channels
        elif kind == "box2i":
            header[name] = struct.unpack("<4i", value)
        elif kind == "compression":
            header[name] = value[0]
        else:
            header[name] = (kind, value)
    return header, pos + 1


def _predict(raw):
    t = np.frombuffer(raw, dtype=np.uint8).astype(np.int64)
    if t.size == 0:
        return t.astype(np.uint8)
    d = t.copy()
    d[1:] -= 128
    return (np.cumsum(d) % 256).astype(np.uint8)


def _reorder(t, expected):
    out = np.empty(expected, dtype=np.uint8)
    half = (expected + 1) // 2
    out[0::2] = t[:half]
    out[1::2] = t[half:expected]
    return out.tobytes()


def _unrle(raw):
    out = bytearray()
    i = 0
    n = len(raw)
    while i < n:
        count = struct.unpack_from("b", raw, i)[0]
        i += 1
        if count < 0:
            out += raw[i:i - count]
            i -= count
        else:
            out += raw[i:i + 1] * (count + 1)
            i += 1
    return bytes(out)


def read_exr(path):
    """Returns {channel name: float32 array (height, width)}, rows top first."""
    with open(path, "rb") as f:
        data = f.read()
    header, pos = _read_header(data)
    comp = header.get("compression", 0)
    if comp not in _LINES_PER_CHUNK:
        raise ValueError("%s: %s compression is not supported by exr_io.py (use ZIP)"
                         % (path, _COMPRESSION_NAMES.get(comp, comp)))
    x0, y0, x1, y1 = header["dataWindow"]
    width, height = x1 - x0 + 1, y1 - y0 + 1
    channels = sorted(header["channels"], key=lambda c: c[0].encode("latin-1"))
    lines = _LINES_PER_CHUNK[comp]
    chunks = (height + lines - 1) // lines
    offsets = struct.unpack_from("<%dQ" % chunks, data, pos)
    planes = {name: np.empty((height, width), dtype=np.float32) for name, _ in channels}
    row_bytes = sum(_PIXEL_TYPES[t][1] for _, t in channels) * width
    for off in offsets:
        y, size = struct.unpack_from("<ii", data, off)
        raw = data[off + 8:off + 8 + size]
        nlines = min(lines, y1 - y + 1)
        expected = row_bytes * nlines
        if size < expected:
            if comp == 1:
                raw = _reorder(_predict(_unrle(raw)), expected)
            elif comp in (2, 3):
                raw = _reorder(_predict(zlib.decompress(raw)), expected)
            else:
                raise ValueError("%s: bad chunk size" % path)
        p = 0
        for line in range(nlines):
            row = y - y0 + line
            for name, ptype in channels:
                dtype, nbytes = _PIXEL_TYPES[ptype]
                planes[name][row] = np.frombuffer(raw, dtype=np.dtype(dtype).newbyteorder("<"),
                                                  count=width, offset=p)
                p += nbytes * width
    return planes


def rgb_of(channels, prefix=None):
    """(h, w, 3) float array: plain R/G/B, or <prefix>.R/G/B (a Blender Combined pass)."""
    if prefix is None:
        if "R" in channels:
            prefix = ""
        else:
            cands = sorted(n[:-2] for n in channels if n.endswith(".Combined.R"))
            if not cands:
                raise ValueError("no R/G/B or <layer>.Combined.R/G/B channels: %s"
                                 % ", ".join(sorted(channels)))
            prefix = cands[0]
    dot = prefix + "." if prefix else ""
    return np.stack([channels[dot + c] for c in "RGB"], axis=-1)


def alpha_of(channels, prefix=None):
    if prefix is None:
        prefix = "" if "A" in channels else sorted(
            n[:-2] for n in channels if n.endswith(".Combined.A"))[0]
    return channels[(prefix + "." if prefix else "") + "A"]


def depth_of(channels):
    for name in ("Z", "ViewLayer.Depth.Z", "depth", "Depth.Z"):
        if name in channels:
            return channels[name]
    cands = [n for n in channels if n.endswith(".Depth.Z")]
    if cands:
        return channels[cands[0]]
    raise ValueError("no depth channel")


def srgb_encode(v):
    """The encoding of `ddof --compare`: clamped to [0, 1], then the sRGB curve."""
    v = np.clip(np.nan_to_num(np.asarray(v, dtype=np.float64), nan=0.0), 0.0, 1.0)
    return np.where(v <= 0.0031308, 12.92 * v, 1.055 * np.power(v, 1.0 / 2.4) - 0.055)


def rmse_srgb(a, b, mask=None):
    d = srgb_encode(a) - srgb_encode(b)
    if mask is not None:
        d = d[mask]
    return float(np.sqrt(np.mean(d * d)))


def psnr_srgb(a, b, mask=None):
    """PSNR over RGB of sRGB-encoded, clamped values, peak 1 (as `ddof --compare`)."""
    r = rmse_srgb(a, b, mask)
    return float("inf") if r == 0.0 else -20.0 * np.log10(r)


def write_png(path, rgb, exposure=0.0):
    """8-bit sRGB PNG of a linear (h, w, 3) array (clamped), for looking at results."""
    img = np.round(srgb_encode(np.asarray(rgb) * 2.0 ** exposure) * 255.0).astype(np.uint8)
    h, w = img.shape[:2]
    raw = b"".join(b"\0" + img[y].tobytes() for y in range(h))

    def chunk(kind, payload):
        body = kind + payload
        return struct.pack(">I", len(payload)) + body + struct.pack(">I", zlib.crc32(body))
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def montage(images, columns, gap=4):
    """Tiles (h, w, 3) arrays of one size into one image, row by row."""
    h, w = images[0].shape[:2]
    rows = (len(images) + columns - 1) // columns
    out = np.ones((rows * h + (rows - 1) * gap, columns * w + (columns - 1) * gap, 3),
                  dtype=np.float32)
    for i, img in enumerate(images):
        r, c = divmod(i, columns)
        out[r * (h + gap):r * (h + gap) + h, c * (w + gap):c * (w + gap) + w] = img
    return out


def main(argv):
    if len(argv) == 4 and argv[1] == "--png":
        write_png(argv[3], rgb_of(read_exr(argv[2])))
    elif len(argv) == 2:
        ch = read_exr(argv[1])
        for name in sorted(ch):
            p = ch[name]
            print("%-28s %dx%d  min %.6g  max %.6g  mean %.6g"
                  % (name, p.shape[1], p.shape[0], p.min(), p.max(), p.mean()))
    elif len(argv) == 3:
        a, b = rgb_of(read_exr(argv[1])), rgb_of(read_exr(argv[2]))
        print("RMSE (sRGB) %.5f  PSNR %.2f dB" % (rmse_srgb(a, b), psnr_srgb(a, b)))
    else:
        print(__doc__)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
