# Checks a rendered nerf_synthetic-layout scene and writes a contact sheet of some of its views.
# Usage: /usr/bin/python3 -m tools.scenes.check_scene assets/tabletop [--sheet docs/sample_scene.png]
# Needs Debian's python3-numpy and python3-pil. Exits 1 with one line per problem found.
import argparse
import colorsys
import json
import math
import os
import sys

import numpy as np
from PIL import Image, ImageDraw


def is_gold(rgba):
    # The lit gold metal is a pale yellow-orange (hue ~40 deg, saturation ~0.43); the noise cube's orange
    # is more saturated (> 0.6), so a probe that lands on the cube instead does not count.
    h, s, _ = colorsys.rgb_to_hsv(*(float(v) / 255 for v in rgba[:3]))
    return rgba[3] == 255 and 33 <= h * 360 <= 48 and 0.3 <= s <= 0.56


def check_split(root, split, radius, size, probe, problems):
    path = os.path.join(root, f"transforms_{split}.json")
    with open(path) as f:
        meta = json.load(f)
    lo, hi = np.array(meta["aabb"][0], float), np.array(meta["aabb"][1], float)
    if not (np.all(lo < hi) and np.all(lo >= -1.5) and np.all(hi <= 1.5)):
        problems.append(f"{path}: aabb {meta['aabb']} is not inside [-1.5, 1.5]^3")
    if not 0.1 < meta["camera_angle_x"] < 3.0:
        problems.append(f"{path}: camera_angle_x {meta['camera_angle_x']} is implausible")
    focal = 0.5 * size / math.tan(0.5 * meta["camera_angle_x"])
    positions, probe_hits = [], 0
    for fr in meta["frames"]:
        m = np.array(fr["transform_matrix"], float)
        name = fr["file_path"]
        rot, pos = m[:3, :3], m[:3, 3]
        positions.append(pos)
        if not name.startswith(f"./{split}/r_") or name.endswith(".png"):
            problems.append(f"{path}: file_path {name} is not ./{split}/r_<i> without extension")
        if np.abs(rot.T @ rot - np.eye(3)).max() > 1e-5 or abs(np.linalg.det(rot) - 1) > 1e-5:
            problems.append(f"{path}: {name} rotation is not rigid")
        if np.abs(m[3] - [0, 0, 0, 1]).max() > 0:
            problems.append(f"{path}: {name} last row is not 0 0 0 1")
        if abs(np.linalg.norm(pos) - radius) > 1e-4:
            problems.append(f"{path}: {name} is at radius {np.linalg.norm(pos):.5f}, not {radius}")
        # OpenGL convention: the camera looks down local -Z, so -Z (third column negated) points at the origin.
        if np.dot(-rot[:, 2], -pos / np.linalg.norm(pos)) < 1 - 1e-6:
            problems.append(f"{path}: {name} does not look at the origin down its -Z")
        if rot[2, 1] < 0:  # local +Y (second column) must lean towards world +Z: images are upright
            problems.append(f"{path}: {name} is upside down")
        png = os.path.join(root, name + ".png")
        img = np.asarray(Image.open(png))
        if img.shape != (size, size, 4):
            problems.append(f"{png}: shape {img.shape}, expected ({size}, {size}, 4)")
            continue
        alpha = img[..., 3]
        border = np.concatenate([alpha[0], alpha[-1], alpha[:, 0], alpha[:, -1]])
        if border.max() > 0:  # the content must stay inside the frame, the background transparent
            problems.append(f"{png}: opaque pixels on the image border")
        if (alpha == 255).mean() < 0.1:
            problems.append(f"{png}: almost empty ({(alpha == 255).mean():.3f} opaque)")
        # Every opaque pixel must lie inside the projected aabb (its 2-D bounding rectangle, 1 px slack for
        # antialiasing): otherwise the aabb would cut content off.
        corners = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])])
        cc = (corners - pos) @ rot
        cu, cv = size / 2 + focal * cc[:, 0] / -cc[:, 2], size / 2 - focal * cc[:, 1] / -cc[:, 2]
        ys, xs = np.nonzero(alpha)
        if len(xs) and (xs.min() + 0.5 < cu.min() - 1 or xs.max() + 0.5 > cu.max() + 1 or
                        ys.min() + 0.5 < cv.min() - 1 or ys.max() + 0.5 > cv.max() + 1):
            problems.append(f"{png}: content outside the projected aabb")
        # Project the gold sphere's centre with the pinhole model in the OpenGL convention (looking down -Z,
        # +Y up, image rows downwards): it must land on gold. This ties the matrices to the pixels.
        pc = rot.T @ (np.array(probe) - pos)
        u, v = size / 2 + focal * pc[0] / -pc[2], size / 2 - focal * pc[1] / -pc[2]
        if pc[2] < 0 and 0 <= u < size and 0 <= v < size:
            probe_hits += is_gold(img[int(v), int(u)])
    # Highlights, reflections and the ring in front of the sphere cover the centre in some views (~80% hit);
    # a mirrored or flipped convention lands on the sphere by chance only (probes moved across an axis: <20%).
    if probe_hits < 0.6 * len(meta["frames"]):
        problems.append(f"{path}: the gold sphere's centre projects onto gold in only {probe_hits} views")
    print(f"{split}: gold sphere centre projects onto gold in {probe_hits}/{len(meta['frames'])} views")
    return meta, np.array(positions)


def contact_sheet(root, views, out, scale=2, cols=6):
    tile = 100 * scale
    rows = math.ceil(len(views) / cols)
    sheet = Image.new("RGB", (cols * tile, rows * tile), (255, 255, 255))
    # A light checkerboard behind the views shows where they are transparent.
    draw = ImageDraw.Draw(sheet)
    for y in range(0, rows * tile, 10):
        for x in range(0, cols * tile, 10):
            if (x // 10 + y // 10) % 2:
                draw.rectangle([x, y, x + 9, y + 9], fill=(228, 228, 228))
    for i, name in enumerate(views):
        img = Image.open(os.path.join(root, name + ".png")).convert("RGBA")
        img = img.resize((tile, tile), Image.LANCZOS)
        sheet.paste(img, ((i % cols) * tile, (i // cols) * tile), img)
    # A 256-colour palette keeps the sheet small enough to commit (~100 KB) and looks the same at this size.
    sheet.quantize(256, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE).save(out, optimize=True)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("scene")
    p.add_argument("--radius", type=float, default=4.0)
    p.add_argument("--size", type=int, default=100)
    p.add_argument("--sheet", help="write a contact sheet PNG here")
    p.add_argument("--probe", type=float, nargs=3, default=[0.43, 0.34, 0.02],
                   help="centre of the gold sphere (tools/scenes/make_scene.py: sphere location)")
    args = p.parse_args()
    problems = []
    train, ptrain = check_split(args.scene, "train", args.radius, args.size, args.probe, problems)
    test, ptest = check_split(args.scene, "test", args.radius, args.size, args.probe, problems)
    if train["aabb"] != test["aabb"] or train["camera_angle_x"] != test["camera_angle_x"]:
        problems.append("train and test disagree on aabb or camera_angle_x")
    # Test views must be new positions: report the closest one to any training camera.
    gap = min(np.linalg.norm(ptrain - q, axis=1).min() for q in ptest)
    elev = np.degrees(np.arcsin(np.concatenate([ptrain, ptest])[:, 2] / args.radius))
    print(f"{len(ptrain)} train + {len(ptest)} test views; elevation {elev.min():.1f} to {elev.max():.1f} deg; "
          f"nearest test-to-train camera distance {gap:.3f}; aabb {train['aabb']}")
    if gap < 0.3:  # make_scene.py keeps test cameras >= 5 degrees (0.35 at radius 4) from every training one
        problems.append(f"a test camera is within {gap:.3f} of a training camera")
    if args.sheet:
        views = [f["file_path"] for f in train["frames"][:9]] + [f["file_path"] for f in test["frames"][:3]]
        contact_sheet(args.scene, views, args.sheet)
        print(f"contact sheet: {args.sheet} ({os.path.getsize(args.sheet)} bytes)")
    for line in problems:
        print(line, file=sys.stderr)
    sys.exit(1 if problems else 0)


main()
