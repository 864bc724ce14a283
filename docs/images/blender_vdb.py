# Renders docs/images/blender-dam-break.png: frame 20 of
# graphs/mpm-dam-break-volume.json's VDB sequence, imported into Blender as a
# Volume object and rendered headless with Cycles.
#   loom run graphs/mpm-dam-break-volume.json --out out --frames 1-20
#   blender -b --factory-startup --python docs/images/blender_vdb.py -- out/water/water_0020.vdb OUT.png
import math
import sys

import bpy

vdb, png = sys.argv[sys.argv.index("--") + 1:][:2]
scene = bpy.context.scene
for obj in list(bpy.data.objects):
    bpy.data.objects.remove(obj)
bpy.ops.object.volume_import(filepath=vdb, directory=vdb.rsplit("/", 1)[0] + "/", files=[{"name": vdb.rsplit("/", 1)[1]}])
water = bpy.context.selected_objects[0]
material = bpy.data.materials.new("water")
material.use_nodes = True
nodes = material.node_tree.nodes
nodes.clear()
output = nodes.new("ShaderNodeOutputMaterial")
volume = nodes.new("ShaderNodeVolumePrincipled")
volume.inputs["Color"].default_value = (0.25, 0.5, 1.0, 1)
volume.inputs["Density"].default_value = 40.0
material.node_tree.links.new(volume.outputs[0], output.inputs["Volume"])
water.data.materials.append(material)
# The box the water moves in: a floor and the far walls of [0, 1]^3 (Blender's z is up: Loom's y).
water.rotation_euler = (math.pi / 2, 0, 0)
for location, scale in (((0.5, -0.5, 0), (0.5, 0.5, 1)), ((0.5, 0, 0.5), (0.5, 1, 0.5))):
    bpy.ops.mesh.primitive_plane_add(location=location)
    plane = bpy.context.object
    plane.scale = scale
    if location[2] > 0:
        plane.rotation_euler = (math.pi / 2, 0, 0)
bpy.ops.object.light_add(type="SUN", rotation=(0.6, 0.2, 0.8))
bpy.context.object.data.energy = 4
camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
scene.collection.objects.link(camera)
camera.location = (1.9, -2.3, 1.3)
camera.rotation_euler = (math.radians(68), 0, math.radians(38))
scene.camera = camera
scene.world = bpy.data.worlds.new("world")
scene.world.color = (0.05, 0.05, 0.06)
scene.render.engine = "CYCLES"
scene.cycles.samples = 64
scene.cycles.use_denoising = False  # Debian builds Blender without OpenImageDenoise
scene.render.resolution_x, scene.render.resolution_y = 480, 320
scene.render.filepath = png
bpy.ops.render.render(write_still=True)
