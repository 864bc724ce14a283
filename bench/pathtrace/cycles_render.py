# Renders a scene written by bench_pathtrace (scene.json: triangle meshes with
# a Lambert colour and a one-sided emission, a uniform sky, a pinhole camera)
# with Blender's Cycles on the CPU, once per sample count, and writes each
# image as a linear PFM and the render times as JSON lines.
#
#   blender -b --factory-startup -P cycles_render.py -- scene.json OUT_DIR
#
# Conventions matched to Loom's PathTrace (verified by bench_pathtrace's
# `cycles` mode, which compares the converged images):
#   emission shader strength 1 with colour Le = radiance Le (front side only:
#   Loom's emitters are one-sided), Diffuse BSDF with roughness 0 = Lambert,
#   camera angle_y = vertical field of view, max_bounces = max_depth - 1 (and
#   the per-kind limits as high), a 1-pixel box filter, linear 32-bit EXR with
#   the Standard view transform; no clamping, denoising, adaptive sampling,
#   light threshold, glossy filter or path guiding.
import json
import os
import sys
import time

import bpy
import numpy as np
from mathutils import Matrix, Vector


def settings(scene, spec):
    scene.render.engine = 'CYCLES'
    c = scene.cycles
    c.device = 'CPU'
    c.use_adaptive_sampling = False
    c.use_denoising = False
    c.sample_clamp_direct = 0.0
    c.sample_clamp_indirect = 0.0
    c.light_sampling_threshold = 0.0
    c.blur_glossy = 0.0
    if hasattr(c, 'use_guiding'):
        c.use_guiding = False
    bounces = spec['max_depth'] - 1
    c.max_bounces = bounces
    for kind in ('diffuse_bounces', 'glossy_bounces', 'transmission_bounces', 'transparent_max_bounces'):
        setattr(c, kind, bounces)
    c.min_light_bounces = 0
    c.caustics_reflective = True
    c.caustics_refractive = True
    c.pixel_filter_type = 'BOX'
    c.filter_width = 1.0
    c.seed = spec.get('seed', 1)
    r = scene.render
    r.resolution_x, r.resolution_y = spec['width'], spec['height']
    r.resolution_percentage = 100
    r.threads_mode = 'FIXED'
    r.threads = spec['threads']
    r.use_persistent_data = True
    r.film_transparent = False
    r.image_settings.file_format = 'OPEN_EXR'
    r.image_settings.color_depth = '32'
    r.image_settings.exr_codec = 'NONE'
    v = scene.view_settings
    v.view_transform = 'Standard'
    v.look = 'None'
    v.exposure = 0.0
    v.gamma = 1.0
    scene.display_settings.display_device = 'sRGB'
    scene.sequencer_colorspace_settings.name = 'Linear'


def material(name, color, emission):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    nodes, links = m.node_tree.nodes, m.node_tree.links
    nodes.clear()
    out = nodes.new('ShaderNodeOutputMaterial')
    diffuse = nodes.new('ShaderNodeBsdfDiffuse')
    diffuse.inputs['Color'].default_value = (*color, 1.0)
    diffuse.inputs['Roughness'].default_value = 0.0
    if max(emission) <= 0:
        links.new(diffuse.outputs['BSDF'], out.inputs['Surface'])
        return m
    # Emission on the front side only: strength = 1 - backfacing.
    geometry = nodes.new('ShaderNodeNewGeometry')
    front = nodes.new('ShaderNodeMath')
    front.operation = 'SUBTRACT'
    front.inputs[0].default_value = 1.0
    links.new(geometry.outputs['Backfacing'], front.inputs[1])
    emit = nodes.new('ShaderNodeEmission')
    emit.inputs['Color'].default_value = (*emission, 1.0)
    links.new(front.outputs['Value'], emit.inputs['Strength'])
    add = nodes.new('ShaderNodeAddShader')
    links.new(diffuse.outputs['BSDF'], add.inputs[0])
    links.new(emit.outputs['Emission'], add.inputs[1])
    links.new(add.outputs['Shader'], out.inputs['Surface'])
    return m


def build(scene, spec):
    for i, o in enumerate(spec['objects']):
        mesh = bpy.data.meshes.new(o['name'])
        mesh.from_pydata([tuple(p) for p in o['vertices']], [], [tuple(f) for f in o['faces']])
        mesh.update()
        obj = bpy.data.objects.new(o['name'], mesh)
        obj.data.materials.append(material('m%d' % i, o['color'], o['emission']))
        scene.collection.objects.link(obj)
    world = bpy.data.worlds.new('sky')
    world.use_nodes = True
    bg = world.node_tree.nodes['Background']
    bg.inputs['Color'].default_value = (*spec['sky'], 1.0)
    bg.inputs['Strength'].default_value = 1.0
    scene.world = world
    cam = spec['camera']
    data = bpy.data.cameras.new('camera')
    data.sensor_fit = 'VERTICAL'
    data.angle_y = cam['fov_y']
    data.clip_start = cam.get('near', 0.01)
    data.clip_end = cam.get('far', 1e6)
    eye, target, up = Vector(cam['eye']), Vector(cam['target']), Vector(cam['up'])
    forward = (target - eye).normalized()
    right = forward.cross(up).normalized()
    true_up = right.cross(forward)
    m = Matrix.Identity(4)
    for row in range(3):
        m[row][0], m[row][1], m[row][2], m[row][3] = right[row], true_up[row], -forward[row], eye[row]
    obj = bpy.data.objects.new('camera', data)
    obj.matrix_world = m
    scene.collection.objects.link(obj)
    scene.camera = obj


def write_pfm(path, rgba, width, height):
    rgb = np.ascontiguousarray(rgba.reshape(height, width, 4)[:, :, :3], dtype='<f4')  # bottom row first, as PFM
    with open(path + '.tmp', 'wb') as f:
        f.write(b'PF\n%d %d\n-1.0\n' % (width, height))
        f.write(rgb.tobytes())

    os.replace(path + '.tmp', path)


def main():
    argv = sys.argv[sys.argv.index('--') + 1:]
    spec = json.load(open(argv[0]))
    out_dir = argv[1]
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    settings(scene, spec)
    build(scene, spec)
    with open(out_dir + '/times.jsonl', 'w') as log:
        for index, spp in enumerate(spec['spp']):
            scene.cycles.samples = spp
            start = time.perf_counter()
            bpy.ops.render.render(write_still=False)
            seconds = time.perf_counter() - start
            exr = '%s/cycles_%d.exr' % (out_dir, index)
            bpy.data.images['Render Result'].save_render(exr, scene=scene)
            image = bpy.data.images.load(exr)
            pixels = np.empty(len(image.pixels), dtype=np.float32)
            image.pixels.foreach_get(pixels)
            write_pfm('%s/cycles_%d.pfm' % (out_dir, index), pixels, spec['width'], spec['height'])
            bpy.data.images.remove(image)
            log.write(json.dumps({'index': index, 'spp': spp, 'seconds': seconds,
                                  'sampling_pattern': scene.cycles.sampling_pattern}) + '\n')
            log.flush()


main()
