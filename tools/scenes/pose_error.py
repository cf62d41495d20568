"""Scores camera poses against the true ones, to measure camera refinement: for the frames of two
transforms*.json matched by the photo their file_path names from each file's folder ("./train/r_0",
"train/r_0" and "train/r_0.png" match, and so does the absolute path that `vknerf export cameras` writes
where training named its photos so), the rotation
error (the angle of R_est R_true^T, degrees) and the translation error (the distance between the camera
centres as a percentage of the true camera's distance to the scene centre). No alignment: both files must be
in the same world frame. The scene centre is TRUE.json's aabb centre, else the point closest to its optical
axes, else the origin (as in perturb_poses), or --scene-centre. Exits 1 with one line naming the file and
field on bad input.

  python3 -m tools.scenes.pose_error /tmp/pp_test/transforms_train_true.json /tmp/pp_test/transforms_train.json
"""
import argparse
import json
import math
import os

import numpy as np

from .poses import fail, frame_key, frame_poses, read_json, rotation_deg, scene_centre


def keyed(path, poses):
    # Photos as paths from the file's folder, as the loader resolves file_path: two files in different
    # folders (or one naming its photos by absolute path) still match frame for frame.
    folder = os.path.dirname(os.path.abspath(path))
    out, first = {}, {}
    for i, (name, m) in enumerate(poses):
        k = frame_key(os.path.join(folder, name.strip()))
        if k in out:
            fail(path, f"frames[{i}].file_path", f"{name} names the photo of frames[{first[k]}] again")
        out[k], first[k] = m, i
    return out


def stats(values):
    return {"mean": float(np.mean(values)), "median": float(np.median(values)), "max": float(np.max(values))}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("true", help="the true poses (transforms_train_true.json from perturb_poses)")
    ap.add_argument("estimate", help="the poses to score")
    ap.add_argument("--scene-centre", type=float, nargs=3, metavar=("X", "Y", "Z"))
    ap.add_argument("--json", metavar="OUT", help="also write the numbers (and each frame's) to this file")
    a = ap.parse_args()

    true_meta, est_meta = read_json(a.true), read_json(a.estimate)
    true_poses, est_poses = frame_poses(a.true, true_meta), frame_poses(a.estimate, est_meta)
    if a.scene_centre:
        if not all(math.isfinite(v) for v in a.scene_centre):
            raise SystemExit("--scene-centre: must be three finite numbers")
        centre, where = np.array(a.scene_centre), "--scene-centre"
    else:
        centre, where = scene_centre(a.true, true_meta, true_poses)
    truth, est = keyed(a.true, true_poses), keyed(a.estimate, est_poses)
    common = [k for k in truth if k in est]
    if not common:
        fail(a.estimate, "frames", f"has no file_path that TRUE's frames have (TRUE {a.true}: "
                                   f"{true_poses[0][0]}, ...; this file: {est_poses[0][0]}, ...)")

    rows = []
    for k in common:
        t, e = truth[k], est[k]
        dist = np.linalg.norm(t[:3, 3] - centre)
        if dist < 1e-9:
            i = list(truth).index(k)
            fail(a.true, f"frames[{i}].transform_matrix", "puts the camera at the scene centre: "
                 "its translation error has no scale (give another --scene-centre)")
        rows.append({"file_path": k, "rotation_deg": rotation_deg(e[:3, :3], t[:3, :3]),
                     "translation_pct": 100 * float(np.linalg.norm(e[:3, 3] - t[:3, 3]) / dist)})
    rot = stats([r["rotation_deg"] for r in rows])
    pos = stats([r["translation_pct"] for r in rows])
    print(f"scene centre ({centre[0]:.6g}, {centre[1]:.6g}, {centre[2]:.6g}): {where}")
    print(f"frames matched: {len(rows)} (of {len(truth)} in {a.true}, {len(est)} in {a.estimate})")
    print(f"rotation error, degrees: mean {rot['mean']:.6f} median {rot['median']:.6f} max {rot['max']:.6f}")
    print(f"translation error, % of the distance to the scene centre: mean {pos['mean']:.6f} "
          f"median {pos['median']:.6f} max {pos['max']:.6f}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"true": a.true, "estimate": a.estimate, "scene_centre": [float(v) for v in centre],
                       "scene_centre_from": where, "frames_matched": len(rows), "frames_true": len(truth),
                       "frames_estimate": len(est), "rotation_deg": rot, "translation_pct": pos,
                       "per_frame": rows}, f, indent=2)
            f.write("\n")


if __name__ == "__main__":
    main()
