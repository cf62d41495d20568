"""Reads the 8-bit RGB/RGBA PNGs `vknerf render` writes (no Pillow on the test machines): the
chunks' zlib stream, each row's filter undone."""
import struct
import zlib

import numpy as np


def read_png(path):
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat, width = 8, b"", None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos:pos + 4])
        kind, body = data[pos + 4:pos + 8], data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour = struct.unpack(">IIBB", body[:10])
            assert depth == 8 and colour in (2, 6), (depth, colour)
            channels = 3 if colour == 2 else 4
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride = width * channels
    out = np.zeros((height, stride), np.int32)
    for y in range(height):
        f, row = raw[y * (stride + 1)], np.frombuffer(raw, np.uint8, stride, y * (stride + 1) + 1).astype(np.int32)
        prev = out[y - 1] if y else np.zeros(stride, np.int32)
        cur = out[y]
        for x in range(stride):
            a = cur[x - channels] if x >= channels else 0
            b, c = prev[x], (prev[x - channels] if x >= channels else 0)
            if f == 0:
                pred = 0
            elif f == 1:
                pred = a
            elif f == 2:
                pred = b
            elif f == 3:
                pred = (a + b) // 2
            else:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
            cur[x] = (row[x] + pred) & 255
    return out.reshape(height, width, channels).astype(np.uint8)


def read_pfm(path):
    """A greyscale PFM (rows bottom to top) as (H, W) float32, rows top to bottom."""
    data = open(path, "rb").read()
    header, rest = data.split(b"\n", 1)
    assert header == b"Pf"
    size, rest = rest.split(b"\n", 1)
    scale, rest = rest.split(b"\n", 1)
    w, h = map(int, size.split())
    dtype = "<f4" if float(scale) < 0 else ">f4"
    return np.frombuffer(rest, dtype, w * h).reshape(h, w)[::-1].astype(np.float32)
