# Renders a forward-facing capture like LLFF's "fern": a potted fern-like plant with thin leaves 0.8 m in front
# of the camera, in a room whose back wall stands 5 m away (floor, a table, a cabinet and a picture between),
# photographed without alpha by 20 hand-held views on a small, roughly planar patch (a 5 x 4 grid, 6 cm apart,
# jittered by ~10% of that, each aimed at the plant with a little yaw, pitch and roll), in LLFF's capture order.
# Run by Blender, not by python3 (tools/scenes/make_ffwd_capture.sh runs this, then tools/scenes/llff_capture.py,
# which writes the LLFF layout and the transforms.json twin), as a module of this package:
#   need_blender.sh's blender_module make_ffwd_capture --out CAPTURE
# Writes <out>/render/: view_NNNN.png (pinhole, principal point at the centre, square pixels: all that LLFF's
# hwf can say) and render.json with the camera, every view's OpenGL camera-to-world pose (metres, +Z up) and
# its near/far bounds: z-depth percentiles of what the view sees, from rays cast through a grid of its pixels
# (LLFF's imgs2poses takes the 0.1st and 99.9th percentiles of its COLMAP points' depths).
import argparse
import json
import math
import os
import random
import sys
import time

import bpy
import numpy as np
from mathutils import Matrix, Vector

from . import blender_parts as parts

FLOOR = -1.5
BACK_WALL_Y = 5.0
POT_TOP = Vector((0.02, 0.8, -0.42))  # the fronds grow from here
AIM = Vector((0.0, 0.8, -0.2))  # the plant's middle, which every view is aimed at


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="make_ffwd_capture.py")
    p.add_argument("--out", required=True, help="dataset folder; the renders go to <out>/render")
    p.add_argument("--width", type=int, default=1008, help="full-resolution width (LLFF's fern: 4032 / 4)")
    p.add_argument("--height", type=int, default=756)
    p.add_argument("--focal", type=float, default=None, help="focal length in pixels (default: fern's 0.81 * width)")
    p.add_argument("--cols", type=int, default=5)
    p.add_argument("--rows", type=int, default=4)
    p.add_argument("--spacing", type=float, default=0.06, help="grid spacing in metres")
    p.add_argument("--samples", type=int, default=12, help="Cycles samples per pixel (no denoiser)")
    p.add_argument("--depth-step", type=int, default=6, help="pixels between the rays cast for the bounds")
    p.add_argument("--seed", type=int, default=7)
    p.add_argument("--threads", type=int, default=2)
    return p.parse_args(argv)


# ---------------------------------------------------------------- the plant

def frond_geometry(rng, verts, faces, azimuth, elevation, length):
    # One frond: an arching spine (a 4 mm strip) with pairs of thin leaflets (kites 6-10 mm wide, pointed at
    # both ends) along it, shorter towards the tip, angled towards the tip, in the plane of the arch.
    direction = Vector((math.cos(elevation) * math.cos(azimuth), math.cos(elevation) * math.sin(azimuth),
                        math.sin(elevation)))
    side = Vector((-math.sin(azimuth), math.cos(azimuth), 0.0))
    droop = rng.uniform(0.35, 0.6)
    base = POT_TOP + Vector((rng.gauss(0, 0.02), rng.gauss(0, 0.02), 0.0))

    def spine(s):
        return base + length * s * direction - Vector((0, 0, droop * length * s * s))

    def tangent(s):
        return (length * direction - Vector((0, 0, 2 * droop * length * s))).normalized()

    def quad(a, b, c, d):
        n = len(verts)
        verts.extend([tuple(a), tuple(b), tuple(c), tuple(d)])
        faces.append((n, n + 1, n + 2, n + 3))

    steps = 20
    for k in range(steps):
        s0, s1 = k / steps, (k + 1) / steps
        quad(spine(s0) - 0.002 * side, spine(s1) - 0.002 * side, spine(s1) + 0.002 * side, spine(s0) + 0.002 * side)
    pairs = rng.randint(15, 19)
    for k in range(pairs):
        s = 0.12 + 0.85 * k / (pairs - 1)
        p, t = spine(s), tangent(s)
        size = length * (0.05 + 0.22 * (1 - s) ** 0.8) * rng.uniform(0.85, 1.1)
        width = 0.006 + 0.004 * (1 - s)
        for sign in (-1, 1):
            out = (sign * side * math.cos(0.55) + t * math.sin(0.55)).normalized()  # ~30 degrees towards the tip
            sag = Vector((0, 0, -0.25 * size * rng.uniform(0.5, 1.5)))
            tip = p + size * out + sag
            across = t.cross(out).cross(out).normalized() * (width / 2)
            mid = p + 0.4 * size * out + 0.4 * sag
            quad(p, mid - across, tip, mid + across)  # a kite, widest 40% of the way out


def build_plant(rng):
    verts, faces = [], []
    count = 20
    for i in range(count):
        azimuth = 2 * math.pi * (i + rng.uniform(-0.3, 0.3)) / count
        frond_geometry(rng, verts, faces, azimuth, math.radians(rng.uniform(30, 80)), rng.uniform(0.45, 0.75))
    mesh = bpy.data.meshes.new("fern")
    mesh.from_pydata(verts, [], faces)
    mesh.materials.append(parts.noise_ramp_material("fern_green", 25.0, 4.0, (0.04, 0.2, 0.03), (0.3, 0.55, 0.1),
                                                    roughness=0.55)[0])
    obj = bpy.data.objects.new("fern", mesh)
    bpy.context.scene.collection.objects.link(obj)
    # The pot (its rim at POT_TOP) on a column standing on the floor.
    clay = parts.noise_ramp_material("clay", 12.0, 3.0, (0.45, 0.18, 0.08), (0.7, 0.32, 0.15), roughness=0.8)[0]
    parts.add(bpy.ops.mesh.primitive_cone_add, clay, "pot", vertices=48, radius1=0.09, radius2=0.13, depth=0.2,
              location=POT_TOP - Vector((0, 0, 0.1)))
    stone, _ = parts.principled("stand", color=(0.5, 0.5, 0.52), roughness=0.6)
    parts.add(bpy.ops.mesh.primitive_cylinder_add, stone, "stand", vertices=32, radius=0.07,
              depth=POT_TOP.z - 0.2 - FLOOR, location=(POT_TOP.x, POT_TOP.y, (POT_TOP.z - 0.2 + FLOOR) / 2))


# ---------------------------------------------------------------- the room

def box(material, name, size, centre):
    obj = parts.add(bpy.ops.mesh.primitive_cube_add, material, name, size=1.0, location=centre)
    obj.scale = size
    return obj


def build_room():
    mesh = bpy.ops.mesh
    planks = parts.brick_material("floor", (0.55, 0.36, 0.2), (0.42, 0.26, 0.13), (0.15, 0.09, 0.05), 4.0, 0.5)
    planks.node_tree.nodes["Brick Texture"].inputs["Brick Width"].default_value = 2.0  # 0.5 x 0.06 m planks
    planks.node_tree.nodes["Brick Texture"].inputs["Mortar Size"].default_value = 0.01
    parts.add(mesh.primitive_plane_add, planks, "floor", size=12.0, location=(0, 3.0, FLOOR))
    plaster = parts.noise_ramp_material("plaster", 1.5, 5.0, (0.62, 0.6, 0.52), (0.85, 0.83, 0.74), roughness=0.9)[0]
    parts.add(mesh.primitive_plane_add, plaster, "back_wall", size=12.0, location=(0, BACK_WALL_Y, FLOOR + 6.0),
              rotation=(math.radians(90), 0, 0))
    # A picture on the back wall, a cabinet against it, a table with a lamp half-way.
    painting = parts.noise_ramp_material("painting", 4.0, 6.0, (0.1, 0.2, 0.55), (0.85, 0.45, 0.15))[0]
    box(painting, "picture", (1.1, 0.04, 0.75), (-0.6, BACK_WALL_Y - 0.02, 0.5))
    wood = parts.noise_ramp_material("cabinet_wood", 6.0, 6.0, (0.22, 0.11, 0.05), (0.5, 0.3, 0.14), roughness=0.6)[0]
    box(wood, "cabinet", (1.2, 0.45, 1.9), (1.6, BACK_WALL_Y - 0.25, FLOOR + 0.95))
    box(wood, "table_top", (1.2, 0.7, 0.05), (-1.1, 2.8, FLOOR + 0.75))
    for dx in (-0.55, 0.55):
        for dy in (-0.3, 0.3):
            box(wood, f"table_leg_{dx:+.2f}_{dy:+.2f}", (0.05, 0.05, 0.72), (-1.1 + dx, 2.8 + dy, FLOOR + 0.36))
    brass, _ = parts.principled("brass", color=(0.8, 0.6, 0.3), metallic=0.8, roughness=0.35)
    parts.add(mesh.primitive_cylinder_add, brass, "lamp_stem", vertices=24, radius=0.02, depth=0.45,
              location=(-1.3, 2.8, FLOOR + 1.0))
    shade, _ = parts.principled("shade", color=(0.9, 0.85, 0.6), roughness=0.8)
    parts.add(mesh.primitive_cone_add, shade, "lamp_shade", vertices=32, radius1=0.2, radius2=0.1, depth=0.22,
              location=(-1.3, 2.8, FLOOR + 1.3))
    world = bpy.data.worlds.new("room")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.85, 0.85, 0.82, 1.0)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.5
    bpy.context.scene.world = world
    sun = parts.add_sun()
    sun.rotation_euler = (math.radians(40), 0, math.radians(20))  # from above and behind the camera


# ---------------------------------------------------------------- cameras

def rotation_about(axis, degrees):
    return Matrix.Rotation(math.radians(degrees), 4, axis)


def forward_poses(rng, cols, rows, spacing):
    # LLFF-style: a person steps the phone over a small grid in rows, back and forth, facing the plant.
    poses = []
    for r in range(rows):
        for c in (range(cols) if r % 2 == 0 else reversed(range(cols))):
            eye = Vector(((c - (cols - 1) / 2) * spacing + rng.gauss(0, 0.1 * spacing), rng.gauss(0, 0.01),
                          ((rows - 1) / 2 - r) * spacing + rng.gauss(0, 0.1 * spacing)))
            target = AIM + Vector((rng.gauss(0, 0.03), 0.0, rng.gauss(0, 0.03)))
            look = (target - eye).to_track_quat("-Z", "Y").to_matrix().to_4x4()
            local = rotation_about("Y", rng.gauss(0, 1.0)) @ rotation_about("X", rng.gauss(0, 1.0)) @ \
                rotation_about("Z", rng.gauss(0, 1.5))
            poses.append(Matrix.Translation(eye) @ look @ local)
    return poses


def depth_bounds(pose, width, height, focal, step):
    # z-depths (along the viewing axis, as LLFF's bounds are) of the first surface under a grid of pixels.
    scene = bpy.context.scene
    depsgraph = bpy.context.evaluated_depsgraph_get()
    eye, rot = pose.to_translation(), pose.to_3x3()
    forward = rot @ Vector((0, 0, -1))
    depths = []
    for v in range(step // 2, height, step):
        for u in range(step // 2, width, step):
            d = (rot @ Vector(((u + 0.5 - width / 2) / focal, -(v + 0.5 - height / 2) / focal, -1.0))).normalized()
            hit, loc, *_ = scene.ray_cast(depsgraph, eye, d)
            if hit:
                depths.append((loc - eye).dot(forward))
    depths = np.array(depths)
    return float(np.percentile(depths, 0.1)), float(np.percentile(depths, 99.9)), float(depths.min()), \
        float(depths.max()), len(depths) / (len(range(step // 2, height, step)) * len(range(step // 2, width, step)))


def main():
    args = parse_args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    rng = random.Random(args.seed)
    build_room()
    build_plant(rng)
    focal = args.focal if args.focal else 0.81 * args.width  # fern: 3260 px at 4032 wide, 64 degrees across
    parts.setup_cycles(args.samples, args.seed, args.threads, args.width, args.height, transparent=False)
    cycles = bpy.context.scene.cycles
    cycles.max_bounces, cycles.diffuse_bounces, cycles.glossy_bounces = 4, 2, 2
    cycles.transmission_bounces = cycles.volume_bounces = cycles.transparent_max_bounces = 0
    bpy.context.scene.render.use_persistent_data = True
    cam = parts.add_camera()
    cam.data.sensor_fit = "HORIZONTAL"
    cam.data.sensor_width = 36.0
    cam.data.lens = focal * 36.0 / args.width
    cam.data.clip_start, cam.data.clip_end = 0.01, 1000.0
    poses = forward_poses(rng, args.cols, args.rows, args.spacing)

    folder = os.path.join(args.out, "render")
    os.makedirs(folder, exist_ok=True)
    views, start = [], time.time()
    bpy.context.view_layer.update()
    for i, pose in enumerate(poses):
        near, far, closest, farthest, hit = depth_bounds(pose, args.width, args.height, focal, args.depth_step)
        if hit < 1.0:
            raise SystemExit(f"make_ffwd_capture: view {i} sees past the room ({100 * (1 - hit):.2f}% of rays)")
        cam.matrix_world = pose
        name = f"view_{i:04d}.png"
        parts.render_still(os.path.abspath(os.path.join(folder, name)))
        views.append({"image": name, "transform_matrix": [[round(pose[r][c], 9) for c in range(4)] for r in range(4)],
                      "near": round(near, 6), "far": round(far, 6), "min_depth": round(closest, 6),
                      "max_depth": round(farthest, 6)})
        print(f"make_ffwd_capture: view {i + 1}/{len(poses)} rendered (bounds {near:.3f} {far:.3f}), "
              f"{time.time() - start:.0f} s so far", flush=True)
    render_s = time.time() - start
    with open(os.path.join(folder, "render.json"), "w") as f:
        json.dump({"camera": {"w": args.width, "h": args.height, "focal": focal}, "views": views,
                   "bounds_percentiles": [0.1, 99.9], "render_seconds": round(render_s, 1)}, f, indent=1)
    print(f"make_ffwd_capture: {len(poses)} views of {args.width}x{args.height} at {args.samples} spp in "
          f"{render_s:.0f} s, in {folder}")


main()
