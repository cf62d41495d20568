# Writes a small unbounded test scene without Blender: an analytic ray tracer in plain Python 3
# (no numpy), PNGs through zlib. A textured ground plane out to the scene box's edge, a few textured
# objects near the centre, a striped wall ring far out, and a sky gradient at infinity; opaque photos
# (no alpha) from a hand-held-like path around the centre, some views looking in, some out.
#   python3 -m tools.scenes.make_unbounded_scene --out /tmp/unbounded [--width 160 --height 120 --train 40 --test 8]
# Writes transforms_train.json and transforms_test.json with aabb_scale 8 (instant-ngp's convention:
# with the default scale 0.33 and offset 0.5 the box is +-12.1 units, the inner cube +-1.5).
# Takes about a minute on one core at the default size.
import argparse
import json
import math
import os
import random
import struct
import zlib

GROUND_Z = -0.5
WALL_RADIUS, WALL_TOP = 9.0, 3.0
SPHERES = [  # centre, radius, two stripe colours
    ((0.0, 0.0, -0.05), 0.45, (0.85, 0.25, 0.2), (0.95, 0.85, 0.3)),
    ((0.9, 0.5, -0.2), 0.3, (0.2, 0.45, 0.85), (0.9, 0.9, 0.95)),
    ((-0.7, 0.8, -0.25), 0.25, (0.25, 0.7, 0.3), (0.1, 0.15, 0.1)),
    ((-0.6, -0.9, -0.15), 0.35, (0.6, 0.3, 0.75), (0.95, 0.6, 0.2)),
]
SUN = (0.4, -0.3, 0.87)


def normalise(v):
    n = math.sqrt(sum(c * c for c in v))
    return tuple(c / n for c in v)


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def sky(d):
    up = max(-1.0, min(1.0, d[2]))
    h = 0.5 * (up + 1.0)
    return (0.55 + 0.25 * h, 0.7 + 0.2 * h, 0.95)


def ground_colour(x, y):
    # Checker of 0.5-unit squares in two palettes, alternating every 4 units, with rings every 2 units.
    cx, cy = math.floor(x * 2.0), math.floor(y * 2.0)
    region = (math.floor(x / 4.0) + math.floor(y / 4.0)) & 1
    palette = [((0.8, 0.75, 0.6), (0.3, 0.25, 0.2)), ((0.55, 0.7, 0.45), (0.2, 0.35, 0.25))][region]
    c = palette[(cx + cy) & 1]
    r = math.hypot(x, y)
    if abs(r - 2.0 * round(r / 2.0)) < 0.06:
        c = (0.9, 0.3, 0.2)
    return c


def wall_colour(d_angle, z):
    stripe = int(math.floor(d_angle * 24.0 / math.pi)) & 1
    band = int(math.floor((z - GROUND_Z) * 2.0)) & 1
    base = [(0.75, 0.55, 0.4), (0.35, 0.4, 0.6)][stripe]
    return tuple(c * (0.8 if band else 1.0) for c in base)


def shade(colour, n):
    light = 0.35 + 0.65 * max(0.0, dot(n, SUN))
    return tuple(c * light for c in colour)


def trace(o, d):
    best, hit = float("inf"), None
    for centre, radius, c1, c2 in SPHERES:
        oc = (o[0] - centre[0], o[1] - centre[1], o[2] - centre[2])
        b = dot(oc, d)
        disc = b * b - (dot(oc, oc) - radius * radius)
        if disc > 0:
            t = -b - math.sqrt(disc)
            if 1e-4 < t < best:
                best, hit = t, ("sphere", centre, radius, c1, c2)
    if d[2] < 0:
        t = (GROUND_Z - o[2]) / d[2]
        if 1e-4 < t < best:
            best, hit = t, ("ground",)
    # Wall ring: x^2 + y^2 = R^2, from the inside.
    a = d[0] * d[0] + d[1] * d[1]
    if a > 1e-12:
        b = o[0] * d[0] + o[1] * d[1]
        c = o[0] * o[0] + o[1] * o[1] - WALL_RADIUS * WALL_RADIUS
        disc = b * b - a * c
        if disc > 0:
            t = (-b + math.sqrt(disc)) / a
            z = o[2] + t * d[2]
            if 1e-4 < t < best and GROUND_Z <= z <= WALL_TOP:
                best, hit = t, ("wall",)
    if hit is None:
        return sky(d)
    p = (o[0] + best * d[0], o[1] + best * d[1], o[2] + best * d[2])
    if hit[0] == "sphere":
        _, centre, radius, c1, c2 = hit
        n = tuple((p[k] - centre[k]) / radius for k in range(3))
        stripe = int(math.floor((math.atan2(n[1], n[0]) + math.pi) * 6.0 / math.pi + 3.0 * n[2])) & 1
        return shade(c1 if stripe else c2, n)
    if hit[0] == "ground":
        return shade(ground_colour(p[0], p[1]), (0.0, 0.0, 1.0))
    n = normalise((-p[0], -p[1], 0.0))
    return shade(wall_colour(math.atan2(p[1], p[0]), p[2]), n)


def srgb(c):
    c = max(0.0, min(1.0, c))
    v = 12.92 * c if c <= 0.0031308 else 1.055 * c ** (1 / 2.4) - 0.055
    return int(round(v * 255.0))


def write_png(path, width, height, rows):
    raw = b"".join(b"\x00" + bytes(r) for r in rows)

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(raw, 9)))
        f.write(chunk(b"IEND", b""))


def look(position, target):
    forward = normalise(tuple(target[k] - position[k] for k in range(3)))
    right = normalise((forward[1], -forward[0], 0.0))  # z up: right = forward x up
    up = (right[1] * forward[2] - right[2] * forward[1], right[2] * forward[0] - right[0] * forward[2],
          right[0] * forward[1] - right[1] * forward[0])
    back = tuple(-c for c in forward)
    # camera-to-world, OpenGL convention: columns right, up, back (the camera looks down -Z)
    return [[right[k], up[k], back[k], position[k]] for k in range(3)] + [[0.0, 0.0, 0.0, 1.0]]


def hand_held_path(count, rng):
    # A walk around the centre at radius ~2.6 and eye height ~0.8 with hand-held wobble; every third
    # view looks outward past the centre's side, toward the ground and walls.
    poses = []
    for i in range(count):
        a = 2.0 * math.pi * (i + rng.uniform(-0.3, 0.3)) / count
        r = 2.6 + rng.uniform(-0.25, 0.25)
        p = (r * math.cos(a), r * math.sin(a), 0.8 + rng.uniform(-0.15, 0.15))
        if i % 3 == 2:
            target = (p[0] * 3.0 + rng.uniform(-1, 1), p[1] * 3.0 + rng.uniform(-1, 1), 0.0)
        else:
            target = (rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.0))
        poses.append(look(p, target))
    return poses


def render(c2w, width, height, angle_x, supersample):
    focal = 0.5 * width / math.tan(0.5 * angle_x)
    o = tuple(c2w[k][3] for k in range(3))
    rows = []
    for y in range(height):
        row = []
        for x in range(width):
            acc = [0.0, 0.0, 0.0]
            for sy in range(supersample):
                for sx in range(supersample):
                    u = (x + (sx + 0.5) / supersample - 0.5 * width) / focal
                    v = -(y + (sy + 0.5) / supersample - 0.5 * height) / focal
                    local = (u, v, -1.0)
                    d = normalise(tuple(sum(c2w[k][j] * local[j] for j in range(3)) for k in range(3)))
                    c = trace(o, d)
                    for k in range(3):
                        acc[k] += c[k]
            n = supersample * supersample
            row.extend(srgb(a / n) for a in acc)
        rows.append(row)
    return rows


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--out", required=True)
    p.add_argument("--width", type=int, default=160)
    p.add_argument("--height", type=int, default=120)
    p.add_argument("--train", type=int, default=40)
    p.add_argument("--test", type=int, default=8)
    p.add_argument("--supersample", type=int, default=2)
    p.add_argument("--aabb-scale", type=int, default=8)
    p.add_argument("--seed", type=int, default=3)
    args = p.parse_args()
    rng = random.Random(args.seed)
    angle_x = 1.2
    poses = hand_held_path(args.train + args.test, rng)
    # Held-out views are spread over the path.
    test_ids = set(range(1, len(poses), max(1, len(poses) // args.test))[: args.test])
    os.makedirs(os.path.join(args.out, "images"), exist_ok=True)
    splits = {"train": [], "test": []}
    for i, c2w in enumerate(poses):
        name = "images/%03d.png" % i
        write_png(os.path.join(args.out, name), args.width, args.height,
                  render(c2w, args.width, args.height, angle_x, args.supersample))
        splits["test" if i in test_ids else "train"].append({"file_path": name, "transform_matrix": c2w})
    for split, frames in splits.items():
        with open(os.path.join(args.out, "transforms_%s.json" % split), "w") as f:
            json.dump({"camera_angle_x": angle_x, "aabb_scale": args.aabb_scale, "frames": frames}, f, indent=1)


if __name__ == "__main__":
    main()
