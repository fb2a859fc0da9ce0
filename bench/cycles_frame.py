# The Cycles side of the speed comparison (docs/PERFORMANCE.md): the bunny's frame of
# bench/tracer_bench.cpp (1280x720, 16 spp, the studio look's three lights, sky and ground) rendered by
# Blender's Cycles on the CPU, render time only (the scene's set-up and the file's loading are not
# timed), with Cycles' default light paths and no denoiser.
#
#   blender -b --factory-startup --python bench/cycles_frame.py -- MESH.ply OUT.exr [SPP] [THREADS] [WIDTH] [HEIGHT] [GROUND] [SEED]
#
# GROUND: catcher (default: a shadow catcher, as meshtour's ground catches the model's shadows) or
# none (the model on the world alone: less work for Cycles than meshtour's frame, the conservative
# comparison). SEED: Cycles' sampling seed (default 0); a converged reference takes another seed
# than the frames measured against it, or their first samples would be the reference's too and
# their error would read low (bench/cycles_equal_error.sh).
#
# Prints "cycles: S seconds" (the render alone). OUT.exr is the linear beauty, for the error against
# a converged reference (the same command at 4096 spp).
#
# The scene follows the studio look (tracer/look.cpp) as closely as Cycles' nodes allow: three
# sun lamps of the look's directions (camera space there, turned into world space here), colours,
# irradiances and angular diameters; a uniform world of the look's ambient colour; the model a
# diffuse + glossy (GGX) surface of the look's grey; the ground a shadow catcher. The camera is
# tracer_bench's: 18 degrees above the bunny's centre, a 35-degree vertical field of view, the
# whole model in frame. Same work, not the same picture: Cycles bounces light, meshtour does not.
import math
import os
import sys
import time

import bpy

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cycles_settings  # noqa: E402 (beside this script)
from mathutils import Vector

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
if len(argv) < 2:
    sys.exit("usage: blender -b --factory-startup --python cycles_frame.py -- MESH.ply OUT.exr [SPP] [THREADS] [WIDTH] [HEIGHT] [GROUND] [SEED]")
mesh_path, out_path = argv[0], argv[1]
spp = int(argv[2]) if len(argv) > 2 else 16
threads = int(argv[3]) if len(argv) > 3 else 2
width = int(argv[4]) if len(argv) > 4 else 1280
height = int(argv[5]) if len(argv) > 5 else 720
ground_mode = argv[6] if len(argv) > 6 else "catcher"
if ground_mode not in ("catcher", "none"):
    sys.exit("GROUND must be catcher or none")
seed = int(argv[7]) if len(argv) > 7 else 0

bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_mesh.ply(filepath=mesh_path)
model = bpy.context.selected_objects[0]
# PLY's Y up against Blender's Z up: the importer keeps the file's axes, so stand the bunny up.
model.rotation_euler = (math.radians(90.0), 0.0, 0.0)
bpy.context.view_layer.update()
corners = [model.matrix_world @ Vector(c) for c in model.bound_box]
lo = Vector((min(c.x for c in corners), min(c.y for c in corners), min(c.z for c in corners)))
hi = Vector((max(c.x for c in corners), max(c.y for c in corners), max(c.z for c in corners)))
centre, diagonal = (lo + hi) / 2, (hi - lo).length

scene = bpy.context.scene
cycles_settings.apply(scene, spp, seed, threads, width, height, transparent=False)

# The camera: tracer_bench's (Y up there; Z up here).
fov = math.radians(35.0)
elevation = math.radians(18.0)
distance = 0.55 * diagonal / math.tan(fov / 2)
camera_data = bpy.data.cameras.new("camera")
camera_data.sensor_fit = "VERTICAL"
camera_data.angle_y = fov
camera = bpy.data.objects.new("camera", camera_data)
scene.collection.objects.link(camera)
camera.location = centre + distance * Vector((0.0, -math.cos(elevation), math.sin(elevation)))
forward = (centre - camera.location).normalized()
camera.rotation_euler = forward.to_track_quat("-Z", "Y").to_euler()
scene.camera = camera
bpy.context.view_layer.update()
right = camera.matrix_world.to_3x3() @ Vector((1, 0, 0))
up = camera.matrix_world.to_3x3() @ Vector((0, 1, 0))
towards_viewer = -forward

# The studio look's lights (tracer/look.cpp): direction from the camera's frame, colour, irradiance,
# angular diameter.
for name, d, colour, strength, diameter in [
    ("key", (-0.55, 0.85, 0.6), (1.0, 0.96, 0.90), 1.15, 22.0),
    ("fill", (0.85, 0.15, 0.55), (0.90, 0.95, 1.0), 0.3, 45.0),
    ("rim", (0.2, 1.3, -0.7), (1.0, 1.0, 1.0), 0.6, 15.0),
]:
    towards_light = (d[0] * right + d[1] * up + d[2] * towards_viewer).normalized()
    lamp = bpy.data.lights.new(name, "SUN")
    lamp.color = colour
    lamp.energy = strength * math.pi  # Cycles' sun strength is irradiance in W/m^2; meshtour's lights are radiometric (albedo * E / pi)
    lamp.angle = math.radians(diameter)
    obj = bpy.data.objects.new(name, lamp)
    obj.rotation_euler = (-towards_light).to_track_quat("-Z", "Y").to_euler()
    scene.collection.objects.link(obj)

world = bpy.data.worlds.new("sky")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.22, 0.23, 0.25, 1.0)
scene.world = world

material = bpy.data.materials.new("clay")
material.use_nodes = True
bsdf = material.node_tree.nodes["Principled BSDF"]
bsdf.inputs["Base Color"].default_value = (0.75, 0.75, 0.75, 1.0)
bsdf.inputs["Roughness"].default_value = 0.45
bsdf.inputs["Specular"].default_value = 0.5
model.data.materials.clear()
model.data.materials.append(material)
for polygon in model.data.polygons:
    polygon.use_smooth = True

if ground_mode == "catcher":
    bpy.ops.mesh.primitive_plane_add(size=200.0 * diagonal, location=(centre.x, centre.y, lo.z - 5e-4 * diagonal))
    bpy.context.active_object.is_shadow_catcher = True

scene.render.filepath = out_path
start = time.perf_counter()
bpy.ops.render.render(write_still=False)
seconds = time.perf_counter() - start
bpy.data.images["Render Result"].save_render(out_path)
print(f"cycles: {seconds:.3f} seconds ({width}x{height}, {spp} spp, {threads} threads, ground: {ground_mode}, seed {seed})")
