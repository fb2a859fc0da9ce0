# The Cycles side of the comparison of materials and image-based light (bench/cycles_gltf_compare.sh,
# docs/FIDELITY.md): a glTF file rendered by Blender's Cycles on the CPU from a camera meshtour wrote
# (`meshtour path --camera-frames cams.json`), lit by an equirectangular environment image alone, on a
# transparent background, as linear EXR.
#
#   blender -b --factory-startup --python cycles_gltf.py -- MODEL.gltf|glb CAMS.json FRAME ENV.exr OUT.exr \
#       [SPP] [THREADS] [WIDTH] [HEIGHT] [BOUNCES] [SEED] [ROTATION_DEG] [LAMBERT]
#
# LAMBERT 1: every material's Principled BSDF replaced by a Diffuse BSDF (roughness 0: Lambert) of
# the same base colour and normal inputs, for the light-transport-only comparison against
# meshtour's `--materials look` with the look's specular 0 (both then shade a Lambertian surface of
# the file's colours: what differs is the light, not the BRDF).
#
# Set-up, as close to meshtour's `--environment ENV --bounces B` (no lights, no ground) as Cycles allows:
# - the model through Blender's own glTF importer (Principled BSDF: base colour, metallic, roughness,
#   normal, occlusion unused by Cycles, emission, alpha); Blender 3.4's importer has no Draco: decode first;
# - the camera: meshtour's eye, target, up and vertical field of view, in Blender's Z-up frame (the
#   importer turns glTF's +Y up into +Z: (x, y, z) -> (x, -z, y));
# - the world: the image as an Environment Texture (linear colour, Cycles' default bilinear
#   interpolation, equirectangular), strength 1, turned about Z by ROTATION_DEG (the offset between
#   the two conventions, measured by compare.sh's sun test, plus meshtour's --environment-rotation);
#   importance-sampled (Cycles' automatic map);
# - light paths: BOUNCES (default 0: direct light only, meshtour's default; each of Cycles' diffuse,
#   glossy and total bounces set to it), transparency bounces 8, no caustic filter, clamping off;
# - 1280x720 or the size given, SPP samples, no adaptive sampling, no denoiser, Blackman-Harris 1.5 px
#   (Cycles' default, meshtour's filter), seed SEED.
# Prints "cycles: S seconds" (the render alone).
import json
import math
import os
import sys
import time

import bpy
from mathutils import Matrix, Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import cycles_settings  # noqa: E402 (beside this script)

argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
if len(argv) < 5:
    sys.exit("usage: blender -b --factory-startup --python cycles_gltf.py -- MODEL CAMS.json FRAME ENV.exr OUT.exr "
             "[SPP] [THREADS] [WIDTH] [HEIGHT] [BOUNCES] [SEED] [ROTATION_DEG]")
model_path, cams_path, frame, env_path, out_path = argv[0], argv[1], int(argv[2]), argv[3], argv[4]
spp = int(argv[5]) if len(argv) > 5 else 256
threads = int(argv[6]) if len(argv) > 6 else 2
width = int(argv[7]) if len(argv) > 7 else 1280
height = int(argv[8]) if len(argv) > 8 else 720
bounces = int(argv[9]) if len(argv) > 9 else 0
seed = int(argv[10]) if len(argv) > 10 else 0
rotation = float(argv[11]) if len(argv) > 11 else 0.0
lambert = len(argv) > 12 and argv[12] == "1"

# Blender 3.4's glTF importer calls numpy.bool, which Debian 12's numpy (1.24) no longer has: the
# alias it stood for, put back for the importer (it needs python3-numpy).
import numpy

if not hasattr(numpy, "bool"):
    numpy.bool = bool

bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=model_path)

if lambert:
    for material in bpy.data.materials:
        if not material.use_nodes:
            continue
        tree = material.node_tree
        for principled in [n for n in tree.nodes if n.type == "BSDF_PRINCIPLED"]:
            diffuse = tree.nodes.new("ShaderNodeBsdfDiffuse")
            diffuse.inputs["Roughness"].default_value = 0.0
            diffuse.inputs["Color"].default_value = principled.inputs["Base Color"].default_value
            for name, target in (("Base Color", "Color"), ("Normal", "Normal")):
                for link in list(principled.inputs[name].links):
                    tree.links.new(link.from_socket, diffuse.inputs[target])
            for link in list(principled.outputs["BSDF"].links):
                tree.links.new(diffuse.outputs["BSDF"], link.to_socket)
            tree.nodes.remove(principled)

with open(cams_path) as f:
    cams = json.load(f)
cam = next((c for c in cams if c["frame"] == frame), None)
if cam is None:
    sys.exit(f"{cams_path} has no frame {frame}")


def blender_axes(v):
    return Vector((v[0], -v[2], v[1]))


eye, target, up = blender_axes(cam["eye"]), blender_axes(cam["target"]), blender_axes(cam["up"])
camera_data = bpy.data.cameras.new("meshtour")
camera_data.sensor_fit = "VERTICAL"
camera_data.angle = math.radians(cam["vertical_fov_deg"])
camera_data.clip_start = 0.001 * (eye - target).length
camera_data.clip_end = 1000.0 * (eye - target).length
camera = bpy.data.objects.new("meshtour", camera_data)
bpy.context.scene.collection.objects.link(camera)
# A camera looks along its -Z with +Y up.
back = (eye - target).normalized()
right = up.cross(back).normalized()
true_up = back.cross(right)
camera.matrix_world = Matrix(((right.x, true_up.x, back.x, eye.x), (right.y, true_up.y, back.y, eye.y),
                              (right.z, true_up.z, back.z, eye.z), (0, 0, 0, 1)))

scene = bpy.context.scene
scene.camera = camera
world = bpy.data.worlds.new("environment")
scene.world = world
world.use_nodes = True
nodes, links = world.node_tree.nodes, world.node_tree.links
nodes.clear()
coords = nodes.new("ShaderNodeTexCoord")
mapping = nodes.new("ShaderNodeMapping")
mapping.inputs["Rotation"].default_value = (0.0, 0.0, math.radians(rotation))
texture = nodes.new("ShaderNodeTexEnvironment")
texture.image = bpy.data.images.load(env_path)
texture.image.colorspace_settings.name = "Linear"
background = nodes.new("ShaderNodeBackground")
background.inputs["Strength"].default_value = 1.0
output = nodes.new("ShaderNodeOutputWorld")
links.new(coords.outputs["Generated"], mapping.inputs["Vector"])
links.new(mapping.outputs["Vector"], texture.inputs["Vector"])
links.new(texture.outputs["Color"], background.inputs["Color"])
links.new(background.outputs["Background"], output.inputs["Surface"])

cycles_settings.apply(scene, spp, seed, threads, width, height, transparent=True)
scene.cycles.max_bounces = bounces
scene.cycles.diffuse_bounces = bounces
scene.cycles.glossy_bounces = bounces
scene.cycles.transmission_bounces = bounces
scene.cycles.volume_bounces = 0
scene.cycles.transparent_max_bounces = 8
scene.cycles.sample_clamp_direct = 0.0
scene.cycles.sample_clamp_indirect = 0.0
scene.cycles.blur_glossy = 0.0
scene.cycles.caustics_reflective = True
scene.cycles.caustics_refractive = True
scene.cycles.filter_width = 1.5
scene.world.cycles.sampling_method = "AUTOMATIC"
scene.render.image_settings.color_mode = "RGBA"
scene.render.filepath = out_path
scene.view_settings.look = "None"
scene.view_settings.exposure = 0.0

start = time.perf_counter()
bpy.ops.render.render(write_still=True)
print(f"cycles: {time.perf_counter() - start:.3f} seconds")
