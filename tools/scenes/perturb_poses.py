"""Writes a copy of a nerf_synthetic-style scene whose training poses are wrong by known amounts, to
measure camera refinement (per-photo pose corrections learned while training) with pose_error.

Each camera of the split (default train) is turned by exactly --degrees about a random axis through its
centre (R' = Rot(axis, angle) R, a world-frame rotation of the camera-to-world rotation) and moved by
--shift times its distance to the scene centre in a random direction. The scene centre is the json's aabb
centre, else the point closest to all optical axes, else the origin (a printed line says which). OUT gets
that split's json perturbed, transforms_<split>_true.json (the original file, for pose_error), the other
splits' jsons copied unchanged and symbolic links to the image folders (nothing big is copied). Every other
key, top-level or per frame (camera_angle_x, aabb, fl_x, ...), is kept. The same --seed gives the same file.

OUT must be new or empty, or one this tool wrote before (its .perturb_poses.json marker lists what it made).

  python3 -m tools.scenes.perturb_poses assets/tabletop /tmp/pp_test --degrees 1.0 --shift 0.015
  python3 -m tools.scenes.pose_error /tmp/pp_test/transforms_train_true.json /tmp/pp_test/transforms_train.json
"""
import argparse
import math
import os
import shutil

import numpy as np

from .poses import frame_poses, scene_centre
from .scene_copy import (SPLITS, check_link_names, image_links, prepare_out, read_splits, refuse_scene_folder,
                         write_marker)
from .transforms_json import write_transforms

MARKER = ".perturb_poses.json"
TOOL = "perturb_poses"


def rotation(axis, radians):
    # Rodrigues: the rotation by `radians` about the unit vector `axis`.
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + math.sin(radians) * k + (1 - math.cos(radians)) * (k @ k)


def unit(rng):
    while True:  # uniform on the sphere
        v = rng.standard_normal(3)
        if np.linalg.norm(v) > 1e-6:
            return v / np.linalg.norm(v)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene", help="a folder with transforms_train.json, transforms_test.json (and _val)")
    ap.add_argument("out", help="the new scene folder")
    ap.add_argument("--degrees", type=float, required=True, help="rotation of every camera, in degrees")
    ap.add_argument("--shift", type=float, required=True,
                    help="move of every camera, as a fraction of its distance to the scene centre (0.015: 1.5%%)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--split", default="train", choices=SPLITS, help="the split whose poses are perturbed")
    a = ap.parse_args()
    if not (math.isfinite(a.degrees) and math.isfinite(a.shift) and a.shift >= 0):
        raise SystemExit("--degrees must be finite and --shift finite and not negative")
    refuse_scene_folder(a.scene, a.out)

    metas = read_splits(a.scene, a.split)  # every split's matrices checked before anything is written
    src = os.path.join(a.scene, f"transforms_{a.split}.json")
    meta = metas[a.split]
    poses = frame_poses(src, meta)
    centre, where = scene_centre(src, meta, poses)
    print(f"scene centre ({centre[0]:.6g}, {centre[1]:.6g}, {centre[2]:.6g}): {where}")

    links = {}
    for split, m in metas.items():
        links.update(image_links(a.scene, os.path.join(a.scene, f"transforms_{split}.json"), m))
    outputs = [f"transforms_{s}.json" for s in metas] + [f"transforms_{a.split}_true.json"]
    check_link_names(a.scene, links, outputs, MARKER, TOOL)

    rng = np.random.default_rng(a.seed)
    frames = []
    for fr, (_, m) in zip(meta["frames"], poses):
        turn, move = rotation(unit(rng), math.radians(a.degrees)), unit(rng)
        out_m = m.copy()
        out_m[:3, :3] = turn @ m[:3, :3]
        out_m[:3, 3] = m[:3, 3] + a.shift * np.linalg.norm(m[:3, 3] - centre) * move
        new = dict(fr)
        new["transform_matrix"] = [[float(v) for v in row] for row in out_m[:3]] + [fr["transform_matrix"][3]]
        frames.append(new)

    prepare_out(a.out, MARKER, TOOL)
    made = []
    for name, target in sorted(links.items()):
        os.symlink(target, os.path.join(a.out, name))
        made.append(name)
    for split in metas:
        name = f"transforms_{split}.json"
        if split == a.split:
            write_transforms(os.path.join(a.out, name), {k: v for k, v in meta.items() if k != "frames"}, frames)
            shutil.copyfile(src, os.path.join(a.out, f"transforms_{split}_true.json"))
            made.append(f"transforms_{split}_true.json")
        else:
            shutil.copyfile(os.path.join(a.scene, name), os.path.join(a.out, name))
        made.append(name)
    write_marker(a.out, MARKER, TOOL, a.scene,
                 {"split": a.split, "degrees": a.degrees, "shift": a.shift, "seed": a.seed}, made)
    print(f"{a.out}: transforms_{a.split}.json with its {len(frames)} cameras turned {a.degrees:g} deg and moved "
          f"{100 * a.shift:g}% of their distance to the centre (seed {a.seed}); transforms_{a.split}_true.json the "
          f"original; {', '.join(f'transforms_{s}.json' for s in metas if s != a.split) or 'no other split'} copied; "
          f"linked {', '.join(sorted(links))}")


if __name__ == "__main__":
    main()
