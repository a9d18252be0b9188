"""The render set-up the docs pictures share: a camera aimed at a point, a sun, a light grey world, EEVEE.

Used by the ``render_blender_*.py`` scripts (run them with the ``blender`` extra). Colors are
rendered with the *Standard* view transform, so the colormap's colors come out as they are.
"""

import math

import bpy
import numpy as np


def camera_looking_at(location, target):
    """A new camera object at ``location``, linked to the scene, looking at ``target``."""
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    bpy.context.collection.objects.link(cam)
    cam.location = tuple(location)
    look = np.asarray(target, dtype=float) - np.asarray(location, dtype=float)
    cam.rotation_euler = (math.atan2(math.hypot(look[0], look[1]), -look[2]), 0.0,
                          math.atan2(look[1], look[0]) - math.pi / 2)
    bpy.context.scene.camera = cam
    return cam


def render_still(path, size, sun_degrees=(40, 10, 30)):
    """Light the scene (a sun at ``sun_degrees``, a light grey world) and render it with EEVEE to ``path``."""
    scene = bpy.context.scene
    sun = bpy.data.objects.new("sun", bpy.data.lights.new("sun", "SUN"))
    sun.data.energy = 3.0
    sun.rotation_euler = tuple(math.radians(a) for a in sun_degrees)
    bpy.context.collection.objects.link(sun)
    world = bpy.data.worlds.new("world")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.85, 0.85, 0.85, 1.0)
    scene.world = world
    scene.render.engine = "BLENDER_EEVEE"
    scene.eevee.taa_render_samples = 16
    scene.render.resolution_x, scene.render.resolution_y = size
    scene.view_settings.view_transform = "Standard"  # the colormap's colors as they are
    scene.render.image_settings.color_mode = "RGB"
    scene.render.filepath = str(path)
    bpy.ops.render.render(write_still=True)
