"""Writes a large copy of a nerf_synthetic-style scene for testing the memory path of big datasets:
every image enlarged by an integer factor (pixel replication), the transforms files copied (their
camera_angle_x holds for any resolution), train frames repeated until there are --frames of them.
Python's standard library only, no numpy (PNGs through png_file: 8-bit grey or RGB, with or without alpha,
not interlaced); every copy is written as RGBA.

  python3 -m tools.scenes.upscale_scene assets/tabletop /tmp/tabletop800 --factor 8 --frames 100
"""
import argparse
import json
import os

from . import png_file


def rgba_rows(rows, channels):
    # One layout to enlarge and write: RGB gets an opaque alpha, by slice assignment rather than per pixel.
    if channels == 4:
        return rows
    out = []
    for r in rows:
        line = bytearray(b"\xff" * (len(r) // 3 * 4))
        for k in range(3):
            line[k::4] = r[k::3]
        out.append(bytes(line))
    return out


def enlarge(src, dst, factor):
    try:
        w, h, channels, rows = png_file.read(src)
    except png_file.PngError as e:
        raise SystemExit(str(e)) from None
    big = [b"".join(r[i:i + 4] * factor for i in range(0, len(r), 4)) for r in rgba_rows(rows, channels)]
    png_file.write(dst, w * factor, h * factor, 4, [r for r in big for _ in range(factor)])


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
