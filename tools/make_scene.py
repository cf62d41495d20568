# Builds vknerf's sample scene "tabletop" and renders it in nerf_synthetic layout.
# Run by Blender, not by python3:  blender -b --factory-startup -P tools/make_scene.py -- --out assets/tabletop
# (tools/make_scene.sh installs Debian's blender if needed and does exactly that).
#
# Everything is made here from primitives and procedural textures, so the scene is our own work and
# the renders are reproducible: fixed Cycles seed, fixed thread count, seeded camera positions (a re-render
# matches the committed PNGs to within a few levels in an odd pixel: Cycles on 2 threads is not bit-exact).
import argparse
import json
import math
import os
import random
import struct
import sys

import _cycles  # Blender's Cycles module: tells which optional features this build has
import bpy
from mathutils import Matrix, Vector

# Top of the plate; everything stands on it, so content spans z in [-0.5, 0.7]. With the plate radius of
# 1.05 this keeps every view inside the frame (>= 7 px margin) at radius 4 and camera_angle_x 0.691 for
# elevations from -15 to 72 degrees, while the cameras aim at the origin.
FLOOR = -0.4


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


# ---------------------------------------------------------------- materials

def principled(name, color=None, metallic=0.0, roughness=0.5):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    if color is not None:
        bsdf.inputs["Base Color"].default_value = (*color, 1.0)
    bsdf.inputs["Metallic"].default_value = metallic
    bsdf.inputs["Roughness"].default_value = roughness
    return mat, bsdf


def checker_material():
    mat, bsdf = principled("plate_checker", roughness=0.6)
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    coord = nodes.new("ShaderNodeTexCoord")
    checker = nodes.new("ShaderNodeTexChecker")
    checker.inputs["Color1"].default_value = (0.85, 0.82, 0.72, 1.0)  # cream
    checker.inputs["Color2"].default_value = (0.05, 0.22, 0.25, 1.0)  # dark teal
    # Object coordinates are in scene units: scale 5 gives 0.2-unit squares, ~10 across the disc, ~6 px at 100x100.
    checker.inputs["Scale"].default_value = 5.0
    links.new(coord.outputs["Object"], checker.inputs["Vector"])
    links.new(checker.outputs["Color"], bsdf.inputs["Base Color"])
    return mat


def noise_material():
    mat, bsdf = principled("cube_noise", roughness=0.45)
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    coord = nodes.new("ShaderNodeTexCoord")
    noise = nodes.new("ShaderNodeTexNoise")
    noise.inputs["Scale"].default_value = 6.0
    noise.inputs["Detail"].default_value = 4.0
    ramp = nodes.new("ShaderNodeValToRGB")
    ramp.color_ramp.elements[0].position = 0.35
    ramp.color_ramp.elements[0].color = (0.55, 0.03, 0.02, 1.0)  # brick red
    ramp.color_ramp.elements[1].position = 0.65
    ramp.color_ramp.elements[1].color = (1.0, 0.55, 0.08, 1.0)  # orange
    links.new(coord.outputs["Object"], noise.inputs["Vector"])
    links.new(noise.outputs["Fac"], ramp.inputs["Fac"])
    links.new(ramp.outputs["Color"], bsdf.inputs["Base Color"])
    return mat


# ---------------------------------------------------------------- objects

def add(obj_op, material, name, **kwargs):
    obj_op(**kwargs)
    obj = bpy.context.active_object
    obj.name = name
    obj.data.materials.append(material)
    return obj


def smooth(obj):
    for poly in obj.data.polygons:
        poly.use_smooth = True


def build_scene():
    mesh = bpy.ops.mesh
    # Plate: a flat checkered disc, the only "floor"; it ends inside the box so the background stays empty.
    add(mesh.primitive_cylinder_add, checker_material(), "plate",
        vertices=96, radius=1.05, depth=0.1, location=(0, 0, FLOOR - 0.05))

    gold, _ = principled("gold", color=(1.0, 0.71, 0.29), metallic=1.0, roughness=0.12)
    sphere = add(mesh.primitive_uv_sphere_add, gold, "glossy_sphere",
                 segments=64, ring_count=32, radius=0.42, location=(0.43, 0.34, FLOOR + 0.42))
    smooth(sphere)

    add(mesh.primitive_cube_add, noise_material(), "noise_cube",
        size=0.6, location=(-0.47, 0.3, FLOOR + 0.3), rotation=(0, 0, math.radians(30)))

    # Thin structures, 1-2 pixels wide at 100x100 from radius 4: an upright ring and three rods.
    blue, _ = principled("blue", color=(0.05, 0.15, 0.8), roughness=0.35)
    ring = add(mesh.primitive_torus_add, blue, "thin_ring",
               major_segments=96, minor_segments=12, major_radius=0.4, minor_radius=0.03,
               location=(0.085, -0.51, FLOOR + 0.43), rotation=(math.radians(90), 0, math.radians(15)))
    smooth(ring)

    green, _ = principled("green", color=(0.1, 0.6, 0.12), roughness=0.4)
    for i, (x, y, h) in enumerate([(-0.55, -0.34, 1.1), (-0.72, -0.53, 0.8), (-0.41, -0.6, 0.95)]):
        rod = add(mesh.primitive_cylinder_add, green, f"rod_{i}",
                  vertices=16, radius=0.022, depth=h, location=(x, y, FLOOR + h / 2))
        smooth(rod)

    purple, _ = principled("purple", color=(0.45, 0.08, 0.6), roughness=0.5)
    add(mesh.primitive_cone_add, purple, "cone",
        vertices=48, radius1=0.22, depth=0.5, location=(0.72, -0.3, FLOOR + 0.25))


def build_lights():
    world = bpy.data.worlds.new("neutral")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.8, 0.8, 0.8, 1.0)  # neutral grey sky; hidden by the transparent film
    bg.inputs["Strength"].default_value = 0.6
    bpy.context.scene.world = world

    sun_data = bpy.data.lights.new("sun", type="SUN")
    sun_data.energy = 3.0
    sun_data.angle = math.radians(5)  # slightly soft shadows
    sun = bpy.data.objects.new("sun", sun_data)
    sun.rotation_euler = (math.radians(40), math.radians(10), math.radians(35))
    bpy.context.scene.collection.objects.link(sun)


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
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = args.samples
    scene.cycles.use_adaptive_sampling = False  # a fixed sample count keeps the noise level uniform
    scene.cycles.seed = args.seed
    scene.cycles.use_animated_seed = False
    # Debian's Blender 3.4 is built without OpenImageDenoise; use it only where the build has it.
    scene.cycles.use_denoising = bool(getattr(_cycles, "with_openimagedenoise", False))
    if scene.cycles.use_denoising:
        scene.cycles.denoiser = "OPENIMAGEDENOISE"
    scene.render.threads_mode = "FIXED"
    scene.render.threads = args.threads
    scene.render.resolution_x = scene.render.resolution_y = args.size
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = True
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGBA"
    scene.render.image_settings.color_depth = "8"
    scene.render.image_settings.compression = 100
    # Standard sRGB, no Filmic tone curve: a NeRF learns the display colours, plain sRGB is what loaders assume.
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"

    cam_data = bpy.data.cameras.new("camera")
    cam_data.lens_unit = "FOV"
    cam_data.sensor_fit = "HORIZONTAL"
    cam_data.angle = 0.6911112070083618  # nerf_synthetic's camera_angle_x (a 50 mm lens on a 36 mm sensor)
    cam = bpy.data.objects.new("camera", cam_data)
    scene.collection.objects.link(cam)
    scene.camera = cam
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


def strip_png_text(path):
    # Blender writes the date and render timings into tEXt chunks; dropping them (CRCs are per chunk, so the
    # rest stays valid) makes a re-render reproduce the committed files byte for byte.
    with open(path, "rb") as f:
        data = f.read()
    out, pos = [data[:8]], 8
    while pos < len(data):
        length = struct.unpack(">I", data[pos:pos + 4])[0]
        end = pos + 12 + length
        if data[pos + 4:pos + 8] not in (b"tEXt", b"zTXt", b"iTXt"):
            out.append(data[pos:end])
        pos = end
    with open(path, "wb") as f:
        f.write(b"".join(out))


def render_split(cam, args, split, positions, aabb):
    scene = bpy.context.scene
    os.makedirs(os.path.join(args.out, split), exist_ok=True)
    frames = []
    for i, pos in enumerate(positions):
        cam.matrix_world = look_at_origin(pos)
        bpy.context.view_layer.update()
        scene.render.filepath = os.path.abspath(os.path.join(args.out, split, f"r_{i}.png"))
        bpy.ops.render.render(write_still=True)
        strip_png_text(scene.render.filepath)
        m = cam.matrix_world
        frames.append({
            "file_path": f"./{split}/r_{i}",
            "transform_matrix": [[round(m[r][c], 8) for c in range(4)] for r in range(4)],
        })
    # Same keys as nerf_synthetic plus "aabb"; written by hand so each matrix row stays on one line.
    lines = ["{", f'  "camera_angle_x": {json.dumps(cam.data.angle_x)},', f'  "aabb": {json.dumps(aabb)},',
             '  "frames": [']
    for i, fr in enumerate(frames):
        rows = ",\n        ".join(json.dumps(r) for r in fr["transform_matrix"])
        comma = "," if i + 1 < len(frames) else ""
        lines += ["    {", f'      "file_path": {json.dumps(fr["file_path"])},',
                  f'      "transform_matrix": [\n        {rows}\n      ]', "    }" + comma]
    lines += ["  ]", "}", ""]
    text = "\n".join(lines)
    json.loads(text)  # fail here, not in a loader, if the hand-written JSON were malformed
    with open(os.path.join(args.out, f"transforms_{split}.json"), "w") as f:
        f.write(text)


def main():
    args = parse_args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    build_scene()
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
