# Second half of tools/scenes/make_ffwd_capture.sh: turns make_ffwd_capture.py's renders (<capture>/render) into the
# forward-facing capture as LLFF ships its scenes (NeRF's nerf_llff_data), and the same cameras as a
# transforms.json without a box, so that the two loaders can be compared:
#   <capture>/poses_bounds.npy: N x 17 float64, per image (in file-name order) the 3 x 5 matrix [R | t | hwf]
#     flattened row by row, then the near and far bounds. R's columns are the camera's [down, right, back]
#     axes in world coordinates (NeRF's load_llff turns them into OpenGL's [right, up, back] = [col1, -col0,
#     col2]), t the camera's centre, hwf = (height, width, focal) of the full-resolution images; the bounds
#     are z-depth percentiles of what the image sees (make_ffwd_capture.py: the 0.1st and 99.9th, as LLFF's
#     imgs2poses takes them from COLMAP's points);
#   <capture>/images/IMG_NNNN.JPG at full resolution (a phone's JPEGs), images_2/ and images_4/ with
#     imageNNN.png at 1/2 and 1/4 (as the shipped scenes' downscaled folders are named), block means in
#     linear light;
#   <json>/transforms.json: fl_x fl_y cx cy w h of the 1/2 images, frames with file_path and the OpenGL
#     camera-to-world transform_matrix, no aabb or aabb_scale; transforms_train.json / transforms_test.json
#     hold out every 8th image from the first (LLFF's llffhold 8); <json>/images/ holds images_2's files.
# Then it checks what it wrote: poses_bounds.npy read back through load_llff's convention gives transforms.json's
# matrices, hwf scales to its intrinsics, the images are the stated sizes and the JSON images are images_2's.
# Usage: /usr/bin/python3 -m tools.scenes.llff_capture CAPTURE --json CAPTURE-json   (from the repository root)
import argparse
import json
import os
import shutil
import sys

import numpy as np
from PIL import Image

from .transforms_json import write_transforms
from .warp import downscale

LLFF_HOLD = 8  # the NeRF papers' test views: every 8th image


def llff_row(c2w, hwf, near, far):
    # OpenGL camera-to-world [right, up, back | centre] -> LLFF's [down, right, back | centre | hwf] + bounds.
    m = np.asarray(c2w, float)
    rot = np.stack([-m[:3, 1], m[:3, 0], m[:3, 2]], axis=1)
    return np.concatenate([np.concatenate([rot, m[:3, 3:4], np.array(hwf, float)[:, None]], axis=1).ravel(),
                           [near, far]])


def load_llff_c2w(poses_bounds):
    # What NeRF's load_llff.py does with the file, up to its recentring: OpenGL camera-to-world, hwf, bounds.
    poses = poses_bounds[:, :-2].reshape([-1, 3, 5])
    c2w = np.concatenate([poses[:, :, 1:2], -poses[:, :, 0:1], poses[:, :, 2:4]], axis=2)
    return c2w, poses[:, :, 4], poses_bounds[:, -2:]


def main():
    p = argparse.ArgumentParser()
    p.add_argument("capture", help="folder with render/render.json from tools/scenes/make_ffwd_capture.py; LLFF goes here")
    p.add_argument("--json", required=True, help="folder for the transforms.json twin (1/2-resolution images)")
    args = p.parse_args()
    with open(os.path.join(args.capture, "render", "render.json")) as f:
        meta = json.load(f)
    cam, views = meta["camera"], meta["views"]
    w, h, focal = cam["w"], cam["h"], cam["focal"]
    for folder in ("images", "images_2", "images_4"):
        os.makedirs(os.path.join(args.capture, folder), exist_ok=True)
    os.makedirs(os.path.join(args.json, "images"), exist_ok=True)

    rows, frames = [], []
    for i, view in enumerate(views):
        img = np.asarray(Image.open(os.path.join(args.capture, "render", view["image"])).convert("RGB"))
        Image.fromarray(img).save(os.path.join(args.capture, "images", f"IMG_{i:04d}.JPG"), quality=95)
        for factor in (2, 4):
            Image.fromarray(downscale(img, factor)).save(
                os.path.join(args.capture, f"images_{factor}", f"image{i:03d}.png"), optimize=True)
        shutil.copyfile(os.path.join(args.capture, "images_2", f"image{i:03d}.png"),
                        os.path.join(args.json, "images", f"image{i:03d}.png"))
        rows.append(llff_row(view["transform_matrix"], (h, w, focal), view["near"], view["far"]))
        frames.append({"file_path": f"images/image{i:03d}.png", "transform_matrix": view["transform_matrix"]})
    np.save(os.path.join(args.capture, "poses_bounds.npy"), np.array(rows, dtype=np.float64))
    head = {"fl_x": focal / 2, "fl_y": focal / 2, "cx": w / 4, "cy": h / 4, "w": w // 2, "h": h // 2}
    write_transforms(os.path.join(args.json, "transforms.json"), head, frames)
    test = [i for i in range(len(frames)) if i % LLFF_HOLD == 0]
    write_transforms(os.path.join(args.json, "transforms_train.json"), head,
                     [fr for i, fr in enumerate(frames) if i not in test])
    write_transforms(os.path.join(args.json, "transforms_test.json"), head, [frames[i] for i in test])

    # Checks: the two layouts describe the same cameras and the same pixels.
    problems = []
    c2w, hwf, bounds = load_llff_c2w(np.load(os.path.join(args.capture, "poses_bounds.npy")))
    with open(os.path.join(args.json, "transforms.json")) as f:
        tj = json.load(f)
    for i, fr in enumerate(tj["frames"]):
        if np.abs(c2w[i] - np.array(fr["transform_matrix"])[:3]).max() > 1e-9:
            problems.append(f"view {i}: poses_bounds.npy read as load_llff does disagrees with transforms.json")
    if np.abs(hwf / [2, 2, 2] - [tj["h"], tj["w"], tj["fl_x"]]).max() > 1e-9:
        problems.append("hwf / 2 differs from transforms.json's h, w, fl_x")
    for folder, size in (("images", (w, h)), ("images_2", (w // 2, h // 2)), ("images_4", (w // 4, h // 4))):
        for name in sorted(os.listdir(os.path.join(args.capture, folder))):
            with Image.open(os.path.join(args.capture, folder, name)) as im:
                if im.size != size or im.mode != "RGB":
                    problems.append(f"{folder}/{name}: {im.mode} {im.size[0]}x{im.size[1]}, expected RGB {size}")
    if not (bounds[:, 0] > 0).all() or not (bounds[:, 1] > bounds[:, 0]).all():
        problems.append("bounds are not 0 < near < far")
    centres = c2w[:, :, 3]
    print(f"llff_capture: {len(views)} views, {w}x{h} focal {focal:g} (images_2: {w // 2}x{h // 2}); held out "
          f"(llffhold {LLFF_HOLD}): {test}; near {bounds[:, 0].min():.3f}-{bounds[:, 0].max():.3f}, far "
          f"{bounds[:, 1].min():.3f}-{bounds[:, 1].max():.3f} (far / near "
          f"{bounds[:, 1].max() / bounds[:, 0].min():.1f}); "
          f"camera patch {np.ptp(centres, axis=0).round(3).tolist()} m")
    for line in problems:
        print(line, file=sys.stderr)
    sys.exit(1 if problems else 0)


main()
