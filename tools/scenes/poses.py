# The camera poses of a transforms*.json as perturb_poses and pose_error read them: the frames checked with
# one clear line per bad field (the loader's "FILE: field 'X' ..." words), the scene centre the errors are
# relative to, and the angle between two rotations. Needs numpy.
import json
import math
import os

import numpy as np

IMAGE_EXTENSIONS = (".png", ".jpg", ".jpeg")  # what src/io/dataset/transforms_json.cpp tries, any case


def fail(path, field, what):
    raise SystemExit(f"{path}: field '{field}' {what}" if field else f"{path}: {what}")


def read_json(path):
    if not os.path.isfile(path):
        fail(path, None, "no such file" if not os.path.exists(path) else "is not a file")
    try:
        with open(path) as f:
            meta = json.load(f)
    except (ValueError, UnicodeDecodeError) as e:
        fail(path, None, f"is not JSON ({e})")
    if not isinstance(meta, dict):
        fail(path, None, "must hold a JSON object")
    frames = meta.get("frames")
    if frames is None:
        fail(path, "frames", "is missing")
    if not isinstance(frames, list) or not frames:
        fail(path, "frames", "must be a non-empty array")
    return meta


def is_number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def frame_poses(path, meta):
    """[(file_path, 4x4 float array)] of meta's frames; exits naming the field on a bad one."""
    out = []
    for i, fr in enumerate(meta["frames"]):
        where = f"frames[{i}]"
        if not isinstance(fr, dict):
            fail(path, where, "must be an object")
        name = fr.get("file_path")
        if not isinstance(name, str) or not name:
            fail(path, where + ".file_path", "must be a non-empty string")
        m = fr.get("transform_matrix")
        if m is None:
            fail(path, where + ".transform_matrix", "is missing")
        if not (isinstance(m, list) and len(m) == 4 and
                all(isinstance(r, list) and len(r) == 4 and all(is_number(v) for v in r) for r in m)):
            fail(path, where + ".transform_matrix", "must be a 4x4 array of numbers (4 rows of 4)")
        m = np.array(m, float)
        if not np.all(np.isfinite(m)):
            fail(path, where + ".transform_matrix", "holds a value that is not finite (NaN or infinity)")
        out.append((name, m))
    return out


def frame_key(name):
    # ./train/r_0, train/r_0 and train/r_0.png name the same photo.
    key = os.path.normpath(name.strip())
    stem, ext = os.path.splitext(key)
    return stem if ext.lower() in IMAGE_EXTENSIONS else key


def scene_centre(path, meta, poses):
    """(centre, words saying where it came from): the aabb's centre, else the point closest to all
    optical axes (cameras look down their local -Z) when they cross in front of the cameras, else the origin."""
    if "aabb" in meta:
        box = meta["aabb"]
        if not (isinstance(box, list) and len(box) == 2 and all(
                isinstance(c, list) and len(c) == 3 and all(is_number(v) and math.isfinite(v) for v in c) for c in box)):
            fail(path, "aabb", "must be [[min x, y, z], [max x, y, z]]")
        return (np.array(box[0], float) + np.array(box[1], float)) / 2, f"the aabb centre of {path}"
    origins = np.array([m[:3, 3] for _, m in poses])
    dirs = np.array([-m[:3, 2] / max(np.linalg.norm(m[:3, 2]), 1e-12) for _, m in poses])
    if len(poses) >= 2:
        proj = np.eye(3)[None] - dirs[:, :, None] * dirs[:, None, :]  # I - d d^T: the part across each axis
        a, b = proj.sum(0), np.einsum("nij,nj->i", proj, origins)
        # The axes must cross at a clear angle (else the point runs off along them: forward-facing captures).
        if np.linalg.eigvalsh(a)[0] > 0.01 * len(poses):
            p = np.linalg.solve(a, b)
            if np.mean(np.einsum("ni,ni->n", p - origins, dirs) > 0) > 0.5:
                return p, f"the point closest to the {len(poses)} optical axes of {path} (it has no aabb)"
    return np.zeros(3), f"the origin ({path} has no aabb and its optical axes do not meet in front of the cameras)"


def rotation_deg(r_est, r_true):
    # The angle of r_est r_true^T from its cosine and sine together: accurate at small angles as well.
    m = r_est @ r_true.T
    s = np.linalg.norm([m[2, 1] - m[1, 2], m[0, 2] - m[2, 0], m[1, 0] - m[0, 1]]) / 2
    return math.degrees(math.atan2(s, (np.trace(m) - 1) / 2))
