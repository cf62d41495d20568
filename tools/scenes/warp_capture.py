# Second half of tools/scenes/make_capture.sh: turns make_capture.py's wide pinhole renders (<capture>/wide) into the
# dataset a phone and COLMAP would give, in two layouts over the same images/:
#   transforms.json (instant-ngp keys: fl_x fl_y cx cy w h, k1 k2 p1 p2 or is_fisheye + k1..k4, aabb_scale;
#     frames with file_path and an OpenGL camera-to-world transform_matrix), and transforms_train.json /
#     transforms_test.json holding out evenly spaced frames, floor((j + 0.5) n / held) for j = 0..held-1:
#     render.json's held_out of them (the wall scene's 7), else round(0.1 n), the frames vknerf's default
#     holdout picks from transforms.json;
#   sparse/0/cameras.bin (OPENCV or OPENCV_FISHEYE), images.bin, points3D.bin: COLMAP's binary model.
# With --pinhole OUT it also writes the same views without distortion (PINHOLE, no k/p keys) to OUT, which
# today's loaders read; there the COLMAP model is also written as text (sparse/0/*.txt).
# Usage: /usr/bin/python3 -m tools.scenes.warp_capture CAPTURE [--pinhole CAPTURE-pinhole]   (from the repository root)
import argparse
import json
import math
import os

import numpy as np
from PIL import Image

from . import colmap_model as colmap
from . import warp as warping
from .transforms_json import write_transforms

HOLDOUT_FRACTION = 0.1  # vknerf's DatasetOptions.holdoutFraction default


def held_out(n, count=None, fraction=HOLDOUT_FRACTION):
    # Rounds halves up, as vknerf's std::lround does (Python's round would take 4 of 45, not 5).
    if count is None:
        count = min(n, max(1, math.floor(fraction * n + 0.5))) if fraction > 0 else 0
    held = min(n, count)
    return {int((j + 0.5) * n / held) for j in range(held)}


def rigid(matrix):
    # Blender's matrices are single precision (orthonormal to ~1e-7); snapping the rotation to the nearest
    # orthonormal one (1e-7 rad, far below a pixel) lets transforms.json and COLMAP's quaternions carry
    # exactly the same pose.
    m = np.array(matrix, float)
    u, _, vt = np.linalg.svd(m[:3, :3])
    m[:3, :3] = u @ vt
    m[3] = [0, 0, 0, 1]
    return [[round(float(v), 10) for v in row] for row in m]


def header(cam, lens, aabb_scale):
    h = {k: round(cam[k], 6) for k in ("fl_x", "fl_y", "cx", "cy")}
    h.update({"w": cam["w"], "h": cam["h"]})
    model = lens["model"]
    if model == "opencv":
        h.update({k: lens.get(k, 0.0) for k in ("k1", "k2", "p1", "p2")})
        for k in ("k3", "k4", "k5", "k6"):
            if lens.get(k, 0.0):
                raise ValueError(f"instant-ngp's keys carry no {k} for the OpenCV model; use k1 k2 p1 p2 only")
    elif model == "fisheye":
        h["is_fisheye"] = True
        h.update({k: lens.get(k, 0.0) for k in ("k1", "k2", "k3", "k4")})
    h["aabb_scale"] = aabb_scale
    return h


def colmap_camera(cam, lens):
    base = [cam["fl_x"], cam["fl_y"], cam["cx"], cam["cy"]]
    model = lens["model"]
    if model == "pinhole":
        return {"id": 1, "model": "PINHOLE", "width": cam["w"], "height": cam["h"], "params": base}
    if model == "opencv":
        return {"id": 1, "model": "OPENCV", "width": cam["w"], "height": cam["h"],
                "params": base + [lens.get(k, 0.0) for k in ("k1", "k2", "p1", "p2")]}
    return {"id": 1, "model": "OPENCV_FISHEYE", "width": cam["w"], "height": cam["h"],
            "params": base + [lens.get(k, 0.0) for k in ("k1", "k2", "k3", "k4")]}


def write_dataset(out, meta, lens, images, points_uv, text_model):
    # images: list of (name, uint8 H x W x 3); points_uv: per point of meta["points"], list of (view, u, v) in
    # this lens's pixels. Points seen in fewer than two photos are left out, as COLMAP would.
    os.makedirs(os.path.join(out, "images"), exist_ok=True)
    os.makedirs(os.path.join(out, "sparse", "0"), exist_ok=True)
    cam, views = meta["camera"], meta["views"]
    frames = []
    for (name, img), view in zip(images, views):
        Image.fromarray(img).save(os.path.join(out, "images", name), optimize=True)
        frames.append({"file_path": f"images/{name}", "transform_matrix": view["transform_matrix"]})
    head = header(cam, lens, meta["aabb_scale"]) if lens["model"] != "pinhole" else {
        **{k: round(cam[k], 6) for k in ("fl_x", "fl_y", "cx", "cy")}, "w": cam["w"], "h": cam["h"],
        "aabb_scale": meta["aabb_scale"]}
    write_transforms(os.path.join(out, "transforms.json"), head, frames)
    test = held_out(len(frames), meta.get("held_out"))
    write_transforms(os.path.join(out, "transforms_train.json"), head,
                     [f for i, f in enumerate(frames) if i not in test])
    write_transforms(os.path.join(out, "transforms_test.json"), head, [f for i, f in enumerate(frames) if i in test])

    # COLMAP: image ids 1..n in frame order, point ids 1..m; a point's colour is the mean of its observations.
    obs = [[] for _ in views]  # per image: (u, v, point id)
    points = []
    for xyz, track in ((pt["xyz"], t) for pt, t in zip(meta["points"], points_uv) if len(t) >= 2):
        pid = len(points) + 1
        colours, elems = [], []
        for view, u, v in track:
            elems.append((view + 1, len(obs[view])))
            obs[view].append((u, v, pid))
            colours.append(warping.bilinear(images[view][1].astype(float), np.array(u), np.array(v)))
        rgb = [int(c) for c in np.clip(np.round(np.mean(colours, axis=0)), 0, 255)]
        points.append({"id": pid, "xyz": xyz, "rgb": rgb, "error": 0.0, "track": elems})
    colmap_images = []
    for i, ((name, _), view) in enumerate(zip(images, views)):
        rot, t = colmap.world_to_camera(view["transform_matrix"])
        colmap_images.append({"id": i + 1, "qvec": colmap.rotmat_to_qvec(rot).tolist(), "tvec": t.tolist(),
                              "camera_id": 1, "name": name, "xys": [o[:2] for o in obs[i]],
                              "point3D_ids": [o[2] for o in obs[i]]})
    model = os.path.join(out, "sparse", "0")
    camera = colmap_camera(cam, lens)
    colmap.write_cameras(os.path.join(model, "cameras.bin"), [camera])
    colmap.write_images(os.path.join(model, "images.bin"), colmap_images)
    colmap.write_points3D(os.path.join(model, "points3D.bin"), points)
    if text_model:
        colmap.write_text_model(model, [camera], colmap_images, points)
    return test


def main():
    p = argparse.ArgumentParser()
    p.add_argument("capture", help="folder with wide/render.json from tools/scenes/make_capture.py; the dataset goes here")
    p.add_argument("--pinhole", help="also write the undistorted twin of the dataset here")
    p.add_argument("--supersample", type=int, default=2, help="samples per output pixel along each axis")
    args = p.parse_args()
    wide_dir = os.path.join(args.capture, "wide")
    with open(os.path.join(wide_dir, "render.json")) as f:
        meta = json.load(f)
    for view in meta["views"]:
        view["transform_matrix"] = rigid(view["transform_matrix"])
    cam, lens, wide = meta["camera"], meta["lens"], meta["wide_camera"]
    variants = [(args.capture, lens)] + ([(args.pinhole, {"model": "pinhole"})] if args.pinhole else [])
    for out, variant_lens in variants:
        images = []
        for i, view in enumerate(meta["views"]):
            src = np.asarray(Image.open(os.path.join(wide_dir, view["wide_image"])).convert("RGB"))
            images.append((f"frame_{i:04d}.png", warping.warp(src, wide, cam, variant_lens, args.supersample)))
        # The points' pixels through this variant's lens (make_capture.py stored them for the distorted one).
        points_uv = []
        for pt in meta["points"]:
            if variant_lens is lens:
                points_uv.append(pt["views"])
                continue
            track = []
            for view, _, _ in pt["views"]:
                c2w = np.array(meta["views"][view]["transform_matrix"])
                rot, t = colmap.world_to_camera(c2w)
                pc = rot @ np.array(pt["xyz"]) + t
                u, v = cam["fl_x"] * pc[0] / pc[2] + cam["cx"], cam["fl_y"] * pc[1] / pc[2] + cam["cy"]
                if 0 <= u < cam["w"] and 0 <= v < cam["h"]:
                    track.append((view, float(u), float(v)))
            points_uv.append(track)
        test = write_dataset(out, meta, variant_lens, images, points_uv, text_model=variant_lens is not lens)
        print(f"warp_capture: {out}: {len(images)} views ({len(test)} held out: {sorted(test)}), "
              f"lens {variant_lens['model']}")


main()
