# Renders a hand-held, lens-distorted "phone capture" for vknerf's camera-model and real-photo work, photographed
# without alpha through the same phone camera; --scene picks what is photographed:
#   outdoor (default): unbounded: the tabletop objects on a large paved ground, crates at middle distance, a
#     ring of buildings and a cloudy sky, from a hand-held walk round the objects (jittered positions and aim,
#     a few views looking outwards); 45 views, world units as built.
#   wall: an object hanging on a tiled wall that fills every frame, photographed from 0.5-0.9 m
#     (tools/scenes/wall_scene.py); 50 views, 7 held out, and the world normalised as instant-ngp's
#     colmap2nerf.py does with a real capture (origin where the cameras look, mean camera distance 4).
# Run by Blender, not by python3 (tools/scenes/make_capture.sh runs this, then tools/scenes/warp_capture.py, then
# the check), as a module of this package: need_blender.sh's blender_module make_capture --out CAPTURE [--scene wall]
#
# Each view is rendered as a WIDE pinhole image (square pixels, principal point at its centre, oversampled),
# large enough to cover what the distorted camera sees; tools/scenes/warp_capture.py then warps it through the lens
# model, so the distortion in the photos is exact. This script writes <out>/wide/: view_NNNN.png, and
# render.json with the output camera, the lens, every view's pose and its wide intrinsics, the number of views
# to hold out, and 3-D points on the scene's surfaces with the views that see them (for the COLMAP model's
# points3D.bin).
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
from . import lens as lenses
from . import wall_scene

GROUND = parts.FLOOR - 0.1  # the plate (0.1 thick, top at FLOOR) lies on the ground

# Phone-like lenses; the OpenCV one is barrel distortion of a main camera, the fisheye a wide action camera.
DEFAULT_LENSES = {
    "opencv": {"model": "opencv", "k1": -0.12, "k2": 0.03, "p1": 0.001, "p2": -0.0005},
    "fisheye": {"model": "fisheye", "k1": 0.03, "k2": -0.01, "k3": 0.004, "k4": -0.001},
}


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="make_capture.py")
    p.add_argument("--out", required=True, help="dataset folder; the renders go to <out>/wide")
    p.add_argument("--width", type=int, default=270)
    p.add_argument("--height", type=int, default=480)
    p.add_argument("--scene", choices=("outdoor", "wall"), default="outdoor")
    p.add_argument("--views", type=int, default=None, help="default: 45 outdoor, 50 wall")
    p.add_argument("--held-out", type=int, default=None,
                   help="views transforms_test.json holds out, evenly spaced (default: 7 for the wall; else "
                        "round(0.1 n), vknerf's default holdout)")
    p.add_argument("--focal", type=float, default=None,
                   help="fl_x in pixels (default: 1.2963 * width, a phone main camera; fl_y is 0.2%% larger)")
    p.add_argument("--lens", choices=sorted(DEFAULT_LENSES), default="opencv")
    for name in lenses.TERMS:
        p.add_argument(f"--{name}", type=float, default=None, help="distortion term (default: a phone-like lens)")
    p.add_argument("--oversample", type=float, default=1.5, help="wide render's focal length / the output's")
    p.add_argument("--samples", type=int, default=12, help="Cycles samples per wide pixel (no denoiser)")
    p.add_argument("--points-per-view", type=int, default=80, help="surface points seeded from each view")
    p.add_argument("--aabb-scale", type=int, default=4, help="instant-ngp's aabb_scale written to transforms.json")
    p.add_argument("--seed", type=int, default=11)
    p.add_argument("--threads", type=int, default=2)
    return p.parse_args(argv)


# ---------------------------------------------------------------- the unbounded scene

def build_surroundings(rng):
    mesh = bpy.ops.mesh
    # Ground: 80 x 80 units of paving, so it reaches the horizon from every camera.
    parts.add(mesh.primitive_plane_add, parts.brick_material("paving", (0.55, 0.5, 0.42), (0.36, 0.34, 0.3),
                                                       (0.12, 0.12, 0.12), 1.5, 0.15),
              "ground", size=80.0, location=(0, 0, GROUND))
    # Crates at middle distance (inside instant-ngp's aabb_scale 4 cube, |x| < 6): parallax between the
    # objects and the buildings.
    wood = parts.noise_ramp_material("crate_wood", 9.0, 6.0, (0.3, 0.16, 0.06), (0.62, 0.42, 0.2), roughness=0.7)[0]
    for i in range(7):
        a = 2 * math.pi * (i + rng.uniform(-0.25, 0.25)) / 7
        r = rng.uniform(4.3, 5.5)
        s = rng.uniform(0.4, 0.9)
        parts.add(mesh.primitive_cube_add, wood, f"crate_{i}", size=s,
                  location=(r * math.cos(a), r * math.sin(a), GROUND + s / 2),
                  rotation=(0, 0, rng.uniform(0, math.pi)))
    # A ring of buildings 9-13 units away, with gaps: far content beyond the cube, sky seen between them.
    for i in range(11):
        a = 2 * math.pi * (i + rng.uniform(-0.2, 0.2)) / 11
        r = rng.uniform(9.0, 13.0)
        w, d, h = rng.uniform(2.5, 4.5), rng.uniform(1.5, 3.0), rng.uniform(2.0, 6.0)
        hue = [rng.uniform(0.35, 0.9) for _ in range(3)]
        mat = parts.brick_material(f"facade_{i}", hue, [0.8 * c for c in hue], (0.9, 0.9, 0.88), 5.0, 0.4)
        box = parts.add(mesh.primitive_cube_add, mat, f"building_{i}", size=1.0,
                        location=(r * math.cos(a), r * math.sin(a), GROUND + h / 2), rotation=(0, 0, a))
        box.scale = (d, w, h)


def build_sky():
    # Blue gradient with noise clouds, as a function of the view direction only: content at infinity.
    world = bpy.data.worlds.new("sky")
    world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    bg = nodes["Background"]
    coord = nodes.new("ShaderNodeTexCoord")
    sep = nodes.new("ShaderNodeSeparateXYZ")
    links.new(coord.outputs["Generated"], sep.inputs["Vector"])
    gradient = nodes.new("ShaderNodeValToRGB")
    gradient.color_ramp.elements[0].position = 0.0
    gradient.color_ramp.elements[0].color = (0.75, 0.8, 0.88, 1.0)  # pale horizon
    gradient.color_ramp.elements[1].position = 0.6
    gradient.color_ramp.elements[1].color = (0.18, 0.35, 0.8, 1.0)  # deep blue zenith
    links.new(sep.outputs["Z"], gradient.inputs["Fac"])
    clouds = nodes.new("ShaderNodeTexNoise")
    clouds.inputs["Scale"].default_value = 2.5
    clouds.inputs["Detail"].default_value = 6.0
    links.new(coord.outputs["Generated"], clouds.inputs["Vector"])
    cover = nodes.new("ShaderNodeValToRGB")
    cover.color_ramp.elements[0].position = 0.5
    cover.color_ramp.elements[0].color = (0.0, 0.0, 0.0, 1.0)
    cover.color_ramp.elements[1].position = 0.7
    cover.color_ramp.elements[1].color = (1.0, 1.0, 1.0, 1.0)
    links.new(clouds.outputs["Fac"], cover.inputs["Fac"])
    mix = nodes.new("ShaderNodeMixRGB")
    mix.inputs["Color2"].default_value = (0.95, 0.95, 0.95, 1.0)
    links.new(cover.outputs["Color"], mix.inputs["Fac"])
    links.new(gradient.outputs["Color"], mix.inputs["Color1"])
    links.new(mix.outputs["Color"], bg.inputs["Color"])
    bg.inputs["Strength"].default_value = 1.0
    bpy.context.scene.world = world
    parts.add_sun()


# ---------------------------------------------------------------- the hand-held path

def rotation_about(axis, degrees):
    return Matrix.Rotation(math.radians(degrees), 4, axis)


def hand_held_poses(rng, count):
    # One walk around the objects at chest height, aiming roughly at them; the step, distance, height, aim and
    # roll all wander. Every ninth view (starting at the eighth) turns away from the objects, as phones do
    # between shots; the held-out views (evenly spaced, see tools/scenes/warp_capture.py) are never those.
    poses = []
    phi0 = rng.uniform(0, 2 * math.pi)
    for i in range(count):
        phi = phi0 + 2 * math.pi * (i + rng.uniform(-0.3, 0.3)) / count
        radius = 2.9 + 0.35 * math.sin(2 * phi) + rng.gauss(0, 0.08)
        height = GROUND + 1.45 + 0.25 * math.sin(3 * phi + 1) + rng.gauss(0, 0.05)
        eye = Vector((radius * math.cos(phi), radius * math.sin(phi), height))
        target = Vector((rng.gauss(0, 0.12), rng.gauss(0, 0.12), -0.1 + rng.gauss(0, 0.08)))
        look = (target - eye).to_track_quat("-Z", "Y").to_matrix().to_4x4()
        yaw = rng.gauss(0, 2.5)
        pitch = rng.gauss(0, 2.5)
        if i % 9 == 7:
            yaw += rng.choice((-1, 1)) * rng.uniform(100, 170)
            pitch += 20  # towards the horizon and the buildings
        # Yaw about world up, then pitch and roll about the camera's own axes.
        turn = rotation_about("Z", yaw)
        local = rotation_about("X", pitch) @ rotation_about("Z", rng.gauss(0, 3.0))
        poses.append(Matrix.Translation(eye) @ turn @ look @ local)
    return poses


# ---------------------------------------------------------------- cameras

def output_camera(args):
    fx = args.focal if args.focal else 1.2963 * args.width  # 350 px at 270 wide: 69 degrees along the long side
    # Principal point slightly off centre, as calibrations find it.
    return {"w": args.width, "h": args.height, "fl_x": fx, "fl_y": 1.002 * fx,
            "cx": 0.5 * args.width + 0.0045 * args.width, "cy": 0.5 * args.height - 0.0023 * args.height}


def lens_from_args(args):
    lens = dict(DEFAULT_LENSES[args.lens])
    for name in lenses.TERMS:
        if getattr(args, name) is not None:
            lens[name] = getattr(args, name)
    return lens


def wide_camera(out_cam, lens, oversample):
    # The pinhole camera whose image covers every output pixel's footprint (+2 wide pixels of margin for the
    # bilinear taps), square pixels and principal point at the centre, so Blender renders it directly.
    ex, ey = lenses.border_extent(lens, out_cam["fl_x"], out_cam["fl_y"], out_cam["cx"], out_cam["cy"],
                                  out_cam["w"], out_cam["h"])
    f = oversample * max(out_cam["fl_x"], out_cam["fl_y"])
    w = 2 * math.ceil(ex * f + 2)
    h = 2 * math.ceil(ey * f + 2)
    return {"w": w, "h": h, "fl_x": f, "fl_y": f, "cx": w / 2, "cy": h / 2}


def set_blender_camera(cam, wide):
    cam.data.sensor_fit = "HORIZONTAL"
    cam.data.sensor_width = 36.0
    cam.data.lens = wide["fl_x"] * 36.0 / wide["w"]  # focal in pixels = lens / sensor_width * image width
    cam.data.clip_start = 0.01
    cam.data.clip_end = 1000.0


# ---------------------------------------------------------------- points on the surfaces

def gl_to_cv_points(c2w, points):
    # World points -> OpenCV camera frame (x right, y down, z forward) of the OpenGL camera-to-world c2w.
    rot = np.array(c2w)[:3, :3]
    cam = (points - np.array(c2w)[:3, 3]) @ rot  # OpenGL camera frame
    return cam * np.array([1.0, -1.0, -1.0])


def surface_points(rng, poses, out_cam, lens, per_view, centre, scale):
    # Like a structure-from-motion model's: seeded by rays through random pixels of each photo (sky hits
    # nothing and gives no point), then each point is kept in every view where it projects inside the
    # photo through the full lens model and nothing hides it. Returned in the written world, p -> (p - centre)
    # * scale, rounded only there (so the stored pixels stay within 1e-3 px of the points' projections).
    scene = bpy.context.scene
    depsgraph = bpy.context.evaluated_depsgraph_get()
    pts = []
    for pose in poses:
        u = np.array([rng.uniform(0, out_cam["w"]) for _ in range(per_view)])
        v = np.array([rng.uniform(0, out_cam["h"]) for _ in range(per_view)])
        x, y = lenses.undistort(lens, (u - out_cam["cx"]) / out_cam["fl_x"], (v - out_cam["cy"]) / out_cam["fl_y"])
        eye = pose.to_translation()
        for xi, yi in zip(x, y):
            d = (pose.to_3x3() @ Vector((xi, -yi, -1.0))).normalized()
            hit, loc, *_ = scene.ray_cast(depsgraph, eye, d)
            if hit:
                pts.append(tuple(loc))
    pts = np.array(pts)
    tracks = [[] for _ in pts]
    for vi, pose in enumerate(poses):
        c2w = [list(r) for r in pose]
        uv, front = lenses.project(lens, out_cam, gl_to_cv_points(c2w, pts))
        inside = front & (uv[:, 0] >= 0) & (uv[:, 0] < out_cam["w"]) & (uv[:, 1] >= 0) & (uv[:, 1] < out_cam["h"])
        eye = pose.to_translation()
        for pi in np.nonzero(inside)[0]:
            to = Vector(pts[pi]) - eye
            dist = to.length
            hit, loc, *_ = scene.ray_cast(depsgraph, eye, to / dist, distance=dist * 1.001 + 1e-3)
            if hit and (loc - eye).length > dist * (1 - 1e-4) - 1e-4:
                tracks[pi].append([vi, float(uv[pi, 0]), float(uv[pi, 1])])
    keep = [i for i, t in enumerate(tracks) if len(t) >= 2]
    return [{"xyz": [round(float(c), 6) for c in (pts[i] - centre) * scale], "views": tracks[i]} for i in keep]


# ---------------------------------------------------------------- colmap2nerf's world

def closest_point_2_lines(oa, da, ob, db):
    # instant-ngp's scripts/colmap2nerf.py: the midpoint of the closest points of two optical axes (clamped to
    # lie in front of both cameras) and a weight that vanishes for parallel axes.
    da, db = da / np.linalg.norm(da), db / np.linalg.norm(db)
    c = np.cross(da, db)
    denom = np.linalg.norm(c) ** 2
    t = ob - oa
    ta = min(np.linalg.det([t, db, c]) / (denom + 1e-10), 0.0)
    tb = min(np.linalg.det([t, da, c]) / (denom + 1e-10), 0.0)
    return (oa + ta * da + ob + tb * db) * 0.5, denom


def colmap2nerf_frame(poses):
    # (centre, scale) with which colmap2nerf.py maps a capture into instant-ngp's frame, p -> (p - centre) *
    # scale: the origin where the cameras look, their mean distance from it 4 units. (Our world is already
    # +Z up, so its rotation of the mean up vector onto +Z is left out.)
    mats = [np.array(pose) for pose in poses]
    total, weight = np.zeros(3), 0.0
    for mf in mats:
        for mg in mats:
            p, w = closest_point_2_lines(mf[:3, 3], mf[:3, 2], mg[:3, 3], mg[:3, 2])
            if w > 1e-5:
                total, weight = total + p * w, weight + w
    centre = total / weight
    return centre, 4.0 / np.mean([np.linalg.norm(m[:3, 3] - centre) for m in mats])


def main():
    args = parse_args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    rng = random.Random(args.seed)
    if args.scene == "wall":
        args.views = args.views or 50
        args.held_out = 7 if args.held_out is None else args.held_out
        wall_scene.build(rng)
    else:
        args.views = args.views or 45
        parts.build_tabletop()
        build_surroundings(rng)
        build_sky()
    out_cam = output_camera(args)
    lens = lens_from_args(args)
    wide = wide_camera(out_cam, lens, args.oversample)
    parts.setup_cycles(args.samples, args.seed, args.threads, wide["w"], wide["h"], transparent=False)
    # Few bounces: enough for the gold sphere's reflections, and ~2x faster than Cycles' defaults.
    cycles = bpy.context.scene.cycles
    cycles.max_bounces, cycles.diffuse_bounces, cycles.glossy_bounces = 4, 2, 3
    cycles.transmission_bounces = cycles.volume_bounces = cycles.transparent_max_bounces = 0
    # Only the camera moves between views: keep the scene's BVH and shaders instead of rebuilding them.
    bpy.context.scene.render.use_persistent_data = True
    cam = parts.add_camera()
    set_blender_camera(cam, wide)
    poses = (wall_scene.hand_held_poses if args.scene == "wall" else hand_held_poses)(rng, args.views)
    centre, scale = colmap2nerf_frame(poses) if args.scene == "wall" else (np.zeros(3), 1.0)

    folder = os.path.join(args.out, "wide")
    os.makedirs(folder, exist_ok=True)
    views, start = [], time.time()
    for i, pose in enumerate(poses):
        cam.matrix_world = pose
        name = f"view_{i:04d}.png"
        parts.render_still(os.path.abspath(os.path.join(folder, name)))
        matrix = np.array(pose)
        matrix[:3, 3] = (matrix[:3, 3] - centre) * scale
        matrix = [[round(float(matrix[r][c]), 9) for c in range(4)] for r in range(4)]
        views.append({"wide_image": name, "transform_matrix": matrix})
        print(f"make_capture: view {i + 1}/{len(poses)} rendered, {time.time() - start:.0f} s so far", flush=True)
    render_s = time.time() - start
    bpy.context.view_layer.update()
    points = surface_points(rng, poses, out_cam, lens, args.points_per_view, centre, scale)
    with open(os.path.join(folder, "render.json"), "w") as f:
        json.dump({"scene": args.scene, "camera": out_cam, "lens": lens, "wide_camera": wide,
                   "aabb_scale": args.aabb_scale, "held_out": args.held_out, "world_from_blender":
                   {"centre": [round(float(c), 9) for c in centre], "scale": round(float(scale), 9)},
                   "views": views, "points": points, "render_seconds": round(render_s, 1)}, f, indent=1)
    print(f"make_capture: {len(poses)} wide views of {wide['w']}x{wide['h']} at {args.samples} spp in "
          f"{render_s:.0f} s ({render_s / len(poses):.1f} s each), {len(points)} surface points, in {folder}")


main()
