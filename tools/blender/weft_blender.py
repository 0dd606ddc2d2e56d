"""Builds a Blender scene from a Weft recording and renders it with Cycles.

Run headless:

    blender -b --python tools/blender/weft_blender.py -- DIR [options]

DIR is the output folder of `weft --headless ... --out DIR`. The script reads DIR/recording.json,
makes one mesh per cloth from its rest OBJ with a Mesh Cache modifier on its PC2 point cache (or,
for an OBJ-sequence recording, the mesh of the frame rendered), the colliders (animated from
DIR/colliders.csv), a camera framing everything, lights, a floor and materials, then renders.
docs/blender.md describes the options.
"""

import argparse
import csv
import json
import math
import os
import struct
import sys

import bpy
from mathutils import Quaternion, Vector


def parse_arguments():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    parser = argparse.ArgumentParser(prog="weft_blender.py", description="Render a Weft recording with Cycles")
    parser.add_argument("dir", help="recording folder (has recording.json)")
    parser.add_argument("--frame", type=int, default=None, help="render this frame only (default: the last)")
    parser.add_argument("--animation", action="store_true", help="render every frame")
    parser.add_argument("--output", default=None,
                        help="PNG path for --frame (default DIR/render/frame_NNNN.png); for --animation a "
                             "prefix (default DIR/render/frame_)")
    parser.add_argument("--samples", type=int, default=32, help="Cycles samples per pixel")
    parser.add_argument("--resolution", type=int, nargs=2, default=[960, 540], metavar=("W", "H"))
    parser.add_argument("--save", default=None, help="also save the scene as this .blend file")
    parser.add_argument("--no-render", action="store_true", help="build (and --save) the scene only")
    parser.add_argument("--check", action="store_true",
                        help="verify that the deformed meshes match the point caches at the rendered frame "
                             "and that the image is not blank; exit 1 if not")
    return parser.parse_args(argv)


def fail(message):
    print("weft_blender: error: " + message, file=sys.stderr)
    sys.exit(1)


# --- Reading Weft's files ---------------------------------------------------------------------

def read_obj(path):
    """Vertices, faces and per-corner texture coordinates of every object in an OBJ file, as
    objects in file order: [(name, vertices, faces, face_uvs)]. Vertex order is kept, which the
    point cache relies on."""
    objects = []
    positions, texcoords = [], []
    current = None
    with open(path) as obj:
        for line in obj:
            fields = line.split()
            if not fields:
                continue
            if fields[0] == "o":
                current = {"name": " ".join(fields[1:]), "first": len(positions), "faces": [], "uvs": []}
                objects.append(current)
            elif fields[0] == "v":
                positions.append(tuple(float(c) for c in fields[1:4]))
            elif fields[0] == "vt":
                texcoords.append((float(fields[1]), float(fields[2])))
            elif fields[0] == "f":
                if current is None:
                    current = {"name": os.path.basename(path), "first": 0, "faces": [], "uvs": []}
                    objects.append(current)
                corners = [corner.split("/") for corner in fields[1:]]
                current["faces"].append([int(c[0]) - 1 for c in corners])
                if all(len(c) > 1 and c[1] for c in corners):
                    current["uvs"].append([texcoords[int(c[1]) - 1] for c in corners])
    result = []
    for index, entry in enumerate(objects):
        end = objects[index + 1]["first"] if index + 1 < len(objects) else len(positions)
        first = entry["first"]
        faces = [[v - first for v in face] for face in entry["faces"]]
        result.append((entry["name"], positions[first:end], faces,
                       entry["uvs"] if len(entry["uvs"]) == len(faces) else None))
    return result


def read_pc2_sample(path, frame):
    """One sample of a PC2 file as a list of (x, y, z), clamped to the samples it has."""
    with open(path, "rb") as cache:
        header = cache.read(32)
        if len(header) != 32 or header[:12] != b"POINTCACHE2\0":
            fail(path + ": not a PC2 point cache")
        _, points, _, _, samples = struct.unpack("<iiffi", header[12:])
        frame = max(0, min(frame, samples - 1))
        cache.seek(32 + 12 * points * frame)
        data = struct.unpack("<%df" % (3 * points), cache.read(12 * points))
        return [data[3 * i:3 * i + 3] for i in range(points)], samples


def read_collider_rows(path):
    """{collider name: [(frame, location, quaternion wxyz)]} from colliders.csv."""
    rows = {}
    if not os.path.exists(path):
        return rows
    with open(path, newline="") as table:
        for row in csv.DictReader(table):
            rows.setdefault(row["collider"], []).append(
                (int(row["frame"]), tuple(float(row[k]) for k in ("x", "y", "z")),
                 tuple(float(row[k]) for k in ("qw", "qx", "qy", "qz"))))
    return rows


# --- Building the scene -----------------------------------------------------------------------

def make_material(name, colour, roughness, sheen=0.0):
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    bsdf = material.node_tree.nodes.get("Principled BSDF")
    bsdf.inputs["Base Color"].default_value = (*colour, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    if sheen > 0.0 and "Sheen" in bsdf.inputs:
        bsdf.inputs["Sheen"].default_value = sheen
    return material


def make_mesh_object(name, vertices, faces, uvs, material, parent):
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(vertices, [], faces)
    if uvs is not None:
        layer = mesh.uv_layers.new(name="UVMap")
        corner = 0
        for face_uvs in uvs:
            for uv in face_uvs:
                layer.data[corner].uv = uv
                corner += 1
    mesh.update()
    for polygon in mesh.polygons:
        polygon.use_smooth = True
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    obj.parent = parent
    obj.data.materials.append(material)
    return obj


def add_collider(spec, rows, material, parent):
    kind = spec["type"]
    if kind == "sphere":
        bpy.ops.mesh.primitive_uv_sphere_add(segments=96, ring_count=48, radius=spec["radius"])
        obj = bpy.context.active_object
        bpy.ops.object.shade_smooth()
    elif kind == "box":
        bpy.ops.mesh.primitive_cube_add(size=2.0)
        obj = bpy.context.active_object
        obj.scale = Vector(spec["half_extents"])
    elif kind == "plane":
        bpy.ops.mesh.primitive_plane_add(size=40.0)
        obj = bpy.context.active_object
        # The primitive faces +Z; turn it to the plane's normal (in Weft's frame).
        obj.rotation_mode = "QUATERNION"
        obj.rotation_quaternion = Vector((0.0, 0.0, 1.0)).rotation_difference(Vector(spec["normal"]))
    elif "vertices" in spec:
        # Capsules, cylinders and OBJ meshes come as the triangles Weft collides with.
        obj = make_mesh_object("collider_" + spec["name"], [tuple(v) for v in spec["vertices"]],
                               [tuple(t) for t in spec["triangles"]], None, material, parent)
        material = None  # make_mesh_object assigned it
    else:
        print("weft_blender: collider type %r is not drawn" % kind, file=sys.stderr)
        return None
    obj.name = "collider_" + spec["name"]
    obj.parent = parent
    if material is not None:
        obj.data.materials.append(material)
    base_rotation = obj.rotation_quaternion.copy() if obj.rotation_mode == "QUATERNION" else None
    obj.rotation_mode = "QUATERNION"
    if base_rotation is None:
        base_rotation = obj.rotation_quaternion.copy()
    for frame, location, quaternion in rows.get(spec["name"], []):
        obj.location = location
        obj.rotation_quaternion = Quaternion(quaternion) @ base_rotation
        obj.keyframe_insert("location", frame=frame)
        obj.keyframe_insert("rotation_quaternion", frame=frame)
    return obj


def world_bounds(objects):
    low = Vector((math.inf,) * 3)
    high = Vector((-math.inf,) * 3)
    for obj in objects:
        for corner in obj.bound_box:
            point = obj.matrix_world @ Vector(corner)
            low = Vector(map(min, low, point))
            high = Vector(map(max, high, point))
    return low, high


def build_scene(args, manifest, frame):
    directory = os.path.abspath(args.dir)
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.fps = max(1, int(round(manifest["fps"])))
    scene.frame_start = 0
    scene.frame_end = manifest["frames"]

    # Weft's +Y up becomes Blender's +Z up: everything hangs under an empty turned 90 degrees about X.
    root = bpy.data.objects.new("weft_world", None)
    scene.collection.objects.link(root)
    root.rotation_euler = (math.pi / 2.0, 0.0, 0.0)
    bpy.context.view_layer.update()

    cloth_material = make_material("weft_cloth", (0.72, 0.16, 0.12), 0.75, sheen=0.6)
    collider_material = make_material("weft_collider", (0.55, 0.57, 0.6), 0.35)
    floor_material = make_material("weft_floor", (0.3, 0.3, 0.32), 0.9)

    cloths = []
    for entry in manifest["cloths"]:
        if entry.get("point_cache"):
            name, vertices, faces, uvs = read_obj(os.path.join(directory, entry["rest_mesh"]))[0]
            obj = make_mesh_object(entry["name"], vertices, faces, uvs, cloth_material, root)
            cache = obj.modifiers.new("weft_point_cache", "MESH_CACHE")
            cache.cache_format = "PC2"
            cache.filepath = os.path.join(directory, entry["point_cache"])
            cache.time_mode = "FRAME"
            cache.play_mode = "SCENE"
            cache.frame_start = 0.0
            cache.frame_scale = 1.0
            cache.interpolation = "NONE"
            cache.deform_mode = "OVERWRITE"
            cloths.append((obj, entry))
    if not cloths and manifest.get("frame_files"):
        # An OBJ-sequence recording: the meshes of the frame rendered.
        digits = len(manifest["frame_files"]) - len("frame_.obj")
        path = os.path.join(directory, "frame_%0*d.obj" % (digits, frame))
        if not os.path.exists(path):
            fail(path + ": no such frame file")
        for name, vertices, faces, uvs in read_obj(path):
            cloths.append((make_mesh_object(name, vertices, faces, uvs, cloth_material, root), None))
    if not cloths:
        fail(os.path.join(directory, "recording.json") + ": no cloths to show")
    for obj, _ in cloths:
        solidify = obj.modifiers.new("weft_thickness", "SOLIDIFY")
        solidify.thickness = 0.004
        solidify.offset = 0.0

    rows = read_collider_rows(os.path.join(directory, manifest.get("collider_transforms", "colliders.csv")))
    colliders = [c for c in (add_collider(spec, rows, collider_material, root) for spec in manifest["colliders"]) if c]

    scene.frame_set(frame)
    bpy.context.view_layer.update()
    low, high = world_bounds([obj for obj, _ in cloths] + [c for c in colliders if "plane" not in c.name])
    centre = (low + high) / 2.0
    size = max((high - low).length, 0.5)

    # A floor under everything unless a plane collider is there already.
    if not any(spec["type"] == "plane" for spec in manifest["colliders"]):
        bpy.ops.mesh.primitive_plane_add(size=size * 20.0, location=(centre.x, centre.y, low.z - 0.002))
        bpy.context.active_object.name = "floor"
        bpy.context.active_object.data.materials.append(floor_material)

    # Camera in front (Weft's +Z is Blender's -Y) and above, aimed at the centre.
    target = bpy.data.objects.new("camera_target", None)
    scene.collection.objects.link(target)
    target.location = centre
    camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    scene.collection.objects.link(camera)
    camera.data.lens = 40.0
    camera.location = centre + Vector((0.5, -1.2, 0.7)) * size * 1.05
    aim = camera.constraints.new("TRACK_TO")
    aim.target = target
    aim.track_axis = "TRACK_NEGATIVE_Z"
    aim.up_axis = "UP_Y"
    scene.camera = camera

    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    scene.collection.objects.link(sun)
    sun.data.energy = 2.0
    sun.data.angle = math.radians(8.0)
    sun.rotation_euler = (math.radians(40.0), math.radians(15.0), math.radians(30.0))
    fill = bpy.data.objects.new("fill", bpy.data.lights.new("fill", "AREA"))
    scene.collection.objects.link(fill)
    fill.data.energy = 25.0 * size * size
    fill.data.size = size
    fill.location = centre + Vector((-1.2, -0.8, 1.0)) * size
    fill_aim = fill.constraints.new("TRACK_TO")
    fill_aim.target = target
    fill_aim.track_axis = "TRACK_NEGATIVE_Z"
    fill_aim.up_axis = "UP_Y"

    world = bpy.data.worlds.new("weft_world")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.02, 0.025, 0.035, 1.0)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 1.0
    scene.world = world

    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = args.samples
    scene.cycles.use_denoising = False
    scene.render.resolution_x, scene.render.resolution_y = args.resolution
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "PNG"
    return cloths


def check_caches(directory, cloths, frame):
    """The evaluated (deformed) mesh of each cached cloth against its PC2 sample at `frame`."""
    depsgraph = bpy.context.evaluated_depsgraph_get()
    worst = 0.0
    for obj, entry in cloths:
        if entry is None:
            continue
        expected, _ = read_pc2_sample(os.path.join(directory, entry["point_cache"]), frame)
        # The check reads the cache modifier's output: turn thickness off for it.
        obj.modifiers["weft_thickness"].show_viewport = False
        depsgraph.update()
        evaluated = obj.evaluated_get(depsgraph)
        mesh = evaluated.to_mesh()
        if len(mesh.vertices) != len(expected):
            fail("%s: %d vertices after the cache modifier, the cache has %d" % (obj.name, len(mesh.vertices), len(expected)))
        for vertex, point in zip(mesh.vertices, expected):
            worst = max(worst, (vertex.co - Vector(point)).length)
        evaluated.to_mesh_clear()
        obj.modifiers["weft_thickness"].show_viewport = True
        rest = obj.data.vertices
        moved = max((v.co - Vector(p)).length for v, p in zip(rest, expected))
        print("weft_blender: %s at frame %d: largest distance to the cache %.3g m (the rest mesh is %.3g m away)"
              % (obj.name, frame, worst, moved))
    if worst > 1e-5:
        fail("the deformed mesh differs from the point cache by %.3g m" % worst)


def check_image(path):
    image = bpy.data.images.load(path)
    pixels = list(image.pixels)
    luminance = [0.2126 * pixels[i] + 0.7152 * pixels[i + 1] + 0.0722 * pixels[i + 2] for i in range(0, len(pixels), 4)]
    mean = sum(luminance) / len(luminance)
    spread = math.sqrt(sum((l - mean) ** 2 for l in luminance) / len(luminance))
    reddish = sum(1 for i in range(0, len(pixels), 4) if pixels[i] > 1.5 * pixels[i + 1] + 0.02) / (len(pixels) / 4)
    print("weft_blender: %s: %dx%d, mean luminance %.3f, spread %.3f, cloth-coloured pixels %.1f%%"
          % (path, image.size[0], image.size[1], mean, spread, 100.0 * reddish))
    if spread < 0.02 or reddish < 0.005:
        fail(path + ": the render looks blank (no contrast or no cloth)")


def main():
    args = parse_arguments()
    directory = os.path.abspath(args.dir)
    manifest_path = os.path.join(directory, "recording.json")
    if not os.path.exists(manifest_path):
        fail(manifest_path + ": not found; expected the folder of a `weft --headless` run")
    with open(manifest_path) as manifest_file:
        manifest = json.load(manifest_file)
    if manifest.get("format") != "weft-recording" or manifest.get("version") != 1:
        fail(manifest_path + ": format/version: expected \"weft-recording\" version 1")

    # Frames actually recorded (a run still going or stopped early has fewer than asked).
    recorded = manifest["frames"]
    for entry in manifest["cloths"]:
        if entry.get("point_cache"):
            recorded = min(recorded, read_pc2_sample(os.path.join(directory, entry["point_cache"]), 0)[1] - 1)
    frame = recorded if args.frame is None else args.frame
    if frame < 0 or frame > recorded:
        fail("--frame %d: expected a frame in 0..%d (the frames recorded)" % (frame, recorded))

    cloths = build_scene(args, manifest, frame)
    bpy.context.scene.frame_end = recorded
    if args.check:
        check_caches(directory, cloths, frame)
    if args.save:
        bpy.ops.wm.save_as_mainfile(filepath=os.path.abspath(args.save))
        print("weft_blender: saved " + os.path.abspath(args.save))
    if args.no_render:
        return
    scene = bpy.context.scene
    if args.animation:
        scene.render.filepath = args.output or os.path.join(directory, "render", "frame_")
        bpy.ops.render.render(animation=True)
        print("weft_blender: rendered frames 0..%d to %s####.png" % (recorded, scene.render.filepath))
        return
    output = os.path.abspath(args.output or os.path.join(directory, "render", "frame_%04d.png" % frame))
    os.makedirs(os.path.dirname(output), exist_ok=True)
    scene.frame_set(frame)
    scene.render.filepath = output
    bpy.ops.render.render(write_still=True)
    print("weft_blender: rendered frame %d to %s" % (frame, output))
    if args.check:
        check_image(output)


try:
    main()
except SystemExit:
    raise
except Exception as error:  # Blender keeps running after a script error: exit non-zero instead
    import traceback
    traceback.print_exc()
    fail(str(error))
