# Blender building blocks shared by make_scene.py, make_detail_object.py, make_capture.py (and its
# wall_scene.py) and make_ffwd_capture.py: materials, the tabletop objects, lights, Cycles settings, PNG
# clean-up, and the nerf_synthetic-style cameras around an object at the origin with their transforms JSON.
# Imported inside Blender (needs bpy), never by python3.
import math
import os
import struct

import _cycles  # Blender's Cycles module: tells which optional features this build has
import bpy
from mathutils import Matrix, Vector

from .transforms_json import write_transforms

# Top of the plate; everything stands on it, so content spans z in [-0.5, 0.7].
FLOOR = -0.4
# Centre of the gold sphere (the checkers project it into views to test the poses).
GOLD_SPHERE_CENTRE = (0.43, 0.34, FLOOR + 0.42)


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


def checker_material(name="plate_checker", color1=(0.85, 0.82, 0.72), color2=(0.05, 0.22, 0.25), scale=5.0):
    # Defaults: the tabletop's plate, cream and dark teal.
    mat, bsdf = principled(name, roughness=0.6)
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    coord = nodes.new("ShaderNodeTexCoord")
    checker = nodes.new("ShaderNodeTexChecker")
    checker.inputs["Color1"].default_value = (*color1, 1.0)
    checker.inputs["Color2"].default_value = (*color2, 1.0)
    # Object coordinates are in scene units: scale 5 gives 0.2-unit squares, ~10 across the disc, ~6 px at 100x100.
    checker.inputs["Scale"].default_value = scale
    links.new(coord.outputs["Object"], checker.inputs["Vector"])
    links.new(checker.outputs["Color"], bsdf.inputs["Base Color"])
    return mat


def noise_ramp_material(name, scale, detail, color_lo, color_hi, roughness=0.45, coords="Object"):
    # Principled BSDF whose base colour is a two-colour ramp over a noise texture.
    mat, bsdf = principled(name, roughness=roughness)
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    coord = nodes.new("ShaderNodeTexCoord")
    noise = nodes.new("ShaderNodeTexNoise")
    noise.inputs["Scale"].default_value = scale
    noise.inputs["Detail"].default_value = detail
    ramp = nodes.new("ShaderNodeValToRGB")
    ramp.color_ramp.elements[0].position = 0.35
    ramp.color_ramp.elements[0].color = (*color_lo, 1.0)
    ramp.color_ramp.elements[1].position = 0.65
    ramp.color_ramp.elements[1].color = (*color_hi, 1.0)
    links.new(coord.outputs[coords], noise.inputs["Vector"])
    links.new(noise.outputs["Fac"], ramp.inputs["Fac"])
    links.new(ramp.outputs["Color"], bsdf.inputs["Base Color"])
    return mat, nodes, links, ramp, bsdf


def brick_material(name, color1, color2, mortar, scale, variation_scale):
    # Bricks in object coordinates (scene units), multiplied by a large-scale noise so that distant parts
    # of a big surface still differ from one another.
    mat, nodes, links, ramp, bsdf = noise_ramp_material(
        name, variation_scale, 3.0, (0.55, 0.55, 0.55), (1.0, 1.0, 1.0), roughness=0.8)
    coord = nodes["Texture Coordinate"]
    brick = nodes.new("ShaderNodeTexBrick")
    brick.inputs["Color1"].default_value = (*color1, 1.0)
    brick.inputs["Color2"].default_value = (*color2, 1.0)
    brick.inputs["Mortar"].default_value = (*mortar, 1.0)
    brick.inputs["Scale"].default_value = scale
    links.new(coord.outputs["Object"], brick.inputs["Vector"])
    mix = nodes.new("ShaderNodeMixRGB")
    mix.blend_type = "MULTIPLY"
    mix.inputs["Fac"].default_value = 1.0
    links.new(brick.outputs["Color"], mix.inputs["Color1"])
    links.new(ramp.outputs["Color"], mix.inputs["Color2"])
    links.new(mix.outputs["Color"], bsdf.inputs["Base Color"])
    return mat


def gold_material():
    # The checkers' probe colour (check_scene.is_gold): pale yellow-orange metal.
    return principled("gold", color=(1.0, 0.71, 0.29), metallic=1.0, roughness=0.12)[0]


def noise_material():
    # Brick red to orange.
    return noise_ramp_material("cube_noise", 6.0, 4.0, (0.55, 0.03, 0.02), (1.0, 0.55, 0.08))[0]


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


def build_tabletop():
    # The sample scene's objects (assets/README.md lists them and what each tests).
    mesh = bpy.ops.mesh
    # Plate: a flat checkered disc, radius 1.05, top at FLOOR.
    add(mesh.primitive_cylinder_add, checker_material(), "plate",
        vertices=96, radius=1.05, depth=0.1, location=(0, 0, FLOOR - 0.05))

    sphere = add(mesh.primitive_uv_sphere_add, gold_material(), "glossy_sphere",
                 segments=64, ring_count=32, radius=0.42, location=GOLD_SPHERE_CENTRE)
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


def add_sun():
    sun_data = bpy.data.lights.new("sun", type="SUN")
    sun_data.energy = 3.0
    sun_data.angle = math.radians(5)  # slightly soft shadows
    sun = bpy.data.objects.new("sun", sun_data)
    sun.rotation_euler = (math.radians(40), math.radians(10), math.radians(35))
    bpy.context.scene.collection.objects.link(sun)
    return sun


# ---------------------------------------------------------------- rendering

def setup_cycles(samples, seed, threads, width, height, transparent):
    # Cycles on the CPU with a fixed seed, sample count and thread count, so renders are reproducible;
    # 8-bit sRGB PNG output (RGBA when the film is transparent).
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = samples
    scene.cycles.use_adaptive_sampling = False  # a fixed sample count keeps the noise level uniform
    scene.cycles.seed = seed
    scene.cycles.use_animated_seed = False
    # Debian's Blender 3.4 is built without OpenImageDenoise; use it only where the build has it.
    scene.cycles.use_denoising = bool(getattr(_cycles, "with_openimagedenoise", False))
    if scene.cycles.use_denoising:
        scene.cycles.denoiser = "OPENIMAGEDENOISE"
    scene.render.threads_mode = "FIXED"
    scene.render.threads = threads
    scene.render.resolution_x = width
    scene.render.resolution_y = height
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = transparent
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGBA" if transparent else "RGB"
    scene.render.image_settings.color_depth = "8"
    scene.render.image_settings.compression = 100
    # Standard sRGB, no Filmic tone curve: a NeRF learns the display colours, plain sRGB is what loaders assume.
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"


def add_camera():
    cam_data = bpy.data.cameras.new("camera")
    cam = bpy.data.objects.new("camera", cam_data)
    bpy.context.scene.collection.objects.link(cam)
    bpy.context.scene.camera = cam
    return cam


def strip_png_text(path):
    # Blender writes the date and render timings into tEXt chunks; dropping them (CRCs are per chunk, so the
    # rest stays valid) makes a re-render reproduce the previous files byte for byte.
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


def render_still(path):
    bpy.context.view_layer.update()
    bpy.context.scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    strip_png_text(path)


# ---------------------------------------------------------------- an object at the origin, nerf_synthetic style

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


def add_nerf_synthetic_camera():
    cam = add_camera()
    cam.data.lens_unit = "FOV"
    cam.data.sensor_fit = "HORIZONTAL"
    cam.data.angle = 0.6911112070083618  # nerf_synthetic's camera_angle_x (a 50 mm lens on a 36 mm sensor)
    return cam


def camera_positions(rng, count, radius, avoid=(), min_angle_deg=5.0, z_min=-0.25, z_max=0.95):
    # Uniform on the spherical zone z/r in [z_min, z_max]: by default the upper hemisphere plus ~15 degrees
    # below the equator (which sees the tabletop plate's underside), stopping short of the pole where "up"
    # degenerates. Draws closer than min_angle_deg to a camera in `avoid` are redrawn, so held-out views are
    # new ones (check_scene insists on it).
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


def render_split(cam, out, split, positions, aabb):
    # Renders out/split/r_<i>.png from each position and writes out/transforms_<split>.json.
    os.makedirs(os.path.join(out, split), exist_ok=True)
    frames = []
    for i, pos in enumerate(positions):
        cam.matrix_world = look_at_origin(pos)
        render_still(os.path.abspath(os.path.join(out, split, f"r_{i}.png")))
        m = cam.matrix_world
        frames.append({
            "file_path": f"./{split}/r_{i}",
            "transform_matrix": [[round(m[r][c], 8) for c in range(4)] for r in range(4)],
        })
    # Same keys as nerf_synthetic plus "aabb".
    write_transforms(os.path.join(out, f"transforms_{split}.json"),
                     {"camera_angle_x": cam.data.angle_x, "aabb": aabb}, frames)
