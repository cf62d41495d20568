"""The one PNG reader and writer of the scene tools (change_exposure, upscale_scene): 8-bit grey or RGB,
with or without alpha, not interlaced. Python's standard library only (struct, zlib), so that a tool
without numpy can use it; rows are bytes, which a numpy caller turns into an array in one np.frombuffer.

Grey comes out as RGB (grey + alpha as RGBA): every caller works on colour. Palette, 16-bit and interlaced
PNGs are refused with a PngError naming the file; ancillary chunks (gamma, colour profile) are skipped on
reading and never written.
"""
import struct
import zlib

SIGNATURE = b"\x89PNG\r\n\x1a\n"
CHANNELS = {0: 1, 2: 3, 4: 2, 6: 4}  # PNG colour type: grey, RGB, grey + alpha, RGBA
COLOUR_TYPE = {c: t for t, c in CHANNELS.items()}


class PngError(ValueError):
    """Why a file is not read: str() is "<file>: <reason>" (one line); .reason alone for a caller that
    names the file in its own sentence ("frames[3] names <file>, which <reason>")."""

    def __init__(self, path, reason):
        super().__init__(f"{path}: {reason}")
        self.path, self.reason = path, reason


def chunks(data):
    """(kind, body) of each chunk up to IEND; stops quietly where data ends, so that a header check can
    read only the first bytes of a file."""
    pos = 8
    while pos + 8 <= len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        yield kind, data[pos + 8:pos + 8 + length]
        if kind == b"IEND":
            return
        pos += 12 + length


def header(path, data):
    """(width, height, channels of the file) from the start of a PNG (33 bytes are enough); PngError
    saying why if it is not one this module reads."""
    if data[:8] != SIGNATURE:
        raise PngError(path, "is not a PNG (this tool reads PNGs only)")
    kind, body = next(chunks(data), (None, b""))
    if kind != b"IHDR" or len(body) != 13:
        raise PngError(path, "is a PNG without a valid IHDR chunk")
    width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
    if depth != 8 or colour not in CHANNELS or interlace:
        raise PngError(path, "is not an 8-bit grey or RGB(A) PNG without interlacing (palette, 16-bit and "
                             "interlaced PNGs are not read)")
    if not width or not height:
        raise PngError(path, "is a PNG of no pixels")
    return width, height, CHANNELS[colour]


def unfilter(path, kind, line, prev, bpp):
    """Undoes one scanline's filter in place (PNG spec, section 9): each byte is stored as its difference
    from a guess made from the pixel to its left (a), above (b) and above-left (c), zero off the image."""
    n = len(line)
    if kind == 0:
        return
    if kind == 1:  # sub: a
        for i in range(bpp, n):
            line[i] = (line[i] + line[i - bpp]) & 255
    elif kind == 2:  # up: b
        line[:] = bytes((x + y) & 255 for x, y in zip(line, prev))
    elif kind == 3:  # average: (a + b) / 2, rounded down
        for i in range(bpp):
            line[i] = (line[i] + (prev[i] >> 1)) & 255
        for i in range(bpp, n):
            line[i] = (line[i] + ((line[i - bpp] + prev[i]) >> 1)) & 255
    elif kind == 4:  # Paeth: whichever of a, b, c is nearest a + b - c, ties to a then b
        for i in range(bpp):
            line[i] = (line[i] + prev[i]) & 255  # a = c = 0 off the left edge: the guess is b
        for i in range(bpp, n):
            a, b, c = line[i - bpp], prev[i], prev[i - bpp]
            p = a + b - c
            pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
            line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
    else:
        raise PngError(path, f"has an unknown PNG filter type {kind}")


def colour_row(line, channels):
    # Grey to RGB by slice assignment: one C-level copy per channel instead of a Python loop per pixel.
    if channels >= 3:
        return bytes(line)
    width = len(line) // channels
    out = bytearray(width * (channels + 2))
    grey = line[0::channels]
    for k in range(3):
        out[k::channels + 2] = grey
    if channels == 2:
        out[3::4] = line[1::2]
    return bytes(out)


def read(path):
    """(width, height, channels, rows): channels 3 (RGB) or 4 (RGBA), rows a list of `height` bytes of
    width * channels each, filters undone; PngError naming the file if it cannot be read."""
    with open(path, "rb") as f:
        data = f.read()
    width, height, channels = header(path, data)
    try:
        raw = zlib.decompress(b"".join(body for kind, body in chunks(data) if kind == b"IDAT"))
    except zlib.error as e:
        raise PngError(path, f"is a PNG whose image data does not decompress ({e})") from None
    stride = 1 + width * channels
    if len(raw) < height * stride:
        raise PngError(path, "is a PNG with less image data than its size needs (truncated?)")
    rows, prev = [], bytearray(stride - 1)  # the row above the first is zeros, as PNG defines
    for y in range(height):
        line = bytearray(raw[y * stride + 1:(y + 1) * stride])
        unfilter(path, raw[y * stride], line, prev, channels)
        rows.append(colour_row(line, channels))
        prev = line
    return width, height, channels + 2 if channels < 3 else channels, rows


def write(path, width, height, channels, rows):
    """Writes `height` rows of width * channels bytes each (anything bytes() takes, a numpy row too) as an
    8-bit PNG, channels 1 to 4 (grey, grey + alpha, RGB, RGBA). Unfiltered scanlines: the same pixels always
    give the same file, and file size is not the point of these tools."""
    rows = [bytes(r) for r in rows]
    if channels not in COLOUR_TYPE or len(rows) != height or any(len(r) != width * channels for r in rows):
        raise ValueError(f"{path}: not {height} rows of {width} pixels of 1 to 4 channels "
                         f"(got {len(rows)} rows, {channels} channels)")
    raw = b"".join(b"\x00" + r for r in rows)

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))
    ihdr = struct.pack(">IIBBBBB", width, height, 8, COLOUR_TYPE[channels], 0, 0, 0)
    with open(path, "wb") as f:
        f.write(SIGNATURE + chunk(b"IHDR", ihdr) + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))
