"""Blender peer of the drape benchmark (bench/peers/run).

    blender -b --factory-startup [-t THREADS] --python bench/peers/blender_drape.py -- N final.obj

A 2 m N x N cloth 1 m above a static sphere of radius 0.5 at the origin, simulated for 1 s with
Blender's cloth modifier (defaults except self collision, see bench/peers/README.md). Times the
bake only (not Blender's start-up or the scene build), prints one line of key=value fields
starting with `result`, and writes the final frame's evaluated cloth as a triangulated OBJ in
Y-up axes, like the other simulators' meshes.
"""
import sys
import time

import bpy

# The shared scene, in Blender's Z-up axes.
CLOTH_SIZE = 2.0
CLOTH_HEIGHT = 1.0
SPHERE_RADIUS = 0.5

# Blender's settings, as documented in the peers README.
FPS = 24
FRAMES = 24              # frame steps: 24 at 24 fps = 1 simulated second
QUALITY = 5              # solver steps per frame (the default)
SELF_DISTANCE = 0.005    # the default 0.015 makes false self contacts on a flat grid for N >= 64
SPHERE_SEGMENTS = 64
SPHERE_RINGS = 32


def parse_command_line():
    """N and the OBJ path, the arguments after `--`."""
    args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    if len(args) != 2 or not args[0].isdigit() or int(args[0]) < 2:
        sys.stderr.write("usage: blender -b --factory-startup --python blender_drape.py -- N final.obj\n")
        sys.exit(2)
    return int(args[0]), args[1]


def empty_scene():
    """The factory scene without its cube, camera and light."""
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    scene = bpy.context.scene
    scene.render.fps = FPS
    scene.render.fps_base = 1.0
    scene.use_gravity = True
    scene.gravity = (0.0, 0.0, -9.81)
    scene.frame_start = 1
    scene.frame_end = 1 + FRAMES
    scene.frame_set(1)
    return scene


def add_sphere():
    """UV sphere collider (Collision modifier defaults)."""
    bpy.ops.mesh.primitive_uv_sphere_add(segments=SPHERE_SEGMENTS, ring_count=SPHERE_RINGS,
                                         radius=SPHERE_RADIUS, location=(0.0, 0.0, 0.0))
    sphere = bpy.context.active_object
    sphere.name = "sphere"
    sphere.modifiers.new("collision", "COLLISION")
    return sphere


def add_cloth(scene, n):
    """An n x n vertex grid of quads at CLOTH_HEIGHT with a cloth modifier."""
    spacing = CLOTH_SIZE / (n - 1)
    half = CLOTH_SIZE / 2.0
    # Row-major vertices, from_pydata so the count is exactly n * n.
    vertices = [(-half + i * spacing, -half + j * spacing, 0.0) for j in range(n) for i in range(n)]
    quads = [(j * n + i, j * n + i + 1, (j + 1) * n + i + 1, (j + 1) * n + i)
             for j in range(n - 1) for i in range(n - 1)]
    mesh = bpy.data.meshes.new("cloth")
    mesh.from_pydata(vertices, [], quads)
    mesh.update()
    cloth = bpy.data.objects.new("cloth", mesh)
    cloth.location = (0.0, 0.0, CLOTH_HEIGHT)
    scene.collection.objects.link(cloth)

    modifier = cloth.modifiers.new("cloth", "CLOTH")
    modifier.settings.quality = QUALITY
    modifier.collision_settings.use_collision = True
    modifier.collision_settings.use_self_collision = True
    modifier.collision_settings.self_distance_min = SELF_DISTANCE
    modifier.point_cache.frame_start = 1
    modifier.point_cache.frame_end = 1 + FRAMES
    return cloth, modifier


def bake(scene):
    """Bakes every point cache of the scene; returns the wall seconds it took."""
    with bpy.context.temp_override(scene=scene, view_layer=bpy.context.view_layer):
        start = time.perf_counter()
        outcome = bpy.ops.ptcache.bake_all(bake=True)
        seconds = time.perf_counter() - start
    if outcome != {"FINISHED"}:
        sys.stderr.write("blender_drape: the bake did not finish: %s\n" % outcome)
        sys.exit(1)
    return seconds


def final_triangles(scene, cloth):
    """World-space Y-up vertices and triangles of the cloth at the last frame."""
    scene.frame_set(1 + FRAMES)
    depsgraph = bpy.context.evaluated_depsgraph_get()
    evaluated = cloth.evaluated_get(depsgraph)
    mesh = evaluated.to_mesh()
    to_world = evaluated.matrix_world.copy()
    # Blender (x, y, z) with Z up is (x, z, -y) with Y up: a rotation, so windings are kept.
    vertices = []
    for vertex in mesh.vertices:
        x, y, z = to_world @ vertex.co
        vertices.append((x, z, -y))
    mesh.calc_loop_triangles()
    triangles = [tuple(triangle.vertices) for triangle in mesh.loop_triangles]
    evaluated.to_mesh_clear()
    return vertices, triangles


def write_obj(path, vertices, triangles):
    with open(path, "w") as out:
        out.write("# bench/peers/blender_drape final frame, Y up\no cloth\n")
        out.writelines("v %.9g %.9g %.9g\n" % v for v in vertices)
        out.writelines("f %d %d %d\n" % (a + 1, b + 1, c + 1) for a, b, c in triangles)


def main():
    n, obj_path = parse_command_line()
    scene = empty_scene()
    add_sphere()
    cloth, modifier = add_cloth(scene, n)
    wall_s = bake(scene)

    vertices, triangles = final_triangles(scene, cloth)
    heights = [v[1] for v in vertices]
    inside_1cm = sum(1 for v in vertices if (v[0] ** 2 + v[1] ** 2 + v[2] ** 2) ** 0.5 < SPHERE_RADIUS - 0.01)
    steps = FRAMES * modifier.settings.quality
    print("result simulator=blender version=%s threads=%d N=%d vertices=%d triangles=%d steps=%d "
          "time_step=%.9g simulated_s=%.6g wall_s=%.6f ms_per_step=%.6f min_y=%.6f max_y=%.6f "
          "inside_1cm=%d baked=%d" % (
              bpy.app.version_string.split()[0], scene.render.threads, n, len(vertices), len(triangles),
              steps, 1.0 / (FPS * modifier.settings.quality), FRAMES / FPS, wall_s, 1e3 * wall_s / steps,
              min(heights), max(heights), inside_1cm, int(modifier.point_cache.is_baked)), flush=True)
    write_obj(obj_path, vertices, triangles)


main()
