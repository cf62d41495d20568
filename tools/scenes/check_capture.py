# Checks a capture written by tools/scenes/make_capture.sh: the images exist at the stated size, the poses are rigid,
# transforms.json and the COLMAP binary model agree (intrinsics, lens, poses), the split files partition the
# frames, and the 3-D points land where the photos show them: a point projected through the full lens model
# into two photos that see it finds the same colour in both (and worse agreement when the distortion is
# ignored, which shows that the photos really are distorted as stated).
# Usage: /usr/bin/python3 -m tools.scenes.check_capture CAPTURE   (from the repository root)
# Needs Debian's python3-numpy and python3-pil. Exits 1 with one line per problem found.
import argparse
import json
import os
import sys

import numpy as np
from PIL import Image

from . import colmap_model as colmap
from . import lens as lenses
from .warp import bilinear


def lens_of(meta):
    if meta.get("is_fisheye"):
        return {"model": "fisheye", **{k: meta.get(k, 0.0) for k in ("k1", "k2", "k3", "k4")}}
    if any(meta.get(k, 0.0) for k in ("k1", "k2", "p1", "p2")):
        return {"model": "opencv", **{k: meta.get(k, 0.0) for k in ("k1", "k2", "p1", "p2")}}
    return {"model": "pinhole"}


def colmap_lens(camera):
    p = camera["params"]
    if camera["model"] == "OPENCV":
        return {"model": "opencv", "k1": p[4], "k2": p[5], "p1": p[6], "p2": p[7]}
    if camera["model"] == "OPENCV_FISHEYE":
        return {"model": "fisheye", "k1": p[4], "k2": p[5], "k3": p[6], "k4": p[7]}
    return {"model": "pinhole"}


def main():
    p = argparse.ArgumentParser()
    p.add_argument("capture")
    args = p.parse_args()
    root, problems = args.capture, []
    with open(os.path.join(root, "transforms.json")) as f:
        meta = json.load(f)
    lens = lens_of(meta)
    w, h = meta["w"], meta["h"]
    frames = meta["frames"]
    images, poses = [], []
    for fr in frames:
        m = np.array(fr["transform_matrix"], float)
        rot = m[:3, :3]
        if np.abs(rot.T @ rot - np.eye(3)).max() > 1e-6 or abs(np.linalg.det(rot) - 1) > 1e-6:
            problems.append(f"{fr['file_path']}: rotation is not rigid")
        if np.abs(m[3] - [0, 0, 0, 1]).max() > 0:
            problems.append(f"{fr['file_path']}: last row is not 0 0 0 1")
        img = np.asarray(Image.open(os.path.join(root, fr["file_path"])))
        if img.shape != (h, w, 3):
            problems.append(f"{fr['file_path']}: shape {img.shape}, expected ({h}, {w}, 3) without alpha")
        images.append(img.astype(float))
        poses.append(m)

    # The split files: the same header, and together exactly the frames of transforms.json.
    split_paths = []
    for split in ("train", "test"):
        with open(os.path.join(root, f"transforms_{split}.json")) as f:
            s = json.load(f)
        if {k: v for k, v in s.items() if k != "frames"} != {k: v for k, v in meta.items() if k != "frames"}:
            problems.append(f"transforms_{split}.json: header differs from transforms.json")
        split_paths.append([fr["file_path"] for fr in s["frames"]])
    if sorted(split_paths[0] + split_paths[1]) != sorted(fr["file_path"] for fr in frames) or not split_paths[1]:
        problems.append("transforms_train.json and transforms_test.json do not partition the frames")

    # COLMAP binary model: same camera, lens and poses.
    model = os.path.join(root, "sparse", "0")
    cameras = colmap.read_cameras(os.path.join(model, "cameras.bin"))
    cimages = colmap.read_images(os.path.join(model, "images.bin"))
    points = colmap.read_points3D(os.path.join(model, "points3D.bin"))
    cam = cameras[1]
    if cam["width"] != w or cam["height"] != h or np.abs(np.array(cam["params"][:4]) -
                                                         [meta[k] for k in ("fl_x", "fl_y", "cx", "cy")]).max() > 1e-5:
        problems.append(f"cameras.bin: {cam} disagrees with transforms.json's intrinsics")
    if colmap_lens(cam) != lens:
        problems.append(f"cameras.bin: lens {colmap_lens(cam)} disagrees with transforms.json's {lens}")
    by_name = {im["name"]: im for im in cimages.values()}
    order = []
    for fr, pose in zip(frames, poses):
        im = by_name.get(os.path.basename(fr["file_path"]))
        if im is None:
            problems.append(f"images.bin: no image {os.path.basename(fr['file_path'])}")
            continue
        order.append(im["id"])
        c2w = colmap.camera_to_world_gl(colmap.qvec_to_rotmat(im["qvec"]), im["tvec"])
        if np.abs(c2w - pose).max() > 1e-6:
            problems.append(f"images.bin: {im['name']} pose disagrees with transforms.json")
    frame_of = {image_id: i for i, image_id in enumerate(order)}

    # Points: every observation re-projects through the full model onto its stored pixel, and two photos of
    # a point agree on its colour. The same with the distortion ignored shows the distortion is real.
    intr = {k: meta[k] for k in ("fl_x", "fl_y", "cx", "cy")}
    reproj, same, ignored, shifted = 0.0, [], [], []
    for pt in points.values():
        track = pt["track"]
        if len(track) < 2:
            problems.append(f"points3D.bin: point {pt['id']} has a track of {len(track)}")
            continue
        px, px_pin = [], []
        for image_id, idx in track:
            i = frame_of[image_id]
            rot, t = colmap.world_to_camera(poses[i])
            pc = (rot @ np.array(pt["xyz"]) + t)[None]
            uv = lenses.project(lens, intr, pc)[0][0]
            uv_pin = lenses.project({"model": "pinhole"}, intr, pc)[0][0]
            reproj = max(reproj, float(np.abs(uv - cimages[image_id]["xys"][idx]).max()))
            px.append(bilinear(images[i], uv[0], uv[1]))
            px_pin.append(bilinear(images[i], uv_pin[0], uv_pin[1]) if 0 <= uv_pin[0] < w and 0 <= uv_pin[1] < h
                          else None)
            shifted.append(float(np.hypot(*(uv - uv_pin))))
        same.append(np.abs(px[0] - px[1]).mean())
        if px_pin[0] is not None and px_pin[1] is not None:
            ignored.append(np.abs(px_pin[0] - px_pin[1]).mean())
    if reproj > 1e-3:
        problems.append(f"images.bin: a stored 2-D point is {reproj:.4f} px from its 3-D point's projection")
    # The baseline: colours of unrelated points, which is what a wrong convention would give.
    rng = np.random.default_rng(0)
    pts = list(points.values())
    unrelated = []
    for _ in range(len(pts)):
        a, b = rng.choice(len(pts), 2, replace=False)
        ia, ib = frame_of[pts[a]["track"][0][0]], frame_of[pts[b]["track"][0][0]]
        ua = cimages[pts[a]["track"][0][0]]["xys"][pts[a]["track"][0][1]]
        ub = cimages[pts[b]["track"][0][0]]["xys"][pts[b]["track"][0][1]]
        unrelated.append(np.abs(bilinear(images[ia], *ua) - bilinear(images[ib], *ub)).mean())
    med_same, med_unrel = float(np.median(same)), float(np.median(unrelated))
    print(f"{len(frames)} views {w}x{h}, lens {lens}; {len(pts)} points, mean track "
          f"{np.mean([len(p['track']) for p in pts]):.1f}; max reprojection of stored 2-D points {reproj:.2e} px")
    print(f"colour difference of a point between two photos (median, 0-255): {med_same:.1f} through the full model, "
          f"{np.median(ignored):.1f} ignoring the distortion (mean shift {np.mean(shifted):.1f} px), "
          f"{med_unrel:.1f} between unrelated points")
    if not med_same < 0.35 * med_unrel:
        problems.append(f"points look no more alike in two photos ({med_same:.1f}) "
                        f"than unrelated points ({med_unrel:.1f})")
    if lens["model"] != "pinhole" and np.mean(shifted) > 1 and not np.median(ignored) > med_same:
        problems.append("ignoring the distortion makes the photos agree as well as the full model")
    for line in problems:
        print(line, file=sys.stderr)
    sys.exit(1 if problems else 0)


main()
