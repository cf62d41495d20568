#!/usr/bin/env python3
"""Draws a mesh from `vknerf export mesh` (binary PLY: float x y z, uchar red green blue, int
triangles) from two viewpoints into a PNG, for a look without a mesh viewer. Faces are drawn
with the mean colour of their vertices; matplotlib sorts them back to front per face, so a
close-up may show the odd face in the wrong order. Usage: show_mesh.py MESH.ply OUT.png
[--box x0 y0 z0 x1 y1 z1] (Debian: python3-matplotlib, python3-numpy)."""
import argparse
import struct

import matplotlib

matplotlib.use("Agg")  # headless: CI and servers have no display
import matplotlib.pyplot as plt
import numpy as np
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

TYPES = {"float": "<f4", "double": "<f8", "uchar": "u1", "int": "<i4", "uint": "<u4"}


def read_ply(path):
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    vertices, faces, props, element = 0, 0, [], None
    for line in data[:end].decode("ascii").splitlines():
        words = line.split()
        if words[:1] == ["format"] and words[1] != "binary_little_endian":
            raise SystemExit(f"{path}: not a binary little-endian PLY")
        if words[:1] == ["element"]:
            element = words[1]
            if element == "vertex":
                vertices = int(words[2])
            elif element == "face":
                faces = int(words[2])
        elif words[:1] == ["property"] and element == "vertex":
            props.append((words[2], TYPES[words[1]]))
    v = np.frombuffer(data, dtype=np.dtype(props), count=vertices, offset=end)
    off = end + vertices * v.dtype.itemsize
    # Every face of vknerf's meshes is a triangle: a count byte, then three int indices.
    f = np.frombuffer(data, dtype=np.dtype([("n", "u1"), ("i", "<i4", 3)]), count=faces, offset=off)
    if faces and not (f["n"] == 3).all():
        raise SystemExit(f"{path}: only triangle meshes are drawn")
    return v, f["i"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("mesh")
    ap.add_argument("out")
    ap.add_argument("--box", type=float, nargs=6, help="the axes' extent (default: the mesh's bounds)")
    a = ap.parse_args()
    v, tris = read_ply(a.mesh)
    xyz = np.stack([v["x"], v["y"], v["z"]], 1)
    rgb = np.stack([v["red"], v["green"], v["blue"]], 1) / 255.0
    lo, hi = (np.array(a.box[:3]), np.array(a.box[3:])) if a.box else (xyz.min(0), xyz.max(0))
    fig = plt.figure(figsize=(12, 6))
    for i, (elev, azim) in enumerate([(35, -60), (20, 120)]):
        ax = fig.add_subplot(1, 2, i + 1, projection="3d")
        ax.add_collection3d(Poly3DCollection(xyz[tris], facecolors=rgb[tris].mean(1), edgecolor="none"))
        ax.set_xlim(lo[0], hi[0])
        ax.set_ylim(lo[1], hi[1])
        ax.set_zlim(lo[2], hi[2])
        ax.set_box_aspect(tuple(np.maximum(hi - lo, 1e-6)))
        ax.view_init(elev, azim)
        ax.set_axis_off()
    plt.tight_layout()
    plt.savefig(a.out, dpi=90)
    print(f"{len(xyz)} vertices, {len(tris)} triangles drawn into {a.out}")


if __name__ == "__main__":
    main()
