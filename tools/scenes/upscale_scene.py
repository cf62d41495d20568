"""Writes a large copy of a nerf_synthetic-style scene for testing the memory path of big datasets:
every image enlarged by an integer factor (pixel replication), the transforms files copied (their
camera_angle_x holds for any resolution), train frames repeated until there are --frames of them.
Python's standard library only (8-bit RGBA or RGB PNGs, not interlaced).

  python3 -m tools.scenes.upscale_scene assets/tabletop /tmp/tabletop800 --factor 8 --frames 100
"""
import argparse
import json
import os
import struct
import zlib


def read_png(path):
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise SystemExit(f"{path}: not a PNG")
    pos, idat, width = 8, b"", 0
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            if depth != 8 or colour not in (2, 6) or interlace:
                raise SystemExit(f"{path}: only 8-bit RGB/RGBA PNGs without interlacing")
            channels = 4 if colour == 6 else 3
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw, stride, rows, prev = zlib.decompress(idat), width * channels, [], bytearray(width * channels)
    for y in range(height):
        f, line = raw[y * (stride + 1)], bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            a = line[i - channels] if i >= channels else 0
            b, c = prev[i], prev[i - channels] if i >= channels else 0
            if f == 1: line[i] = (line[i] + a) & 255
            elif f == 2: line[i] = (line[i] + b) & 255
            elif f == 3: line[i] = (line[i] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                line[i] = (line[i] + (a if pa <= pb and pa <= pc else b if pb <= pc else c)) & 255
        rows.append(bytes(line))
        prev = line
    if channels == 3:
        rows = [b"".join(r[i:i + 3] + b"\xff" for i in range(0, len(r), 3)) for r in rows]
    return width, height, rows


def write_png(path, width, height, rows):
    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)
    raw = b"".join(b"\x00" + r for r in rows)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 6, 0, 0, 0)) +
                chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))


def enlarge(src, dst, factor):
    w, h, rows = read_png(src)
    big = [b"".join(r[i:i + 4] * factor for i in range(0, len(r), 4)) for r in rows]
    write_png(dst, w * factor, h * factor, [r for r in big for _ in range(factor)])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene")
    ap.add_argument("out")
    ap.add_argument("--factor", type=int, default=8)
    ap.add_argument("--frames", type=int, default=0, help="train frames to write (default: as many as the scene has)")
    a = ap.parse_args()
    done = {}
    for split in ("train", "val", "test"):
        name = os.path.join(a.scene, f"transforms_{split}.json")
        if not os.path.exists(name):
            continue
        j = json.load(open(name))
        frames = j["frames"]
        want = a.frames if split == "train" and a.frames else len(frames)
        out_frames = []
        for k in range(want):
            fr = dict(frames[k % len(frames)])
            src = fr["file_path"]
            rel = src + f"_{k // len(frames)}" if k >= len(frames) else src
            target = os.path.normpath(os.path.join(a.out, rel + ".png"))
            os.makedirs(os.path.dirname(target), exist_ok=True)
            if target not in done:
                enlarge(os.path.normpath(os.path.join(a.scene, src + ".png")), target, a.factor)
                done[target] = True
            fr["file_path"] = rel
            out_frames.append(fr)
        j["frames"] = out_frames
        json.dump(j, open(os.path.join(a.out, f"transforms_{split}.json"), "w"), indent=2)
        print(f"{split}: {len(out_frames)} frames")


if __name__ == "__main__":
    main()
