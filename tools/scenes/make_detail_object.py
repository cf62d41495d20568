"""Builds a detailed test object in the manner of the nerf_synthetic objects (lego, ship, drums) and renders
it in their layout, to measure how much fine detail a model keeps at full resolution (800x800).

The object, a little fairground pavilion about 2 units across, standing on a plinth at the origin:
  - a 24-sided plinth with brick sides (rows ~6 px tall at 800x800) and a fine checker deck;
  - a round kiosk papered with text-like posters (rows of letter blocks ~4 x 7 px at 800x800, strokes ~2 px),
    a copper roof with a verdigris noise, and a square lattice mast (legs, rungs and X braces, 2-5 px wide)
    crowned by a gold sphere (the checkers' probe, PROBE below);
  - a railing of 60 thin posts and two rails round the deck's edge, and 8 sagging rigging wires (~1.5 px wide
    at 800x800, a fifth of a pixel at 100x100) from the mast to the railing;
  - a chrome ship's wheel (16 spokes, 8 handles) on a wooden trestle; three lacquered drums with chrome
    hoops and tension rods, sticks and a brass cymbal; a grille of 19 x 15 bars at a 0.02 pitch (moire), a
    coil spring; a crate with labels and raised 3-D lettering, two hooped barrels and 24 loose nuts, balls,
    dice and bolts.
Specular surfaces (chrome, gold, steel, brass, clear-coated lacquer, copper) reflect a sky-to-ground
gradient world under a sun. Everything fits in a ball of radius R_MAX about the origin, so the object
stays inside every view. It covers a fifth of the frame seen from the side, 30% from 30 degrees up (the test
circle) and a third from above (pixels with alpha > 0.5, measured at 64x64).

Cameras as in nerf_synthetic: radius 4, camera_angle_x 0.6911; training views uniform on the upper
hemisphere (up to 78 degrees, short of the pole where "up" degenerates), test views on a circle at 30
degrees elevation, evenly spaced in azimuth. Training draws within 5 degrees of a test camera are redrawn
(blender_parts.camera_positions), so every test view is a new one (a band about the test circle holds no training
camera). The object does not depend on --seed; the cameras and the Cycles noise do.

Run by Blender, not by python3, as a module of this package (need_blender.sh's blender_module):
    tools/scenes/make_detail_object.sh OUT [--size 800] [--train 100] [--test 200] [--test-stride 1] [--samples 16] [--seed 7]
which renders and then runs check_scene. Writes OUT/transforms_{train,test}.json (camera_angle_x, aabb,
frames of ./train/r_<i> and 4x4 transform_matrix) and OUT/train/r_<i>.png, OUT/test/r_<i>.png (RGBA).
"""
import argparse
import math
import random
import sys

import bmesh
import bpy
import numpy as np
from mathutils import Matrix, Vector

from . import blender_parts as parts

RADIUS = 4.0  # camera distance (nerf_synthetic's is ~4.03)
TEST_ELEVATION_DEG = 30.0
TRAIN_Z_MAX = 0.98  # sin of the highest training elevation, 78.5 degrees
# At radius 4 a ball of radius 1.25 subtends asin(1.25 / 4) = 18.2 degrees, inside the 19.8 degree half
# field of view, for any camera that aims at the origin: a margin of >= 4 px at 96x96, ~35 px at 800x800.
R_MAX = 1.25

DECK = -0.4  # top of the plinth; everything stands on it
PROBE = (0.0, 0.0, DECK + 1.42)  # centre of the gold sphere: make_detail_object.sh passes it to check_scene --probe


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="make_detail_object.py")
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument("--size", type=int, default=800, help="image width = height in pixels")
    p.add_argument("--train", type=int, default=100)
    p.add_argument("--test", type=int, default=200)
    p.add_argument("--test-stride", type=int, default=1,
                   help="render every k-th test view only (the held-out subset a benchmark uses); the training "
                        "cameras stay those drawn around all --test views")
    p.add_argument("--samples", type=int, default=16, help="Cycles samples per pixel (no denoiser)")
    p.add_argument("--seed", type=int, default=7, help="camera positions and Cycles noise")
    p.add_argument("--threads", type=int, default=2)
    args = p.parse_args(argv)
    if args.test_stride < 1:
        p.error(f"--test-stride must be >= 1, got {args.test_stride}")
    return args


# ---------------------------------------------------------------- materials

def wrapped_coords(nodes, links, radius):
    # (arc length round the z axis at `radius`, z, 0): a 2-D texture (brick, posters) wrapped round a
    # cylinder at its true scale, with one seam where atan2 jumps.
    coord = nodes.new("ShaderNodeTexCoord")
    xyz = nodes.new("ShaderNodeSeparateXYZ")
    links.new(coord.outputs["Object"], xyz.inputs["Vector"])
    angle = nodes.new("ShaderNodeMath")
    angle.operation = "ARCTAN2"
    links.new(xyz.outputs["Y"], angle.inputs[0])
    links.new(xyz.outputs["X"], angle.inputs[1])
    arc = nodes.new("ShaderNodeMath")
    arc.operation = "MULTIPLY"
    arc.inputs[1].default_value = radius
    links.new(angle.outputs["Value"], arc.inputs[0])
    out = nodes.new("ShaderNodeCombineXYZ")
    links.new(arc.outputs["Value"], out.inputs["X"])
    links.new(xyz.outputs["Z"], out.inputs["Y"])
    return out.outputs["Vector"]


def box_side_coords(nodes, links):
    # (x + y, z, 0): on the vertical faces of an axis-aligned box a 2-D texture at its true scale.
    coord = nodes.new("ShaderNodeTexCoord")
    xyz = nodes.new("ShaderNodeSeparateXYZ")
    links.new(coord.outputs["Object"], xyz.inputs["Vector"])
    along = nodes.new("ShaderNodeMath")
    along.operation = "ADD"
    links.new(xyz.outputs["X"], along.inputs[0])
    links.new(xyz.outputs["Y"], along.inputs[1])
    out = nodes.new("ShaderNodeCombineXYZ")
    links.new(along.outputs["Value"], out.inputs["X"])
    links.new(xyz.outputs["Z"], out.inputs["Y"])
    return out.outputs["Vector"]


def math_node(nodes, links, operation, a, b):
    # a, b: a socket or a constant.
    node = nodes.new("ShaderNodeMath")
    node.operation = operation
    for i, v in enumerate((a, b)):
        if isinstance(v, (int, float)):
            node.inputs[i].default_value = v
        else:
            links.new(v, node.inputs[i])
    return node.outputs["Value"]


def brick_node(nodes, vector_links, color1, color2, mortar, width, height, mortar_size):
    # A brick texture in scene units (Scale 1): bricks `width` x `height` with `mortar_size` gaps.
    links, vector = vector_links
    brick = nodes.new("ShaderNodeTexBrick")
    brick.inputs["Color1"].default_value = (*color1, 1.0)
    brick.inputs["Color2"].default_value = (*color2, 1.0)
    brick.inputs["Mortar"].default_value = (*mortar, 1.0)
    brick.inputs["Scale"].default_value = 1.0
    brick.inputs["Brick Width"].default_value = width
    brick.inputs["Row Height"].default_value = height
    brick.inputs["Mortar Size"].default_value = mortar_size
    links.new(vector, brick.inputs["Vector"])
    return brick


def text_like_material(name, coords):
    # Printed sheets: rows of letter-sized blocks (random blanks between them make words) whose ink is
    # broken by a fine noise into strokes, on poster sheets of a few paper tints. coords(nodes, links) gives
    # the 2-D surface coordinates in scene units.
    mat, bsdf = parts.principled(name, roughness=0.6)
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    vec = coords(nodes, links)
    ink, paper = (0.02, 0.02, 0.03), (0.9, 0.88, 0.8)
    # Letters 0.013 x 0.025 at a 0.018 x 0.03 pitch; tint per block uniform, ~25% of blocks stay blank.
    letters = brick_node(nodes, (links, vec), ink, paper, paper, 0.018, 0.03, 0.005)
    grey = nodes.new("ShaderNodeRGBToBW")
    links.new(letters.outputs["Color"], grey.inputs["Color"])
    letter = math_node(nodes, links, "LESS_THAN", grey.outputs["Val"], 0.67)
    strokes = nodes.new("ShaderNodeTexNoise")
    strokes.inputs["Scale"].default_value = 160.0
    strokes.inputs["Detail"].default_value = 0.0
    links.new(vec, strokes.inputs["Vector"])
    stroke = math_node(nodes, links, "GREATER_THAN", strokes.outputs["Fac"], 0.47)
    printed = math_node(nodes, links, "MULTIPLY", letter, stroke)
    sheets = brick_node(nodes, (links, vec), (1.0, 0.95, 0.75), (0.75, 0.88, 1.0), (0.15, 0.15, 0.15),
                        0.22, 0.26, 0.006)
    text = nodes.new("ShaderNodeMixRGB")
    links.new(printed, text.inputs["Fac"])
    text.inputs["Color1"].default_value = (1.0, 1.0, 1.0, 1.0)
    text.inputs["Color2"].default_value = (*ink, 1.0)
    tinted = nodes.new("ShaderNodeMixRGB")
    tinted.blend_type = "MULTIPLY"
    tinted.inputs["Fac"].default_value = 1.0
    links.new(text.outputs["Color"], tinted.inputs["Color1"])
    links.new(sheets.outputs["Color"], tinted.inputs["Color2"])
    links.new(tinted.outputs["Color"], bsdf.inputs["Base Color"])
    return mat


def wood_material(name, scale=14.0):
    # Wave bands distorted by noise: grain lines a few pixels apart at 800x800.
    mat, bsdf = parts.principled(name, roughness=0.5)
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    coord = nodes.new("ShaderNodeTexCoord")
    wave = nodes.new("ShaderNodeTexWave")
    wave.inputs["Scale"].default_value = scale
    wave.inputs["Distortion"].default_value = 6.0
    wave.inputs["Detail"].default_value = 3.0
    links.new(coord.outputs["Object"], wave.inputs["Vector"])
    ramp = nodes.new("ShaderNodeValToRGB")
    ramp.color_ramp.elements[0].color = (0.25, 0.12, 0.04, 1.0)
    ramp.color_ramp.elements[1].color = (0.62, 0.4, 0.2, 1.0)
    links.new(wave.outputs["Fac"], ramp.inputs["Fac"])
    links.new(ramp.outputs["Color"], bsdf.inputs["Base Color"])
    return mat


def lacquer_material(name, color):
    # Glossy paint under a clear coat: two stacked highlights.
    mat, bsdf = parts.principled(name, color=color, roughness=0.3)
    bsdf.inputs["Clearcoat"].default_value = 1.0
    bsdf.inputs["Clearcoat Roughness"].default_value = 0.03
    return mat


def metal(name, color, roughness):
    return parts.principled(name, color=color, metallic=1.0, roughness=roughness)[0]


def make_materials():
    m = {
        "chrome": metal("chrome", (0.9, 0.9, 0.92), 0.05),
        "steel": metal("steel", (0.55, 0.56, 0.58), 0.3),
        "brass": metal("brass", (0.85, 0.6, 0.25), 0.25),
        "bronze": metal("bronze", (0.35, 0.22, 0.12), 0.4),
        "gold": parts.gold_material(),
        "rope": parts.principled("rope", color=(0.08, 0.06, 0.05), roughness=0.7)[0],
        "red_lacquer": lacquer_material("red_lacquer", (0.5, 0.02, 0.03)),
        "blue_lacquer": lacquer_material("blue_lacquer", (0.02, 0.08, 0.45)),
        "enamel": lacquer_material("enamel", (0.9, 0.75, 0.05)),
        "wood": wood_material("wood"),
        "deck": parts.checker_material("deck_checker", (0.8, 0.78, 0.72), (0.12, 0.13, 0.16), scale=25.0),
        "posters": text_like_material("posters", lambda n, l: wrapped_coords(n, l, 0.3)),
        "labels": text_like_material("labels", box_side_coords),
        "dice": parts.noise_material(),
    }
    # Bricks ~0.042 x 0.021 (Scale 12 on the 0.5 x 0.25 default brick), wrapped round the plinth.
    m["brick"] = parts.brick_material("plinth_brick", (0.55, 0.2, 0.12), (0.7, 0.42, 0.3), (0.8, 0.78, 0.72),
                                      12.0, 3.0)
    nodes, links = m["brick"].node_tree.nodes, m["brick"].node_tree.links
    links.new(wrapped_coords(nodes, links, 1.05), nodes["Brick Texture"].inputs["Vector"])
    roof, _, _, _, roof_bsdf = parts.noise_ramp_material("copper_roof", 9.0, 6.0, (0.15, 0.5, 0.4),
                                                          (0.72, 0.36, 0.18), roughness=0.35)
    roof_bsdf.inputs["Metallic"].default_value = 0.7
    m["roof"] = roof
    head, _, _, _, _ = parts.noise_ramp_material("drum_head", 40.0, 2.0, (0.78, 0.76, 0.7), (0.95, 0.94, 0.9),
                                                 roughness=0.55)
    m["head"] = head
    return m


# ---------------------------------------------------------------- geometry

def mesh_object(name, bm, material, smooth_angle_deg=50.0):
    # One object from a bmesh. Smooth shading with auto smooth: round tubes, sharp caps.
    mesh = bpy.data.meshes.new(name)
    bm.to_mesh(mesh)
    bm.free()
    for poly in mesh.polygons:
        poly.use_smooth = True
    mesh.use_auto_smooth = True
    mesh.auto_smooth_angle = math.radians(smooth_angle_deg)
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def tubes(name, material, segments, radius, sides=8):
    # Thin straight rods, one object: a capped cylinder from p0 to p1 for each (p0, p1).
    bm = bmesh.new()
    for p0, p1 in segments:
        p0, p1 = Vector(p0), Vector(p1)
        d = p1 - p0
        rot = d.to_track_quat("Z", "Y").to_matrix().to_4x4()
        bmesh.ops.create_cone(bm, cap_ends=True, cap_tris=False, segments=sides, radius1=radius,
                              radius2=radius, depth=d.length, matrix=Matrix.Translation((p0 + p1) / 2) @ rot)
    return mesh_object(name, bm, material)


def polyline(points):
    return list(zip(points[:-1], points[1:]))


def sagging(a, b, sag, n=24):
    # A hanging wire from a to b: the straight line lowered by a parabola, sag at the middle.
    a, b = Vector(a), Vector(b)
    return [a.lerp(b, t) - Vector((0, 0, 4 * sag * t * (1 - t))) for t in (i / n for i in range(n + 1))]


def ring_points(radius, z, count, phase=0.0):
    return [(radius * math.cos(phase + 2 * math.pi * i / count), radius * math.sin(phase + 2 * math.pi * i / count), z)
            for i in range(count)]


def build_plinth_and_kiosk(m):
    mesh = bpy.ops.mesh
    plinth = parts.add(mesh.primitive_cylinder_add, m["brick"], "plinth",
                       vertices=24, radius=1.05, depth=0.2, location=(0, 0, DECK - 0.1))
    plinth.data.materials.append(m["deck"])
    for poly in plinth.data.polygons:
        if poly.normal.z > 0.5:
            poly.material_index = 1  # the top face is the checkered deck
    kiosk = parts.add(mesh.primitive_cylinder_add, m["posters"], "kiosk",
                      vertices=64, radius=0.3, depth=0.52, location=(0, 0, DECK + 0.26))
    parts.smooth(kiosk)
    parts.smooth(parts.add(mesh.primitive_torus_add, m["steel"], "cornice", major_segments=96, minor_segments=12,
                           major_radius=0.31, minor_radius=0.02, location=(0, 0, DECK + 0.52)))
    roof = parts.add(mesh.primitive_cone_add, m["roof"], "roof",
                     vertices=64, radius1=0.4, depth=0.28, location=(0, 0, DECK + 0.52 + 0.14))
    parts.smooth(roof)


def build_mast(m, z0=DECK + 0.72, z1=DECK + 1.34, w0=0.1, w1=0.035, levels=6):
    # A tapering square lattice tower: 4 legs, a square of rungs at each level, X braces on each face.
    corners = []
    for k in range(levels + 1):
        t = k / levels
        z, w = z0 + t * (z1 - z0), w0 + t * (w1 - w0)
        corners.append([(w, w, z), (-w, w, z), (-w, -w, z), (w, -w, z)])
    legs, rungs, braces = [], [], []
    for k in range(levels):
        for j in range(4):
            a, b = corners[k][j], corners[k][(j + 1) % 4]
            c, d = corners[k + 1][j], corners[k + 1][(j + 1) % 4]
            legs.append((a, c))
            braces += [(a, d), (b, c)]
    for k in range(1, levels + 1):
        rungs += polyline(corners[k] + [corners[k][0]])
    tubes("mast_legs", m["steel"], legs, 0.008)
    tubes("mast_rungs", m["steel"], rungs, 0.005)
    tubes("mast_braces", m["steel"], braces, 0.0035, sides=6)
    parts.smooth(parts.add(bpy.ops.mesh.primitive_uv_sphere_add, m["gold"], "gold_sphere",
                           segments=48, ring_count=24, radius=0.09, location=PROBE))
    return corners[-1], corners[3]


def build_railing_and_rigging(m, mast_top, mast_mid):
    rail_r, top = 0.98, DECK + 0.14
    posts = [((x, y, DECK), (x, y, top)) for x, y, _ in ring_points(rail_r, 0, 60)]
    tubes("railing_posts", m["brass"], posts, 0.005)
    for name, z, tube in (("rail_top", top, 0.006), ("rail_mid", DECK + 0.07, 0.004)):
        parts.smooth(parts.add(bpy.ops.mesh.primitive_torus_add, m["brass"], name, major_segments=240,
                               minor_segments=8, major_radius=rail_r, minor_radius=tube, location=(0, 0, z)))
    # 8 wires from the mast (top and middle corners alternately) to the top rail, between the deck items.
    wires = []
    for i, end in enumerate(ring_points(rail_r, top, 8, phase=math.pi / 8)):
        start = (mast_top if i % 2 == 0 else mast_mid)[(i // 2) % 4]
        wires += polyline(sagging(start, end, 0.04))
    tubes("rigging", m["rope"], wires, 0.0025, sides=6)


def build_wheel(m, cx=0.6, cz=DECK + 0.33):
    # A ship's wheel in the xz plane (axle along y) on a wooden trestle, handles between the spokes.
    mesh = bpy.ops.mesh
    upright = (math.radians(90), 0, 0)
    parts.smooth(parts.add(mesh.primitive_torus_add, m["chrome"], "wheel_rim", major_segments=128, minor_segments=12,
                           major_radius=0.21, minor_radius=0.012, location=(cx, 0, cz), rotation=upright))
    parts.smooth(parts.add(mesh.primitive_torus_add, m["chrome"], "wheel_inner_ring", major_segments=64,
                           minor_segments=8, major_radius=0.07, minor_radius=0.008, location=(cx, 0, cz),
                           rotation=upright))
    parts.smooth(parts.add(mesh.primitive_cylinder_add, m["brass"], "wheel_hub", vertices=24, radius=0.035,
                           depth=0.05, location=(cx, 0, cz), rotation=upright))
    centre = Vector((cx, 0, cz))
    spokes, handles, knobs = [], [], []
    for i in range(16):
        a = 2 * math.pi * i / 16
        u = Vector((math.cos(a), 0, math.sin(a)))
        spokes.append((centre + 0.03 * u, centre + 0.21 * u))
        if i % 2:  # 8 handles, none pointing straight at the kiosk or the railing
            handles.append((centre + 0.21 * u, centre + 0.27 * u))
            knobs.append(centre + 0.275 * u)
    tubes("wheel_spokes", m["chrome"], spokes, 0.0045)
    tubes("wheel_handles", m["wood"], handles, 0.009)
    for i, p in enumerate(knobs):
        parts.smooth(parts.add(mesh.primitive_uv_sphere_add, m["wood"], f"wheel_knob_{i}",
                               segments=16, ring_count=8, radius=0.016, location=p))
    trestle = []
    for y in (-0.05, 0.05):
        trestle += [((cx - 0.13, y, DECK), (cx, y, cz - 0.02)), ((cx + 0.13, y, DECK), (cx, y, cz - 0.02))]
    tubes("wheel_trestle", m["wood"], trestle, 0.01)
    tubes("wheel_axle", m["steel"], [((cx, -0.07, cz), (cx, 0.07, cz))], 0.01)


def drum(m, name, x, y, radius, height, shell):
    mesh = bpy.ops.mesh
    zc = DECK + height / 2
    parts.smooth(parts.add(mesh.primitive_cylinder_add, shell, f"{name}_shell", vertices=64, radius=radius,
                           depth=height, location=(x, y, zc)))
    parts.add(mesh.primitive_cylinder_add, m["head"], f"{name}_head", vertices=64, radius=radius * 0.97,
              depth=0.004, location=(x, y, DECK + height + 0.002))
    for z, tag in ((DECK + height, "top"), (DECK + 0.008, "bottom")):
        parts.smooth(parts.add(mesh.primitive_torus_add, m["chrome"], f"{name}_hoop_{tag}", major_segments=96,
                               minor_segments=8, major_radius=radius + 0.004, minor_radius=0.007, location=(x, y, z)))
    rods = [((px + x, py + y, DECK + 0.012), (px + x, py + y, DECK + height - 0.004))
            for px, py, _ in ring_points(radius + 0.012, 0, 10)]
    tubes(f"{name}_rods", m["chrome"], rods, 0.003, sides=6)


def build_drums(m):
    drum(m, "drum_big", 0.15, 0.56, 0.13, 0.22, m["red_lacquer"])
    drum(m, "drum_small", -0.16, 0.62, 0.1, 0.16, m["blue_lacquer"])
    drum(m, "drum_tom", 0.43, 0.45, 0.08, 0.28, m["red_lacquer"])
    top = DECK + 0.22 + 0.01
    tubes("drum_sticks", m["wood"], [((0.05, 0.5, top), (0.27, 0.63, top)), ((0.06, 0.63, top + 0.012),
                                                                           (0.26, 0.5, top + 0.012))], 0.006)
    # Cymbal on a thin stand, tilted towards the outside.
    tubes("cymbal_stand", m["steel"], [((-0.35, 0.45, DECK), (-0.35, 0.45, DECK + 0.48))], 0.006)
    tubes("cymbal_feet", m["steel"], [((-0.35, 0.45, DECK + 0.1), (-0.35 + 0.08 * dx, 0.45 + 0.08 * dy, DECK))
                                      for dx, dy, _ in ring_points(1.0, 0, 3)], 0.004)
    parts.add(bpy.ops.mesh.primitive_cone_add, m["brass"], "cymbal", vertices=96, radius1=0.12, radius2=0.015,
              depth=0.012, location=(-0.35, 0.45, DECK + 0.5), rotation=(math.radians(-12), math.radians(-10), 0))


def build_grille_and_spring(m, x=-0.62, half_w=0.2, z0=DECK + 0.05, z1=DECK + 0.37):
    # A screen facing -x: a frame on two feet round a grid of bars 0.02 apart, ~5 px at 800x800 and well
    # under a pixel at 100x100 (a moire test).
    frame = polyline([(x, -half_w, z0), (x, half_w, z0), (x, half_w, z1), (x, -half_w, z1), (x, -half_w, z0)])
    frame += [((x, y, DECK), (x, y, z0)) for y in (-half_w + 0.03, half_w - 0.03)]
    tubes("grille_frame", m["bronze"], frame, 0.008)
    bars = [((x, y, z0), (x, y, z1)) for y in np.arange(-half_w + 0.02, half_w - 0.01, 0.02)]
    bars += [((x, -half_w, z), (x, half_w, z)) for z in np.arange(z0 + 0.02, z1 - 0.01, 0.02)]
    tubes("grille_bars", m["bronze"], bars, 0.0028, sides=6)
    # A coil spring: 10 turns of wire, radius 0.06, standing on the deck.
    turns, n = 10, 160
    coil = [(-0.45 + 0.06 * math.cos(2 * math.pi * turns * i / n), -0.5 + 0.06 * math.sin(2 * math.pi * turns * i / n),
             DECK + 0.006 + 0.26 * i / n) for i in range(n + 1)]
    tubes("spring", m["chrome"], polyline(coil), 0.005, sides=6)


def build_crate_and_small_parts(m):
    mesh = bpy.ops.mesh
    crate = parts.add(mesh.primitive_cube_add, m["labels"], "crate", size=1.0, location=(0.0, -0.6, DECK + 0.11),
                      scale=(0.28, 0.2, 0.22))
    # Into the mesh: the labels' object coordinates then measure scene units, as the other textures do.
    bpy.ops.object.transform_apply(location=False, rotation=False, scale=True)
    crate.data.materials.append(m["wood"])
    for poly in crate.data.polygons:
        if abs(poly.normal.z) > 0.5:
            poly.material_index = 1  # a wooden lid; the labels wrap the sides
    # Raised lettering on a sign on the lid, facing -y (outwards).
    bpy.ops.object.text_add(location=(0.0, -0.62, DECK + 0.225), rotation=(math.radians(90), 0, 0))
    text = bpy.context.active_object
    text.name = "sign_text"
    text.data.body = "VKNERF"
    text.data.align_x = "CENTER"
    text.data.size = 0.06
    text.data.extrude = 0.006
    text.data.materials.append(m["enamel"])
    bpy.ops.object.convert(target="MESH")  # a mesh like everything else: content_aabb counts meshes
    for i, (x, y) in enumerate(((0.3, -0.6), (0.38, -0.45))):
        parts.smooth(parts.add(mesh.primitive_cylinder_add, m["wood"], f"barrel_{i}", vertices=48, radius=0.06,
                               depth=0.13, location=(x, y, DECK + 0.065)))
        for j, z in enumerate((0.02, 0.065, 0.11)):
            parts.smooth(parts.add(mesh.primitive_torus_add, m["steel"], f"barrel_{i}_hoop_{j}", major_segments=64,
                                   minor_segments=6, major_radius=0.061, minor_radius=0.004,
                                   location=(x, y, DECK + z)))
    scatter_small_parts(m, random.Random(11))


def scatter_small_parts(m, rng, count=24):
    # Loose nuts, balls, dice and bolts in the free sectors of the deck, not touching one another. The rng
    # is fixed: the object is the same whatever --seed.
    mesh = bpy.ops.mesh
    placed = []
    keep_clear = [(-0.45, -0.5, 0.1), (0.0, -0.6, 0.2), (0.3, -0.6, 0.09), (0.38, -0.45, 0.09)]
    while len(placed) < count:
        r = rng.uniform(0.38, 0.8)
        a = math.radians(rng.choice((rng.uniform(200, 245), rng.uniform(285, 340))))
        x, y = r * math.cos(a), r * math.sin(a)
        if any(math.hypot(x - px, y - py) < pr + 0.035 for px, py, pr in keep_clear + placed):
            continue
        i, kind, turn = len(placed), len(placed) % 4, rng.uniform(0, math.pi)
        if kind == 0:
            parts.add(mesh.primitive_cylinder_add, m["brass"], f"nut_{i}", vertices=6, radius=0.022, depth=0.014,
                      location=(x, y, DECK + 0.007), rotation=(0, 0, turn))
        elif kind == 1:
            parts.smooth(parts.add(mesh.primitive_uv_sphere_add, m["chrome"], f"ball_{i}", segments=24,
                                   ring_count=12, radius=0.018, location=(x, y, DECK + 0.018)))
        elif kind == 2:
            parts.add(mesh.primitive_cube_add, m["dice"], f"die_{i}", size=0.035, location=(x, y, DECK + 0.0175),
                      rotation=(0, 0, turn))
        else:
            u = Vector((math.cos(turn), math.sin(turn), 0))
            p = Vector((x, y, DECK + 0.007))
            tubes(f"bolt_{i}", m["steel"], [(p - 0.03 * u, p + 0.03 * u)], 0.006)
            parts.add(mesh.primitive_cylinder_add, m["steel"], f"bolt_head_{i}", vertices=6, radius=0.013,
                      depth=0.01, location=p - 0.033 * u, rotation=(0, math.radians(90), turn))
        placed.append((x, y, 0.03))


def build_object():
    m = make_materials()
    build_plinth_and_kiosk(m)
    mast_top, mast_mid = build_mast(m)
    build_railing_and_rigging(m, mast_top, mast_mid)
    build_wheel(m)
    build_drums(m)
    build_grille_and_spring(m)
    build_crate_and_small_parts(m)


def farthest_point():
    # Largest distance of any vertex from the origin (the framing guarantee of R_MAX).
    far = 0.0
    for obj in bpy.context.scene.objects:
        if obj.type != "MESH":
            continue
        co = np.empty(3 * len(obj.data.vertices))
        obj.data.vertices.foreach_get("co", co)
        w = np.array(obj.matrix_world)
        pts = co.reshape(-1, 3) @ w[:3, :3].T + w[:3, 3]
        far = max(far, float(np.linalg.norm(pts, axis=1).max()))
    return far


def build_lights():
    # Sky-to-ground gradient (near-neutral, so the gold probe keeps its hue) for the metals to reflect, and
    # the tabletop's sun for shadows and highlights.
    world = bpy.data.worlds.new("gradient")
    world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    coord = nodes.new("ShaderNodeTexCoord")  # in a world, Generated is the view direction
    xyz = nodes.new("ShaderNodeSeparateXYZ")
    links.new(coord.outputs["Generated"], xyz.inputs["Vector"])
    up = math_node(nodes, links, "MULTIPLY_ADD", xyz.outputs["Z"], 0.5)
    up.node.inputs[2].default_value = 0.5  # z in [-1, 1] -> [0, 1]
    ramp = nodes.new("ShaderNodeValToRGB")
    ramp.color_ramp.elements[0].position = 0.45
    ramp.color_ramp.elements[0].color = (0.18, 0.16, 0.14, 1.0)  # ground
    ramp.color_ramp.elements[1].position = 0.52
    ramp.color_ramp.elements[1].color = (0.95, 0.93, 0.9, 1.0)  # horizon
    top = ramp.color_ramp.elements.new(1.0)
    top.color = (0.7, 0.75, 0.85, 1.0)  # zenith
    links.new(up, ramp.inputs["Fac"])
    bg = nodes["Background"]
    links.new(ramp.outputs["Color"], bg.inputs["Color"])
    bg.inputs["Strength"].default_value = 0.7
    bpy.context.scene.world = world
    parts.add_sun()


def test_positions(count):
    # nerf_synthetic's test path: evenly spaced round a circle at one elevation.
    e = math.radians(TEST_ELEVATION_DEG)
    return [Vector((RADIUS * math.cos(e) * math.cos(a), RADIUS * math.cos(e) * math.sin(a), RADIUS * math.sin(e)))
            for a in (2 * math.pi * i / count for i in range(count))]


def main():
    args = parse_args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    build_object()
    far = farthest_point()
    assert far <= R_MAX, f"the object reaches {far:.3f} from the origin, beyond R_MAX = {R_MAX}"
    build_lights()
    parts.setup_cycles(args.samples, args.seed, args.threads, args.size, args.size, transparent=True)
    cam = parts.add_nerf_synthetic_camera()
    aabb = parts.content_aabb()
    test = test_positions(args.test)
    train = parts.camera_positions(random.Random(args.seed), args.train, RADIUS, avoid=test,
                                   z_min=0.0, z_max=TRAIN_Z_MAX)
    parts.render_split(cam, args.out, "train", train, aabb)
    rendered_test = test[::args.test_stride]
    parts.render_split(cam, args.out, "test", rendered_test, aabb)
    print(f"make_detail_object: wrote {args.train} train + {len(rendered_test)} test views to {args.out}, "
          f"aabb {aabb}, farthest point {far:.3f}")


main()
