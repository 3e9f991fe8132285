# Shared by the three <scene>_cycles.py scripts: builds a peer scene in Blender 3.4 and renders it
# with Cycles (the third peer of docs/PEERS.md). Each scene script describes its geometry,
# materials, lamp and camera in caustica's coordinates and conventions (right-handed, y up) and
# calls render(); this module turns them into Blender objects (z up), sets Cycles up as
# bench/peers/README.md explains, renders and writes:
#   OUT.exr  the linear float image, as Cycles made it;
#   OUT.png  the same values clamped to [0, 1] and truncated to 8 bits (x 255, no rounding): what
#            caustica writes by default, so image_diff compares like with like;
# and prints one line that run.sh parses:
#   cycles: mode=M size=N time_limit=T render_s=R convert_s=C
# (render_s: the seconds bpy.ops.render.render took, scene synchronisation, BVH build and the
# EXR's writing included; convert_s: the seconds spent reading the EXR back and writing the PNG,
# which run.sh takes off the process's wall time: a cost of our comparison, not of Cycles).
# Cycles' own progress lines ("... | Time:00:05.37 | ... | Sample 57/...") give its samples and
# its render time; run.sh reads them from the log.
#
#   blender -b --factory-startup --python-exit-code 2 -P SCENE_cycles.py -- \
#       --out PREFIX [--size 512] [--time SECONDS] [--samples N] [--mode mnee|path] [--seed N]
#       [--threads 2] [--lamp-radius 0.02]
#
# --mode mnee: path tracing with shadow caustics (manifold next-event estimation: the glass and
# metal objects cast, the diffuse ones receive, the lamp is a caustics light); --mode path: plain
# path tracing (caustics only where a path from a diffuse surface happens to hit the lamp).
import argparse
import math
import struct
import sys
import time
import zlib
from array import array

import bpy
from mathutils import Matrix, Vector

# Our point lights become Cycles point lights of this radius (--lamp-radius): a true point
# (radius 0) cannot be hit by a path, so plain path tracing would draw no caustic at all; at 0.02
# the lamp's image through the glass sphere, ~0.005 wide, is under a pixel of the 512 x 512 image.
LAMP_RADIUS = 0.02
# A Cycles point light of power P (watts) has the radiant intensity P / (4 pi) and a Diffuse
# BSDF of albedo kd reflects kd / pi of its irradiance, so the floor's radiance is
# kd P cos / (4 pi^2 d^2); our lights give kd C cos / (c0 + c2 d^2) without the 1 / pi. With the
# falloff written as Cycles' quadratic falloff with smooth c0 / c2 (see point_light), the two agree
# when P = 4 pi^2 C / c2. run.sh checks it on a directly lit floor patch against caustica's render.
def lamp_power(c2):
    return 4.0 * math.pi ** 2 / c2


def to_blender(p):
    """Our (x, y, z), y up, to Blender's (x, -z, y), z up: a rotation, so handedness is kept."""
    return Vector((p[0], -p[2], p[1]))


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog="SCENE_cycles.py")
    parser.add_argument("--out", required=True, help="output prefix: writes PREFIX.exr and PREFIX.png")
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--time", type=float, default=0.0, help="Cycles' time limit in seconds (0: none)")
    parser.add_argument("--samples", type=int, default=0, help="samples per pixel (0: as many as the time allows)")
    parser.add_argument("--mode", choices=("mnee", "path"), default="mnee")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--lamp-radius", type=float, default=LAMP_RADIUS)
    args = parser.parse_args(argv)
    if args.time <= 0 and args.samples <= 0:
        parser.error("give --time or --samples")
    return args


# ---------------------------------------------------------------------------------------------
# Geometry, built in our coordinates and rotated into Blender's.

def _mesh_object(name, vertices, faces, material):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata([tuple(to_blender(v)) for v in vertices], [], faces)
    # Every face smooth, with auto smooth at 30 degrees: curved walls get interpolated normals
    # (MNEE refuses casters without smooth normals), the sharp rims and caps stay sharp.
    for polygon in mesh.polygons:
        polygon.use_smooth = True
    mesh.use_auto_smooth = True
    mesh.auto_smooth_angle = math.radians(30.0)
    mesh.validate()
    mesh.update()
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def box(name, lo, hi, material):
    """The axis-aligned box [lo, hi] (our gr.cube translate(t) scale(s): lo = t - s, hi = t + s)."""
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    vertices = [(x0, y0, z0), (x1, y0, z0), (x1, y1, z0), (x0, y1, z0),
                (x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)]
    # Counter-clockwise seen from outside (right-handed, in our coordinates).
    faces = [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (3, 7, 6, 2), (0, 4, 7, 3), (1, 2, 6, 5)]
    return _mesh_object(name, vertices, faces, material)


def lathe(name, profile, centre, material, segments=256):
    """A surface of revolution about the vertical axis through centre: profile is a polyline of
    (r, y) points (y relative to centre), walked so that the surface's outside is on the
    (dy, -dr) side of each segment (e.g. up the outer wall of a cylinder, then inwards across its
    top). Points with r = 0 become poles."""
    cx, cy, cz = centre
    vertices, rings = [], []
    for r, y in profile:
        if r == 0.0:
            rings.append([len(vertices)] * segments)
            vertices.append((cx, cy + y, cz))
        else:
            ring = []
            for j in range(segments):
                a = 2.0 * math.pi * j / segments
                ring.append(len(vertices))
                vertices.append((cx + r * math.cos(a), cy + y, cz + r * math.sin(a)))
            rings.append(ring)
    faces = []
    for i in range(len(profile) - 1):
        (r0, y0), (r1, y1) = profile[i], profile[i + 1]
        flip = None
        for j in range(segments):
            k = (j + 1) % segments
            quad = [rings[i][j], rings[i][k], rings[i + 1][k], rings[i + 1][j]]
            # Drop the repeated pole vertex of a triangle next to a pole.
            face = [v for n, v in enumerate(quad) if v not in quad[:n]]
            if len(face) < 3:
                continue
            if flip is None:
                # Orient the segment's faces so that their normals point to the (dy, -dr) side.
                a, b, c = (Vector(vertices[v]) for v in face[:3])
                mid = 2.0 * math.pi * (j + 0.5) / segments
                want = Vector(((y1 - y0) * math.cos(mid), -(r1 - r0), (y1 - y0) * math.sin(mid)))
                flip = (b - a).cross(c - a).dot(want) < 0.0
            faces.append(tuple(reversed(face)) if flip else tuple(face))
    return _mesh_object(name, vertices, faces, material)


def sphere(name, centre, radius, material, rings=128, segments=256):
    profile = [(radius * math.sin(math.pi * i / rings), -radius * math.cos(math.pi * i / rings))
               for i in range(rings + 1)]
    profile[0] = (0.0, -radius)
    profile[-1] = (0.0, radius)
    return lathe(name, profile, centre, material, segments)


# ---------------------------------------------------------------------------------------------
# Materials.

def _material(name):
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    nodes = material.node_tree.nodes
    nodes.clear()
    output = nodes.new("ShaderNodeOutputMaterial")
    return material, nodes, material.node_tree.links, output


def diffuse(name, kd):
    """Our opaque kd: a Diffuse BSDF of albedo kd, black to every path that has already bounced
    off a diffuse surface. caustica has no indirect diffuse light (no ambient, no GI map), so the
    only light reaching a diffuse surface is the lamp's, directly or through mirrors and glass;
    Cycles needs two diffuse bounces for its shadow caustics (MNEE counts one for the receiver
    and one for the light) and would otherwise add floor-to-wall interreflection."""
    material, nodes, links, output = _material(name)
    lit = nodes.new("ShaderNodeBsdfDiffuse")
    lit.inputs["Color"].default_value = (kd[0], kd[1], kd[2], 1.0)
    lit.inputs["Roughness"].default_value = 0.0
    black = nodes.new("ShaderNodeBsdfDiffuse")
    black.inputs["Color"].default_value = (0.0, 0.0, 0.0, 1.0)
    path = nodes.new("ShaderNodeLightPath")
    bounced = nodes.new("ShaderNodeMath")
    bounced.operation = "GREATER_THAN"
    bounced.inputs[1].default_value = 0.5
    links.new(path.outputs["Diffuse Depth"], bounced.inputs[0])
    mix = nodes.new("ShaderNodeMixShader")
    links.new(bounced.outputs[0], mix.inputs["Fac"])
    links.new(lit.outputs["BSDF"], mix.inputs[1])
    links.new(black.outputs["BSDF"], mix.inputs[2])
    links.new(mix.outputs["Shader"], output.inputs["Surface"])
    return material


def glass(name, ior):
    """Our clear dielectric (ks = 1, set_ri(ior)): a sharp Glass BSDF, Fresnel between the
    reflection and the refraction, white."""
    material, nodes, links, output = _material(name)
    bsdf = nodes.new("ShaderNodeBsdfGlass")
    bsdf.distribution = "SHARP"
    bsdf.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    bsdf.inputs["IOR"].default_value = ior
    links.new(bsdf.outputs["BSDF"], output.inputs["Surface"])
    return material


def mirror(name, ks):
    """Our set_reflective mirror of colour ks (kd = 0): a sharp Glossy BSDF of colour ks."""
    material, nodes, links, output = _material(name)
    bsdf = nodes.new("ShaderNodeBsdfGlossy")
    bsdf.distribution = "SHARP"
    bsdf.inputs["Color"].default_value = (ks[0], ks[1], ks[2], 1.0)
    bsdf.inputs["Roughness"].default_value = 0.0
    links.new(bsdf.outputs["BSDF"], output.inputs["Surface"])
    return material


def liquid(name, ior_air, ior_glass, centre, top_y, wall_r, per_unit):
    """A dielectric medium inside glass: a sharp Glass BSDF whose index is ior_air where the
    liquid meets air (its top, inside wall_r, above top_y; object coordinates relative to
    centre) and ior_air / ior_glass where it meets the glass (a single interface between the two
    media, as our CSG union makes it), and a Volume Absorption that keeps per_unit of the light
    per unit of distance: (1 - colour) density = ln(1 / per_unit), density = ln(1 / min per_unit)."""
    material, nodes, links, output = _material(name)
    coordinates = nodes.new("ShaderNodeTexCoord")
    split = nodes.new("ShaderNodeSeparateXYZ")
    links.new(coordinates.outputs["Object"], split.inputs[0])
    # Object coordinates are Blender's (x, -z, y) of ours, around the object's origin (0).
    up = nodes.new("ShaderNodeMath")
    up.operation = "GREATER_THAN"
    up.inputs[1].default_value = top_y - 1e-3 - centre[1]
    links.new(split.outputs["Z"], up.inputs[0])
    r2 = nodes.new("ShaderNodeVectorMath")
    r2.operation = "DOT_PRODUCT"
    flat = nodes.new("ShaderNodeCombineXYZ")
    links.new(split.outputs["X"], flat.inputs["X"])
    links.new(split.outputs["Y"], flat.inputs["Y"])
    sub = nodes.new("ShaderNodeVectorMath")
    sub.operation = "SUBTRACT"
    sub.inputs[1].default_value = (centre[0], -centre[2], 0.0)
    links.new(flat.outputs[0], sub.inputs[0])
    links.new(sub.outputs[0], r2.inputs[0])
    links.new(sub.outputs[0], r2.inputs[1])
    inside = nodes.new("ShaderNodeMath")
    inside.operation = "LESS_THAN"
    inside.inputs[1].default_value = wall_r ** 2
    links.new(r2.outputs["Value"], inside.inputs[0])
    top = nodes.new("ShaderNodeMath")
    top.operation = "MULTIPLY"
    links.new(up.outputs[0], top.inputs[0])
    links.new(inside.outputs[0], top.inputs[1])
    ior = nodes.new("ShaderNodeMapRange")
    ior.inputs["To Min"].default_value = ior_air / ior_glass
    ior.inputs["To Max"].default_value = ior_air
    links.new(top.outputs[0], ior.inputs["Value"])
    bsdf = nodes.new("ShaderNodeBsdfGlass")
    bsdf.distribution = "SHARP"
    bsdf.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    links.new(ior.outputs["Result"], bsdf.inputs["IOR"])
    links.new(bsdf.outputs["BSDF"], output.inputs["Surface"])
    density = math.log(1.0 / min(per_unit))
    absorption = nodes.new("ShaderNodeVolumeAbsorption")
    absorption.inputs["Color"].default_value = tuple(1.0 - math.log(1.0 / c) / density for c in per_unit) + (1.0,)
    absorption.inputs["Density"].default_value = density
    links.new(absorption.outputs["Volume"], output.inputs["Volume"])
    return material


# ---------------------------------------------------------------------------------------------
# Lamp, camera, render.

def point_light(args, position, colour, falloff):
    """Our gr.light(position, colour, {c0, c1, c2}) with c1 = 0: a Cycles point light of radius
    args.lamp_radius whose emission goes through a Light Falloff node, quadratic with smooth c0 / c2:
    strength d^2 / (d^2 + c0 / c2) times the light's own 1 / d^2 = c2 / (c0 + c2 d^2)."""
    c0, c1, c2 = falloff
    if c1 != 0.0:
        raise ValueError("Cycles has no linear term to add to a quadratic falloff")
    peak = max(colour)
    light = bpy.data.lights.new("lamp", type="POINT")
    light.color = tuple(c / peak for c in colour)
    light.energy = peak * lamp_power(c2)
    light.shadow_soft_size = args.lamp_radius
    light.cycles.cast_shadow = True
    light.cycles.use_multiple_importance_sampling = True
    light.cycles.is_caustics_light = args.mode == "mnee"
    light.use_nodes = True
    nodes = light.node_tree.nodes
    emission = nodes.get("Emission") or nodes.new("ShaderNodeEmission")
    fall = nodes.new("ShaderNodeLightFalloff")
    fall.inputs["Strength"].default_value = 1.0
    fall.inputs["Smooth"].default_value = c0 / c2
    light.node_tree.links.new(fall.outputs["Quadratic"], emission.inputs["Strength"])
    emission.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    obj = bpy.data.objects.new("lamp", light)
    obj.location = to_blender(position)
    obj.visible_camera = False  # our lights are not drawn
    bpy.context.scene.collection.objects.link(obj)
    return obj


def camera(eye, view, up, fovy):
    """Our gr.render(..., eye, view, up, fovy) on a square image: fovy is the horizontal (and,
    the image being square, the vertical) field of view in degrees."""
    data = bpy.data.cameras.new("camera")
    data.lens_unit = "FOV"
    data.sensor_fit = "HORIZONTAL"
    data.angle_x = math.radians(fovy)
    data.clip_start = 1e-3
    data.clip_end = 1e3
    obj = bpy.data.objects.new("camera", data)
    forward = to_blender(view).normalized()
    right = forward.cross(to_blender(up)).normalized()
    true_up = right.cross(forward)
    # A Blender camera looks down its -z with +y up and +x right.
    rotation = Matrix((right, true_up, -forward)).transposed()
    obj.matrix_world = Matrix.Translation(to_blender(eye)) @ rotation.to_4x4()
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.scene.camera = obj
    return obj


def start():
    """An empty scene (no default cube, lamp or camera) set up for Cycles; returns the arguments."""
    args = parse_args()
    bpy.ops.wm.read_factory_settings(use_empty=True)
    return args


def mark_casters(args, casters, receivers):
    for obj in casters:
        obj.cycles.is_caustics_caster = args.mode == "mnee"
    for obj in receivers:
        obj.cycles.is_caustics_receiver = args.mode == "mnee"


def _write_png8(path, width, height, pixels):
    """pixels: linear RGBA floats, bottom row first (Blender's order). Writes an 8-bit RGB PNG,
    top row first, each value clamped to [0, 1] and truncated (v x 255), as caustica does."""
    rows = []
    for y in range(height - 1, -1, -1):
        row = pixels[y * width * 4:(y + 1) * width * 4]
        values = bytearray(3 * width)
        for x in range(width):
            for c in range(3):
                v = row[4 * x + c]
                values[3 * x + c] = 0 if not v > 0.0 else (255 if v >= 1.0 else int(v * 255.0))
        rows.append(b"\0" + bytes(values))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n")
        f.write(chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)))
        f.write(chunk(b"IDAT", zlib.compress(b"".join(rows), 6)))
        f.write(chunk(b"IEND", b""))


def render(args):
    scene = bpy.context.scene
    scene.render.engine = "CYCLES"
    cycles = scene.cycles
    cycles.device = "CPU"
    scene.render.threads_mode = "FIXED"
    scene.render.threads = args.threads
    scene.render.resolution_x = args.size
    scene.render.resolution_y = args.size
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = False
    scene.render.use_persistent_data = False
    # World black: no ambient light.
    world = bpy.data.worlds.new("black")
    world.use_nodes = False
    world.color = (0.0, 0.0, 0.0)
    scene.world = world
    # Samples: a time limit with a sample count it never reaches, or a fixed count.
    cycles.samples = args.samples if args.samples > 0 else 1 << 24
    cycles.time_limit = args.time if args.samples <= 0 else 0.0
    cycles.use_adaptive_sampling = False
    cycles.use_denoising = False
    cycles.seed = args.seed
    cycles.use_animated_seed = False
    # A box filter one pixel wide: each sample anywhere in its pixel, equally weighted.
    cycles.pixel_filter_type = "BOX"
    cycles.filter_width = 1.0
    # Nothing that trades bias for noise: no clamping, no glossy blur, no light threshold.
    cycles.sample_clamp_direct = 0.0
    cycles.sample_clamp_indirect = 0.0
    cycles.blur_glossy = 0.0
    cycles.light_sampling_threshold = 0.0
    cycles.caustics_reflective = True
    cycles.caustics_refractive = True
    # Our --max-depth 8 for mirrors and glass; diffuse: see diffuse() above; no volume scattering.
    cycles.max_bounces = 12
    cycles.glossy_bounces = 8
    cycles.transmission_bounces = 8
    cycles.diffuse_bounces = 2
    cycles.volume_bounces = 0
    cycles.transparent_max_bounces = 8
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    settings = scene.render.image_settings
    settings.file_format = "OPEN_EXR"
    settings.color_depth = "32"
    settings.exr_codec = "ZIP"
    scene.render.use_file_extension = False
    scene.render.filepath = args.out + ".exr"

    began = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    seconds = time.perf_counter() - began

    began = time.perf_counter()
    image = bpy.data.images.load(args.out + ".exr")
    width, height = image.size
    pixels = array("f", bytes(4 * 4 * width * height))
    image.pixels.foreach_get(pixels)
    _write_png8(args.out + ".png", width, height, pixels)
    converting = time.perf_counter() - began
    print("cycles: mode=%s size=%d time_limit=%g render_s=%.3f convert_s=%.3f" %
          (args.mode, args.size, cycles.time_limit, seconds, converting), flush=True)
