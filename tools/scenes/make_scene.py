# Builds vknerf's sample scene "tabletop" and renders it in nerf_synthetic layout.
# Run by Blender, not by python3, as a module of this package: tools/scenes/make_scene.sh installs Debian's
# blender if needed and runs `blender_module make_scene --out assets/tabletop` (need_blender.sh).
#
# Everything is made here from primitives and procedural textures, so the scene is our own work and
# the renders are reproducible: fixed Cycles seed, fixed thread count, seeded camera positions (a re-render
# matches the committed PNGs to within a few levels in an odd pixel: Cycles on 2 threads is not bit-exact).
import argparse
import json
import math
import os
import random
import sys

import bpy
from mathutils import Matrix, Vector

from . import blender_parts as parts
from .transforms_json import write_transforms

# The plate's top is at parts.FLOOR = -0.4, so content spans z in [-0.5, 0.7]. With the plate radius of
# 1.05 this keeps every view inside the frame (>= 7 px margin) at radius 4 and camera_angle_x 0.691 for
# elevations from -15 to 72 degrees, while the cameras aim at the origin.


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="make_scene.py")
    p.add_argument("--out", required=True, help="output folder, e.g. assets/tabletop")
    p.add_argument("--size", type=int, default=100, help="image width = height in pixels")
    p.add_argument("--train", type=int, default=100)
    p.add_argument("--test", type=int, default=20)
    p.add_argument("--samples", type=int, default=64, help="Cycles samples per pixel (no denoiser)")
    p.add_argument("--radius", type=float, default=4.0, help="camera distance from the origin")
    p.add_argument("--seed", type=int, default=7)
    p.add_argument("--threads", type=int, default=2)
    return p.parse_args(argv)


def build_lights():
    world = bpy.data.worlds.new("neutral")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.8, 0.8, 0.8, 1.0)  # neutral grey sky; hidden by the transparent film
    bg.inputs["Strength"].default_value = 0.6
    bpy.context.scene.world = world
    parts.add_sun()


def content_aabb(pad=0.05):
    lo, hi = Vector((1e9,) * 3), Vector((-1e9,) * 3)
    for obj in bpy.context.scene.objects:
        if obj.type != "MESH":
            continue
        for corner in obj.bound_box:
            p = obj.matrix_world @ Vector(corner)
            lo = Vector(map(min, lo, p))
            hi = Vector(map(max, hi, p))
    # Pad, then round outwards to 0.05 so the numbers in the JSON are short and still enclose everything.
    # (The 1e-6 keeps float noise in e.g. 0.75 * 20 from bumping a bound by a whole step.)
    lo = [math.floor((v - pad) * 20 + 1e-6) / 20 for v in lo]
    hi = [math.ceil((v + pad) * 20 - 1e-6) / 20 for v in hi]
    assert all(-1.5 <= v <= 1.5 for v in lo + hi), (lo, hi)
    return [lo, hi]


# ---------------------------------------------------------------- cameras and rendering

def setup_render(args):
    parts.setup_cycles(args.samples, args.seed, args.threads, args.size, args.size, transparent=True)
    cam = parts.add_camera()
    cam.data.lens_unit = "FOV"
    cam.data.sensor_fit = "HORIZONTAL"
    cam.data.angle = 0.6911112070083618  # nerf_synthetic's camera_angle_x (a 50 mm lens on a 36 mm sensor)
    return cam


def camera_positions(rng, count, radius, avoid=(), min_angle_deg=5.0, z_min=-0.25, z_max=0.95):
    # Uniform on the spherical zone z/r in [z_min, z_max]: the upper hemisphere plus ~15 degrees below the
    # equator (which sees the plate's underside), stopping short of the pole where "up" degenerates.
    # Draws closer than min_angle_deg to a camera in `avoid` are redrawn, so held-out views are new ones.
    min_dist = 2.0 * radius * math.sin(math.radians(min_angle_deg) / 2.0)
    out = []
    while len(out) < count:
        z = rng.uniform(z_min, z_max)
        phi = rng.uniform(0.0, 2.0 * math.pi)
        s = math.sqrt(1.0 - z * z)
        p = Vector((radius * s * math.cos(phi), radius * s * math.sin(phi), radius * z))
        if all((p - q).length >= min_dist for q in avoid):
            out.append(p)
    return out


def look_at_origin(position):
    # Camera looks down its local -Z with local +Y towards world +Z: Blender's (= OpenGL's) convention.
    rot = (-position).to_track_quat("-Z", "Y").to_matrix().to_4x4()
    return Matrix.Translation(position) @ rot


def render_split(cam, args, split, positions, aabb):
    os.makedirs(os.path.join(args.out, split), exist_ok=True)
    frames = []
    for i, pos in enumerate(positions):
        cam.matrix_world = look_at_origin(pos)
        parts.render_still(os.path.abspath(os.path.join(args.out, split, f"r_{i}.png")))
        m = cam.matrix_world
        frames.append({
            "file_path": f"./{split}/r_{i}",
            "transform_matrix": [[round(m[r][c], 8) for c in range(4)] for r in range(4)],
        })
    # Same keys as nerf_synthetic plus "aabb".
    write_transforms(os.path.join(args.out, f"transforms_{split}.json"),
                     {"camera_angle_x": cam.data.angle_x, "aabb": aabb}, frames)


def main():
    args = parse_args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    parts.build_tabletop()
    build_lights()
    cam = setup_render(args)
    aabb = content_aabb()
    # Separate streams for train and test: the test cameras are independent draws, at other positions.
    train = camera_positions(random.Random(args.seed), args.train, args.radius)
    test = camera_positions(random.Random(args.seed + 1000), args.test, args.radius, avoid=train)
    render_split(cam, args, "train", train, aabb)
    render_split(cam, args, "test", test, aabb)
    print(f"make_scene: wrote {args.train} train + {args.test} test views to {args.out}, aabb {aabb}")


main()
