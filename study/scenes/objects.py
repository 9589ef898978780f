# SPDX-License-Identifier: MIT
"""The study scenes' objects: the world's colour, planes, walls, rods, spheres, the monkey, boxes
and hair-like strands, each with its material, scale applied (object coordinates in metres)."""

import math

import bpy


def set_world(scene, color, strength=1.0):
    world = bpy.data.worlds.new("World")
    scene.world = world
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = tuple(color) + (1.0,)
    bg.inputs["Strength"].default_value = strength


def _finish(obj, name, mat, smooth=False, apply_scale=False):
    obj.name = name
    if mat is not None:
        obj.data.materials.append(mat)
    if smooth:
        bpy.ops.object.shade_smooth()
    if apply_scale:
        bpy.ops.object.transform_apply(location=False, rotation=False, scale=True)
    return obj


def plane(name, mat, size, location, rotation=(0.0, 0.0, 0.0)):
    """A plane of size (sx, sy) metres; rotation in degrees. Scale applied, so object
    coordinates are metres."""
    bpy.ops.mesh.primitive_plane_add(size=1.0, location=location,
                                     rotation=tuple(math.radians(a) for a in rotation))
    obj = bpy.context.active_object
    obj.scale = (size[0], size[1], 1.0)
    return _finish(obj, name, mat, apply_scale=True)


def wall(name, mat, size, y, z_center, x_center=0.0):
    """A vertical plane facing the camera (normal -Y) at distance y."""
    return plane(name, mat, size, (x_center, y, z_center), (90.0, 0.0, 0.0))


def rod(name, mat, p0, p1, radius, vertices=24):
    """A cylinder from point p0 to p1."""
    d = [b - a for a, b in zip(p0, p1)]
    length = math.sqrt(sum(c * c for c in d))
    mid = [(a + b) / 2 for a, b in zip(p0, p1)]
    # Turn the +Z axis onto d: tilt by theta about X, then turn by phi + 90 deg about Z
    # (Euler XYZ: X first), which takes +Z to (sin t cos p, sin t sin p, cos t).
    theta = math.acos(max(-1.0, min(1.0, d[2] / length)))
    phi = math.atan2(d[1], d[0])
    bpy.ops.mesh.primitive_cylinder_add(vertices=vertices, radius=radius, depth=length,
                                        location=mid, rotation=(theta, 0.0, phi + math.pi / 2))
    obj = bpy.context.active_object
    return _finish(obj, name, mat, smooth=True)


def sphere(name, mat, location, radius, segments=24, rings=12):
    bpy.ops.mesh.primitive_uv_sphere_add(radius=radius, location=location, segments=segments,
                                         ring_count=rings)
    return _finish(bpy.context.active_object, name, mat, smooth=True)


def monkey(name, mat, location, size, rotation=(-10.0, 0.0, 195.0)):
    bpy.ops.mesh.primitive_monkey_add(size=size, location=location,
                                      rotation=tuple(math.radians(a) for a in rotation))
    obj = _finish(bpy.context.active_object, name, mat, smooth=True)
    mod = obj.modifiers.new("Subdivision", "SUBSURF")
    mod.levels = mod.render_levels = 2
    return obj


def box(name, mat, location, size, rotation_z=0.0):
    bpy.ops.mesh.primitive_cube_add(size=1.0, location=location,
                                    rotation=(0.0, 0.0, math.radians(rotation_z)))
    obj = bpy.context.active_object
    obj.scale = size
    return _finish(obj, name, mat, apply_scale=True)


def strand(name, mat, points, radius):
    """A hair-like strand: a poly curve through points, bevelled to radius and turned into a
    mesh (the study's fg / rest passes switch meshes only)."""
    data = bpy.data.curves.new(name, "CURVE")
    data.dimensions = "3D"
    data.bevel_depth = radius
    data.bevel_resolution = 1
    data.use_fill_caps = True
    spline = data.splines.new("POLY")
    spline.points.add(len(points) - 1)
    for point, p in zip(spline.points, points):
        point.co = (p[0], p[1], p[2], 1.0)
    obj = bpy.data.objects.new(name, data)
    bpy.context.scene.collection.objects.link(obj)
    for other in bpy.context.selected_objects:
        other.select_set(False)
    obj.select_set(True)
    bpy.context.view_layer.objects.active = obj
    bpy.ops.object.convert(target="MESH")
    obj = bpy.context.active_object
    return _finish(obj, name, mat, smooth=True)
