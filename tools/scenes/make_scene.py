# Builds vknerf's sample scene "tabletop" and renders it in nerf_synthetic layout.
# Run by Blender, not by python3, as a module of this package: tools/scenes/make_scene.sh installs Debian's
# blender if needed and runs `blender_module make_scene --out assets/tabletop` (need_blender.sh).
#
# Everything is made here from primitives and procedural textures, so the scene is our own work and
# the renders are reproducible: fixed Cycles seed, fixed thread count, seeded camera positions (a re-render
# matches the committed PNGs to within a few levels in an odd pixel: Cycles on 2 threads is not bit-exact).
import argparse
import json
import random
import sys

import bpy

from . import blender_parts as parts

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


# ---------------------------------------------------------------- cameras and rendering

def setup_render(args):
    parts.setup_cycles(args.samples, args.seed, args.threads, args.size, args.size, transparent=True)
    return parts.add_nerf_synthetic_camera()


def main():
    args = parse_args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    parts.build_tabletop()
    build_lights()
    cam = setup_render(args)
    aabb = parts.content_aabb()
    # Separate streams for train and test: the test cameras are independent draws, at other positions.
    train = parts.camera_positions(random.Random(args.seed), args.train, args.radius)
    test = parts.camera_positions(random.Random(args.seed + 1000), args.test, args.radius, avoid=train)
    parts.render_split(cam, args.out, "train", train, aabb)
    parts.render_split(cam, args.out, "test", test, aabb)
    print(f"make_scene: wrote {args.train} train + {args.test} test views to {args.out}, aabb {aabb}")


main()
