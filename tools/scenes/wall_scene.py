# The "wall" capture of make_capture.py (--scene wall): what a hand-held phone capture of an object
# hanging on a patterned wall looks like, the kind of real capture on which vknerf's fast model once lost
# 8 dB held-out to its distortion loss. Built in metres: a tiled, boldly patterned wall (y = WALL_Y, facing
# -y) that fills every frame, a framed relief, a deep shelf with small objects on it and a hanging plant (up to
# ~0.35 m in front of the wall), photographed from ~0.5 m in two jittered sweeps. Imported inside Blender.
# Why so: b012119's fast model (--steps 2000) collapses on it with its default distortion loss (12.9 dB held-out,
# train 18.8: opaque fog in front of every camera) and not without it (24.2 dB); a first version with plain
# tiles, shallow objects and the camera 0.5-0.9 m away did not show it (25.3 vs 26.7 dB).
import math

import bpy
from mathutils import Matrix, Vector

from . import blender_parts as parts

WALL_Y = 0.1
CENTRE = Vector((0.05, WALL_Y - 0.15, 0.02))  # what the photographer aims at: the objects' middle
SHELF_TOP = -0.1375


def relief_mesh(rng, name, material, width, height, nx, ny, depth):
    # A height field standing out of the wall (towards -y): seeded Gaussian bumps, a carved landscape.
    bumps = [(rng.uniform(-0.5, 0.5) * width, rng.uniform(-0.5, 0.5) * height, rng.uniform(0.02, 0.07),
              rng.uniform(0.3, 1.0)) for _ in range(9)]
    verts = []
    for j in range(ny + 1):
        for i in range(nx + 1):
            x, z = (i / nx - 0.5) * width, (j / ny - 0.5) * height
            h = sum(a * math.exp(-((x - bx) ** 2 + (z - bz) ** 2) / (2 * s * s)) for bx, bz, s, a in bumps)
            verts.append((x, -depth * min(h, 1.0), z))
    faces = [(j * (nx + 1) + i, j * (nx + 1) + i + 1, (j + 1) * (nx + 1) + i + 1, (j + 1) * (nx + 1) + i)
             for j in range(ny) for i in range(nx)]
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    parts.smooth(obj)
    return obj


def box(material, name, size, centre, rotation=(0, 0, 0)):
    obj = parts.add(bpy.ops.mesh.primitive_cube_add, material, name, size=1.0, location=centre, rotation=rotation)
    obj.scale = size
    return obj


def build(rng):
    mesh = bpy.ops.mesh
    # Wall: 8 x 8 m of small tiles (6 x 3 cm, ~2 px of grout at 0.7 m), each tile's colour drawn between two
    # (Blender's brick texture), under a 30 cm noise and bold marbled bands ~10 cm apart: high-frequency, with
    # large features too, and nowhere quite the same.
    tiles = parts.brick_material("wall_tiles", (0.78, 0.62, 0.42), (0.3, 0.42, 0.55), (0.92, 0.9, 0.84), 8.3, 3.0)
    nodes, links = tiles.node_tree.nodes, tiles.node_tree.links
    nodes["Brick Texture"].inputs["Mortar Size"].default_value = 0.03
    wave = nodes.new("ShaderNodeTexWave")
    wave.inputs["Scale"].default_value = 1.6
    wave.inputs["Distortion"].default_value = 8.0
    wave.inputs["Detail"].default_value = 2.0
    links.new(nodes["Texture Coordinate"].outputs["Object"], wave.inputs["Vector"])
    bands = nodes.new("ShaderNodeValToRGB")
    bands.color_ramp.elements[0].position, bands.color_ramp.elements[0].color = 0.3, (0.15, 0.1, 0.2, 1.0)
    bands.color_ramp.elements[1].position, bands.color_ramp.elements[1].color = 0.6, (1.0, 1.0, 1.0, 1.0)
    links.new(wave.outputs["Fac"], bands.inputs["Fac"])
    mix = nodes.new("ShaderNodeMixRGB")
    mix.blend_type, mix.inputs["Fac"].default_value = "MULTIPLY", 1.0
    bsdf = nodes["Principled BSDF"]
    links.new(bsdf.inputs["Base Color"].links[0].from_socket, mix.inputs["Color1"])
    links.new(bands.outputs["Color"], mix.inputs["Color2"])
    links.new(mix.outputs["Color"], bsdf.inputs["Base Color"])
    parts.add(mesh.primitive_plane_add, tiles, "wall", size=8.0, location=(0, WALL_Y, 0.2),
              rotation=(math.radians(90), 0, 0))

    # A framed relief above: a 46 x 34 cm frame, 3.5 cm deep, round a carved height field up to 6 cm deep.
    wood = parts.noise_ramp_material("frame_wood", 14.0, 6.0, (0.25, 0.12, 0.05), (0.55, 0.33, 0.15),
                                     roughness=0.6)[0]
    fz, fw, fh, bar, fd = 0.2, 0.46, 0.34, 0.035, 0.035  # the sides fit between top and bottom (no shared faces)
    for name, size, dx, dz in (("top", (fw, fd, bar), 0, (fh - bar) / 2),
                               ("bottom", (fw, fd, bar), 0, -(fh - bar) / 2),
                               ("left", (bar, fd, fh - 2 * bar), -(fw - bar) / 2, 0),
                               ("right", (bar, fd, fh - 2 * bar), (fw - bar) / 2, 0)):
        box(wood, f"frame_{name}", size, (dx, WALL_Y - fd / 2, fz + dz))
    landscape = parts.noise_ramp_material("relief_paint", 9.0, 5.0, (0.15, 0.35, 0.2), (0.85, 0.75, 0.45))[0]
    relief = relief_mesh(rng, "relief", landscape, fw - 2 * bar, fh - 2 * bar, 48, 34, 0.06)
    relief.location = (0, WALL_Y - 0.004, fz)

    # A shelf below: a 62 x 26 cm board on two brackets, with a vase, four books, a ball and a small cone.
    box(wood, "shelf", (0.62, 0.26, 0.025), (0, WALL_Y - 0.13, SHELF_TOP - 0.0125))
    for x in (-0.22, 0.22):
        box(wood, f"bracket_{x:+.2f}", (0.02, 0.2, 0.08), (x, WALL_Y - 0.1, SHELF_TOP - 0.065))
    ceramic, _ = parts.principled("ceramic", color=(0.08, 0.22, 0.6), roughness=0.3)
    parts.smooth(parts.add(mesh.primitive_uv_sphere_add, ceramic, "vase_body", segments=48, ring_count=24,
                           radius=0.055, location=(-0.19, WALL_Y - 0.17, SHELF_TOP + 0.05)))
    parts.smooth(parts.add(mesh.primitive_cylinder_add, ceramic, "vase_neck", vertices=48, radius=0.025,
                           depth=0.12, location=(-0.19, WALL_Y - 0.17, SHELF_TOP + 0.14)))
    for i in range(4):
        h = rng.uniform(0.13, 0.18)
        colour = [rng.uniform(0.1, 0.85) for _ in range(3)]
        book, _ = parts.principled(f"book_{i}", color=colour, roughness=0.7)
        box(book, f"book_{i}", (0.028, 0.12, h), (0.04 + 0.03 * i, WALL_Y - 0.075, SHELF_TOP + h / 2),
            rotation=(0, math.radians(-14) if i == 3 else 0, 0))
    parts.smooth(parts.add(mesh.primitive_uv_sphere_add, parts.noise_material(), "ball", segments=32,
                           ring_count=16, radius=0.045, location=(0.23, WALL_Y - 0.2, SHELF_TOP + 0.045)))
    purple, _ = parts.principled("purple", color=(0.45, 0.08, 0.6), roughness=0.5)
    parts.add(mesh.primitive_cone_add, purple, "cone", vertices=32, radius1=0.03, depth=0.09,
              location=(-0.07, WALL_Y - 0.22, SHELF_TOP + 0.045))

    # A hanging plant in front of the picture's right edge, 30 cm out from the wall: a bowl on three cords from
    # a bracket arm, leaves (flattened spheres) spilling over its rim.
    iron, _ = parts.principled("iron", color=(0.05, 0.05, 0.05), metallic=0.6, roughness=0.5)
    hang = Vector((0.3, WALL_Y - 0.3, 0.1))
    box(iron, "arm", (0.015, 0.32, 0.015), (hang.x, WALL_Y - 0.16, 0.42))
    for k in range(3):
        a = 2 * math.pi * k / 3
        rim = hang + Vector((0.1 * math.cos(a), 0.1 * math.sin(a), 0.05))
        top = Vector((hang.x, hang.y, 0.42))
        cord = parts.add(mesh.primitive_cylinder_add, iron, f"cord_{k}", vertices=8, radius=0.003,
                         depth=(top - rim).length, location=(rim + top) / 2)
        cord.rotation_mode = "QUATERNION"
        cord.rotation_quaternion = (top - rim).to_track_quat("Z", "Y")
    clay = parts.noise_ramp_material("clay", 12.0, 3.0, (0.45, 0.18, 0.08), (0.7, 0.32, 0.15), roughness=0.8)[0]
    parts.smooth(parts.add(mesh.primitive_uv_sphere_add, clay, "bowl", segments=32, ring_count=16, radius=0.1,
                           location=hang))
    leaf = parts.noise_ramp_material("leaves", 30.0, 4.0, (0.05, 0.22, 0.04), (0.35, 0.6, 0.12), roughness=0.5)[0]
    for k in range(18):
        a, r = rng.uniform(0, 2 * math.pi), rng.uniform(0.02, 0.13)
        centre = hang + Vector((r * math.cos(a), r * math.sin(a), rng.uniform(-0.12, 0.12) if r > 0.09 else 0.09))
        obj = parts.add(mesh.primitive_ico_sphere_add, leaf, f"leaf_{k}", subdivisions=2,
                        radius=rng.uniform(0.025, 0.045), location=centre,
                        rotation=(rng.uniform(0, math.pi), rng.uniform(0, math.pi), 0))
        obj.scale = (1.0, 0.35, 1.6)

    # Daylight from the front and above (the shelf casts shadows on the wall), grey fill from the room.
    world = bpy.data.worlds.new("room")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.8, 0.8, 0.78, 1.0)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.5
    bpy.context.scene.world = world
    sun = parts.add_sun()
    sun.rotation_euler = (math.radians(50), 0, math.radians(25))


def rotation_about(axis, degrees):
    return Matrix.Rotation(math.radians(degrees), 4, axis)


def hand_held_poses(rng, count):
    # Two sweeps along the wall, as a person scans it: left to right a little above the objects, then back a
    # little below them; 0.4-0.6 m from the aim point (0.55-0.75 m from the wall), up to ~45 degrees off the
    # wall's normal, with the step, distance, height, aim, yaw, pitch and roll all jittered. Every view looks at
    # the wall.
    poses = []
    first = (count + 1) // 2
    for i in range(count):
        sweep, k = (0, i) if i < first else (1, i - first)
        n = first if sweep == 0 else count - first
        u = min(1.0, max(0.0, (k + rng.uniform(-0.3, 0.3)) / max(n - 1, 1)))
        if sweep:
            u = 1.0 - u
        azimuth = math.radians(-45 + 90 * u + rng.gauss(0, 2))
        elevation = math.radians((12 if sweep == 0 else -10) + rng.gauss(0, 3))
        dist = 0.5 + 0.08 * math.sin(3 * math.pi * u + 2 * sweep) + rng.gauss(0, 0.02)
        eye = CENTRE + dist * Vector((math.sin(azimuth) * math.cos(elevation),
                                      -math.cos(azimuth) * math.cos(elevation), math.sin(elevation)))
        target = CENTRE + Vector((rng.gauss(0, 0.05), 0.0, rng.gauss(0, 0.04)))
        look = (target - eye).to_track_quat("-Z", "Y").to_matrix().to_4x4()
        turn = rotation_about("Z", rng.gauss(0, 2.5))
        local = rotation_about("X", rng.gauss(0, 2.5)) @ rotation_about("Z", rng.gauss(0, 3.0))
        poses.append(Matrix.Translation(eye) @ turn @ look @ local)
    return poses
