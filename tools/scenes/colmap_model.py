# COLMAP's sparse model, written (binary, and text for loaders that read only that) and read back (binary),
# following the layouts COLMAP documents. Binary, all little-endian:
#   cameras.bin:  uint64 count; per camera: uint32 camera_id, int32 model_id, uint64 width, uint64 height,
#                 float64 params[n] (n fixed by the model).
#   images.bin:   uint64 count; per image: uint32 image_id, float64 qw qx qy qz, float64 tx ty tz (world to
#                 camera, OpenCV axes), uint32 camera_id, name as bytes ending in a NUL, uint64 n_points2D,
#                 per point2D: float64 x, float64 y, int64 point3D_id (-1: none).
#   points3D.bin: uint64 count; per point: uint64 point3D_id, float64 x y z, uint8 r g b, float64 error,
#                 uint64 track_length, per track element: uint32 image_id, uint32 point2D_idx.
import struct

import numpy as np

# name -> (model_id, number of params)
MODELS = {
    "SIMPLE_PINHOLE": (0, 3), "PINHOLE": (1, 4), "SIMPLE_RADIAL": (2, 4), "RADIAL": (3, 5),
    "OPENCV": (4, 8), "OPENCV_FISHEYE": (5, 8), "FULL_OPENCV": (6, 12),
}
MODEL_NAMES = {mid: name for name, (mid, _) in MODELS.items()}


def write_cameras(path, cameras):
    """cameras: list of dicts id, model (a MODELS name), width, height, params."""
    with open(path, "wb") as f:
        f.write(struct.pack("<Q", len(cameras)))
        for c in cameras:
            model_id, n = MODELS[c["model"]]
            if len(c["params"]) != n:
                raise ValueError(f"camera {c['id']}: {c['model']} takes {n} params, got {len(c['params'])}")
            f.write(struct.pack("<IiQQ", c["id"], model_id, c["width"], c["height"]))
            f.write(struct.pack(f"<{n}d", *c["params"]))


def write_images(path, images):
    """images: list of dicts id, qvec (w x y z), tvec, camera_id, name, xys (N x 2), point3D_ids (N)."""
    with open(path, "wb") as f:
        f.write(struct.pack("<Q", len(images)))
        for im in images:
            f.write(struct.pack("<I4d3dI", im["id"], *im["qvec"], *im["tvec"], im["camera_id"]))
            f.write(im["name"].encode("utf-8") + b"\0")
            f.write(struct.pack("<Q", len(im["xys"])))
            for (x, y), pid in zip(im["xys"], im["point3D_ids"]):
                f.write(struct.pack("<2dq", x, y, pid))


def write_points3D(path, points):
    """points: list of dicts id, xyz, rgb (3 ints), error, track (list of (image_id, point2D_idx))."""
    with open(path, "wb") as f:
        f.write(struct.pack("<Q", len(points)))
        for p in points:
            f.write(struct.pack("<Q3d3Bd", p["id"], *p["xyz"], *p["rgb"], p["error"]))
            f.write(struct.pack("<Q", len(p["track"])))
            for image_id, idx in p["track"]:
                f.write(struct.pack("<II", image_id, idx))


def write_text_model(folder, cameras, images, points):
    """The same model as cameras.txt, images.txt, points3D.txt (one line per camera and point, two per image)."""
    with open(f"{folder}/cameras.txt", "w") as f:
        f.write("# CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n")
        for c in cameras:
            f.write(" ".join(str(v) for v in [c["id"], c["model"], c["width"], c["height"], *c["params"]]) + "\n")
    with open(f"{folder}/images.txt", "w") as f:
        f.write("# IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n# POINTS2D[] as (X, Y, POINT3D_ID)\n")
        for im in images:
            f.write(" ".join(str(v) for v in [im["id"], *im["qvec"], *im["tvec"], im["camera_id"], im["name"]]) + "\n")
            f.write(" ".join(f"{x} {y} {pid}" for (x, y), pid in zip(im["xys"], im["point3D_ids"])) + "\n")
    with open(f"{folder}/points3D.txt", "w") as f:
        f.write("# POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n")
        for p in points:
            track = " ".join(f"{i} {j}" for i, j in p["track"])
            f.write(" ".join(str(v) for v in [p["id"], *p["xyz"], *p["rgb"], p["error"]]) + " " + track + "\n")


class _Reader:
    def __init__(self, path):
        with open(path, "rb") as f:
            self.data = f.read()
        self.pos = 0

    def take(self, fmt):
        size = struct.calcsize("<" + fmt)
        if self.pos + size > len(self.data):
            raise ValueError("truncated file")
        out = struct.unpack_from("<" + fmt, self.data, self.pos)
        self.pos += size
        return out

    def name(self):
        end = self.data.index(b"\0", self.pos)
        s = self.data[self.pos:end].decode("utf-8")
        self.pos = end + 1
        return s

    def done(self):
        if self.pos != len(self.data):
            raise ValueError(f"{len(self.data) - self.pos} bytes left over")


def read_cameras(path):
    r = _Reader(path)
    out = {}
    for _ in range(r.take("Q")[0]):
        cid, model_id, w, h = r.take("IiQQ")
        name = MODEL_NAMES[model_id]
        out[cid] = {"id": cid, "model": name, "width": w, "height": h, "params": list(r.take(f"{MODELS[name][1]}d"))}
    r.done()
    return out


def read_images(path):
    r = _Reader(path)
    out = {}
    for _ in range(r.take("Q")[0]):
        vals = r.take("I4d3dI")
        name = r.name()
        n = r.take("Q")[0]
        pts = [r.take("2dq") for _ in range(n)]
        out[vals[0]] = {"id": vals[0], "qvec": list(vals[1:5]), "tvec": list(vals[5:8]), "camera_id": vals[8],
                        "name": name, "xys": [p[:2] for p in pts], "point3D_ids": [p[2] for p in pts]}
    r.done()
    return out


def read_points3D(path):
    r = _Reader(path)
    out = {}
    for _ in range(r.take("Q")[0]):
        vals = r.take("Q3d3Bd")
        n = r.take("Q")[0]
        out[vals[0]] = {"id": vals[0], "xyz": list(vals[1:4]), "rgb": list(vals[4:7]), "error": vals[7],
                        "track": [r.take("II") for _ in range(n)]}
    r.done()
    return out


# ---- poses: vknerf's camera-to-world in the OpenGL convention <-> COLMAP's world-to-camera (OpenCV axes)

GL_TO_CV = np.diag([1.0, -1.0, -1.0])  # flips the camera's y and z axes


def world_to_camera(c2w_gl):
    """4x4 OpenGL camera-to-world -> (R, t) with x_cam = R x_world + t in OpenCV axes."""
    c2w = np.asarray(c2w_gl, float)
    rot_cv = c2w[:3, :3] @ GL_TO_CV  # camera-to-world rotation with OpenCV camera axes
    rot = rot_cv.T
    return rot, -rot @ c2w[:3, 3]


def camera_to_world_gl(rot, t):
    c2w = np.eye(4)
    c2w[:3, :3] = rot.T @ GL_TO_CV
    c2w[:3, 3] = -rot.T @ np.asarray(t, float)
    return c2w


def rotmat_to_qvec(rot):
    """Rotation matrix -> unit quaternion (w, x, y, z), Hamilton convention as COLMAP uses, w >= 0."""
    m = np.asarray(rot, float)
    tr = np.trace(m)
    if tr > 0:
        s = 2.0 * np.sqrt(tr + 1.0)
        q = [0.25 * s, (m[2, 1] - m[1, 2]) / s, (m[0, 2] - m[2, 0]) / s, (m[1, 0] - m[0, 1]) / s]
    else:
        i = int(np.argmax(np.diag(m)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * np.sqrt(1.0 + m[i, i] - m[j, j] - m[k, k])
        q = [0.0] * 4
        q[0] = (m[k, j] - m[j, k]) / s
        q[1 + i] = 0.25 * s
        q[1 + j] = (m[j, i] + m[i, j]) / s
        q[1 + k] = (m[k, i] + m[i, k]) / s
    q = np.array(q) / np.linalg.norm(q)
    return q if q[0] >= 0 else -q


def qvec_to_rotmat(q):
    w, x, y, z = np.asarray(q, float) / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])
