"""Writes a copy of a nerf_synthetic-style scene whose training photos have known, different exposures and
white balances, to measure a per-photo appearance embedding (the model learning each photo's exposure and
white balance while training).

Every photo of the split (default train) gets an exposure factor drawn uniformly from [--low, --high] and,
per colour channel, a white-balance factor drawn uniformly from [1 - wb, 1 + wb] (wb: --white-balance), so
that its R, G and B are multiplied by exposure * r, exposure * g and exposure * b. Kept simple on purpose: the
8-bit sRGB values are multiplied as stored (not in linear light), rounded, and clipped to [0, 255]; alpha is
untouched. The changed photos are written as PNGs into OUT/<split>_exposure/ (named after the frame's index
and its image's stem, as two frames may share a stem) and that split's json points at them, every other key,
top-level or per frame, kept. OUT/exposures_<split>.json lists each frame's file and its factors
[exposure, r, g, b]. The other splits' jsons are copied unchanged and their image folders linked (nothing
big is copied). The same --seed gives the same files.

Photos are read and written by png_file (no image library): 8-bit grey or RGB PNGs, with or without alpha,
not interlaced (grey comes out as RGB, as the channels get different factors). Ancillary chunks (gamma,
colour profile) are not carried over.

OUT must be new or empty, or one this tool wrote before (its .change_exposure.json marker lists what it made).

  python3 -m tools.scenes.change_exposure assets/tabletop /tmp/ce_test --low 0.7 --high 1.3 --white-balance 0.1
"""
import argparse
import json
import math
import os
import shutil

import numpy as np

from . import png_file
from .poses import IMAGE_EXTENSIONS, fail
from .scene_copy import (SPLITS, check_link_names, find_image, image_links, prepare_out, read_splits,
                         refuse_scene_folder, write_marker)
from .transforms_json import write_transforms

MARKER = ".change_exposure.json"
TOOL = "change_exposure"
FACTORS_ARE = ("[exposure, r, g, b]: the 8-bit sRGB R, G, B as stored times exposure * r, g, b, rounded, "
               "clipped to 0..255; alpha untouched")


def read_png(path):
    """(height, width, 3 or 4) uint8: RGB, and alpha where the file has it; png_file.PngError saying why not."""
    width, height, channels, rows = png_file.read(path)
    return np.frombuffer(b"".join(rows), np.uint8).reshape(height, width, channels)


def write_png(path, pixels):
    height, width, channels = pixels.shape
    png_file.write(path, width, height, channels, np.ascontiguousarray(pixels, np.uint8).reshape(height, -1))


def scale(pixels, gains):
    """The photo with R, G, B times gains (3 numbers), rounded and clipped to 0..255; alpha as it was."""
    out = pixels.copy()
    out[..., :3] = np.clip(np.rint(pixels[..., :3] * np.asarray(gains)), 0, 255).astype(np.uint8)
    return out


def check_factors(a):
    # Every factor must stay positive: a zero or negative one is no exposure a camera could have.
    for flag, v in (("--low", a.low), ("--high", a.high), ("--white-balance", a.white_balance)):
        if not math.isfinite(v):
            raise SystemExit(f"{flag}: must be a finite number, not {v}")
    if a.low <= 0:
        raise SystemExit(f"--low: must be positive (a factor of exposure), not {a.low:g}")
    if a.low > a.high:
        raise SystemExit(f"--low {a.low:g} is above --high {a.high:g}: the range [low, high] is empty")
    if not 0 <= a.white_balance < 1:
        raise SystemExit(f"--white-balance: must be in [0, 1) so that 1 - wb stays positive, not {a.white_balance:g}")


def draw_factors(seed, count, low, high, wb):
    """[[exposure, r, g, b]] per frame, in frame order, from one generator: the same seed, the same list."""
    rng = np.random.default_rng(seed)
    return [[float(rng.uniform(low, high))] + [float(v) for v in rng.uniform(1 - wb, 1 + wb, 3)]
            for _ in range(count)]


def source_images(scene, path, meta):
    """Each frame's image file, its header checked, so that bad input stops before OUT is touched."""
    found = []
    for i, fr in enumerate(meta["frames"]):
        image = find_image(scene, path, i, fr["file_path"])
        try:
            with open(image, "rb") as f:
                png_file.header(image, f.read(64))
        except png_file.PngError as e:
            fail(path, f"frames[{i}].file_path", f"names {image}, which {e.reason}")
        found.append(image)
    return found


def new_names(images):
    # The index keeps names apart when two frames share a stem (the same photo twice, or two folders).
    width = len(str(len(images) - 1))
    names = []
    for i, image in enumerate(images):
        stem, ext = os.path.splitext(os.path.basename(image))
        names.append(f"{i:0{width}d}_{stem if ext.lower() in IMAGE_EXTENSIONS else stem + ext}")
    return names


def write_exposures(path, settings, rows):
    # One frame a line, so that the file reads well and diffs well.
    lines = ["{"] + [f"  {json.dumps(k)}: {json.dumps(v)}," for k, v in settings.items()] + ['  "frames": [']
    lines += [f"    {json.dumps(r)}" + ("," if i + 1 < len(rows) else "") for i, r in enumerate(rows)]
    with open(path, "w") as f:
        f.write("\n".join(lines + ["  ]", "}", ""]))


def parse_args():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene", help="a folder with transforms_train.json, transforms_test.json (and _val)")
    ap.add_argument("out", help="the new scene folder")
    ap.add_argument("--low", type=float, default=0.7, help="smallest exposure factor (default 0.7)")
    ap.add_argument("--high", type=float, default=1.3, help="largest exposure factor (default 1.3)")
    ap.add_argument("--white-balance", type=float, default=0.1,
                    help="each channel's factor is drawn from [1 - this, 1 + this] (default 0.1)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--split", default="train", choices=SPLITS, help="the split whose photos are changed")
    a = ap.parse_args()
    check_factors(a)
    return a


def held_out_links(scene, metas, chosen):
    # Only the other splits' images are linked: the chosen split's photos are all rewritten.
    links = {}
    for split, m in metas.items():
        if split != chosen:
            links.update(image_links(scene, os.path.join(scene, f"transforms_{split}.json"), m))
    return links


def write_photos(out, src, meta, images, pngs, factors):
    """Writes each frame's changed photo; returns the frames pointing at them and the rows of the table."""
    frames, rows = [], []
    for i, (fr, image, png, f) in enumerate(zip(meta["frames"], images, pngs, factors)):
        try:
            pixels = read_png(image)
        except png_file.PngError as e:
            fail(src, f"frames[{i}].file_path", f"names {image}, which {e.reason}")
        write_png(os.path.join(out, png), scale(pixels, [f[0] * w for w in f[1:]]))
        new = dict(fr)  # every other key of the frame kept, in its place
        new["file_path"] = "./" + png[:-len(".png")]  # without the extension, as nerf_synthetic writes them
        frames.append(new)
        rows.append({"file_path": new["file_path"], "original": fr["file_path"], "factors": f})
    return frames, rows


def main():
    a = parse_args()
    refuse_scene_folder(a.scene, a.out)
    metas = read_splits(a.scene, a.split)
    src = os.path.join(a.scene, f"transforms_{a.split}.json")
    meta = metas[a.split]
    images = source_images(a.scene, src, meta)
    links = held_out_links(a.scene, metas, a.split)
    folder, table, jsons = f"{a.split}_exposure", f"exposures_{a.split}.json", [f"transforms_{s}.json" for s in metas]
    check_link_names(a.scene, links, jsons + [folder, table], MARKER, TOOL)

    factors = draw_factors(a.seed, len(images), a.low, a.high, a.white_balance)
    pngs = [f"{folder}/{n}.png" for n in new_names(images)]
    settings = {"split": a.split, "low": a.low, "high": a.high, "white_balance": a.white_balance, "seed": a.seed}
    prepare_out(a.out, MARKER, TOOL)
    # The marker first: a run stopped halfway leaves a folder the next run may still empty and rewrite.
    write_marker(a.out, MARKER, TOOL, a.scene, settings, sorted(links) + [folder + "/"] + pngs + jsons + [table])
    for name, target in sorted(links.items()):
        os.symlink(target, os.path.join(a.out, name))
    os.makedirs(os.path.join(a.out, folder))
    frames, rows = write_photos(a.out, src, meta, images, pngs, factors)
    for split in metas:
        name = f"transforms_{split}.json"
        if split == a.split:
            write_transforms(os.path.join(a.out, name), {k: v for k, v in meta.items() if k != "frames"}, frames)
        else:
            shutil.copyfile(os.path.join(a.scene, name), os.path.join(a.out, name))
    write_exposures(os.path.join(a.out, table), {**settings, "factors_are": FACTORS_ARE}, rows)
    exposure = [f[0] for f in factors]
    print(f"{a.out}: {len(frames)} photos of {a.split} in {folder}/ with exposure {min(exposure):.3g}.."
          f"{max(exposure):.3g} and white balance within {a.white_balance:g} (seed {a.seed}), listed in {table}; "
          f"{', '.join(f'transforms_{s}.json' for s in metas if s != a.split) or 'no other split'} copied; "
          f"linked {', '.join(sorted(links)) or 'nothing'}")


if __name__ == "__main__":
    main()
