# Renders an exported Spectral Skin material (`skin export --target cycles --units m`) in Blender
# Cycles on one of two scenes, for tests/export/test_blender.cpp:
#   uniform: a thick flat slab seen from straight above under a uniform white environment of unit
#            radiance (the colour of the skin under uniform white light);
#   shadow:  the same slab under a vertical sun of angle 0, half of it (x < 0) in the sharp shadow
#            of an occluder the camera does not see; the specular lobe is switched off so that the
#            image is the light that crossed the skin.
# Usage: blender --background --factory-startup --python cycles_scene.py -- MATERIAL.py SCENE OUT.exr
#        WIDTH HEIGHT HALF_WIDTH_M SAMPLES
import importlib.util
import sys

import bpy

argv = sys.argv[sys.argv.index("--") + 1:]
material_script, scene_name, out_path = argv[0], argv[1], argv[2]
width, height, half_width, samples = int(argv[3]), int(argv[4]), float(argv[5]), int(argv[6])

bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = samples
scene.cycles.seed = 1
scene.cycles.use_denoising = False
scene.cycles.filter_width = 0.01  # point samples at pixel centres: no blur across the edge
scene.render.resolution_x, scene.render.resolution_y = width, height
scene.render.resolution_percentage = 100
scene.render.image_settings.file_format = "OPEN_EXR"
scene.render.image_settings.color_depth = "32"
scene.view_settings.view_transform = "Standard"

spec = importlib.util.spec_from_file_location("skin_material", material_script)
module = importlib.util.module_from_spec(spec)
spec.loader.exec_module(module)
material = module.make_material()

world = bpy.data.worlds.new("world")
scene.world = world
world.use_nodes = True
background = world.node_tree.nodes["Background"]

# The slab: 1 m wide, 0.2 m deep, top at z = 0.
bpy.ops.mesh.primitive_cube_add(size=1.0, location=(0.0, 0.0, -0.1))
slab = bpy.context.object
slab.scale = (1.0, 1.0, 0.2)
slab.data.materials.append(material)

if scene_name == "uniform":
    background.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    background.inputs["Strength"].default_value = 1.0
elif scene_name == "shadow":
    background.inputs["Strength"].default_value = 0.0
    bsdf = next(n for n in material.node_tree.nodes if n.type == "BSDF_PRINCIPLED")
    for name in ("Specular", "Specular IOR Level"):
        if name in bsdf.inputs:
            bsdf.inputs[name].default_value = 0.0
    sun_data = bpy.data.lights.new("sun", type="SUN")
    sun_data.energy = 3.0
    sun_data.angle = 0.0
    sun = bpy.data.objects.new("sun", sun_data)
    scene.collection.objects.link(sun)  # pointing down -z by default
    bpy.ops.mesh.primitive_plane_add(size=1.0, location=(-0.5, 0.0, 0.002))
    occluder = bpy.context.object
    occluder.visible_camera = False
    black = bpy.data.materials.new("black")  # reflects nothing back onto the slab
    black.use_nodes = True
    black.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0, 0, 0, 1)
    for name in ("Specular", "Specular IOR Level"):
        if name in black.node_tree.nodes["Principled BSDF"].inputs:
            black.node_tree.nodes["Principled BSDF"].inputs[name].default_value = 0.0
    occluder.data.materials.append(black)
else:
    raise SystemExit("unknown scene " + scene_name)

camera_data = bpy.data.cameras.new("camera")
camera_data.type = "ORTHO"
camera_data.ortho_scale = 2.0 * half_width
camera = bpy.data.objects.new("camera", camera_data)
camera.location = (0.0, 0.0, 0.5)
scene.collection.objects.link(camera)
scene.camera = camera

scene.render.filepath = out_path
bpy.ops.render.render(write_still=True)
print("spectral_skin_test: rendered", scene_name, "to", out_path)
