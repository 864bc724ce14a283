# Run by blender_test.cpp as:
#   blender -b --factory-startup --python blender_check.py -- EXR VDB OUT THRESHOLD WIDTH HEIGHT
# Opens Loom's multi-layer EXR and OpenVDB file the way a Blender user does
# and prints what Blender found, for the test to compare with Loom's values:
#   LAYERS <names>            the passes Blender's compositor Image node offers
#   LAYER <name> <file>       that pass, written by Blender's compositor as a float EXR
#   GRID <name> <data_type>   the grids of the imported volume
#   BOUNDS <min xyz> <max xyz> the mesh of Volume to Mesh at THRESHOLD (geometry nodes)
import sys

import bpy
from mathutils import Vector

exr, vdb, out, threshold, width, height = sys.argv[sys.argv.index("--") + 1:][:6]
scene = bpy.context.scene

# The EXR: a compositor Image node, each pass to a Composite node, rendered.
image = bpy.data.images.load(exr)
scene.use_nodes = True
tree = scene.node_tree
for node in list(tree.nodes):
    tree.nodes.remove(node)
source = tree.nodes.new("CompositorNodeImage")
source.image = image
composite = tree.nodes.new("CompositorNodeComposite")
print("LAYERS", " ".join(o.name for o in source.outputs))
camera = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))  # a render needs one
scene.collection.objects.link(camera)
scene.camera = camera
scene.render.engine = "CYCLES"
scene.cycles.samples = 1
scene.render.resolution_x, scene.render.resolution_y = int(width), int(height)  # the EXR's
scene.render.resolution_percentage = 100
settings = scene.render.image_settings
settings.file_format, settings.color_depth, settings.color_mode = "OPEN_EXR", "32", "RGB"
for output in source.outputs:
    if output.name == "Alpha":
        continue
    tree.links.new(output, composite.inputs["Image"])
    scene.render.filepath = f"{out}/{output.name}.exr"
    bpy.ops.render.render(write_still=True)
    print("LAYER", output.name, scene.render.filepath)

# The VDB: File > Import > OpenVDB, then Volume to Mesh in a geometry-nodes modifier.
bpy.ops.object.volume_import(filepath=vdb, directory=vdb.rsplit("/", 1)[0] + "/", files=[{"name": vdb.rsplit("/", 1)[1]}])
volume = bpy.context.selected_objects[0]
volume.data.grids.load()
for grid in volume.data.grids:
    print("GRID", grid.name, grid.data_type)
group = bpy.data.node_groups.new("to_mesh", "GeometryNodeTree")
group.inputs.new("NodeSocketGeometry", "Geometry")
group.outputs.new("NodeSocketGeometry", "Geometry")
to_mesh = group.nodes.new("GeometryNodeVolumeToMesh")
to_mesh.inputs["Threshold"].default_value = float(threshold)
group.links.new(group.nodes.new("NodeGroupInput").outputs[0], to_mesh.inputs["Volume"])
group.links.new(to_mesh.outputs["Mesh"], group.nodes.new("NodeGroupOutput").inputs[0])
volume.modifiers.new("to_mesh", "NODES").node_group = group
evaluated = volume.evaluated_get(bpy.context.evaluated_depsgraph_get())
corners = [evaluated.matrix_world @ Vector(c) for c in evaluated.bound_box]
print("BOUNDS", *[min(c[i] for c in corners) for i in range(3)], *[max(c[i] for c in corners) for i in range(3)])
