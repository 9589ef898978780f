# SPDX-License-Identifier: MIT
"""The study scenes' materials: emission only (an albedo times a fixed fake-Lambert term, no light
sampling), so the only noise in a render is that of the lens and the pixel footprint; and the
albedo builders (procedural textures) they take."""

import math

import bpy

LIGHT_DIR = (0.42, -0.55, 0.72)  # the fake-Lambert light, world space (normalised below)


def _new_material(name):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    return mat, nodes, mat.node_tree.links, out


def unlit(name, albedo, ambient=0.45, key=0.6):
    """Emission = albedo * (ambient + key * max(0, N.L)): shaded, but noise-free.
    albedo(nodes, links) returns a colour socket, or is an RGB tuple."""
    mat, nodes, links, out = _new_material(name)
    geo = nodes.new("ShaderNodeNewGeometry")
    dot = nodes.new("ShaderNodeVectorMath")
    dot.operation = "DOT_PRODUCT"
    n = math.sqrt(sum(c * c for c in LIGHT_DIR))
    dot.inputs[1].default_value = tuple(c / n for c in LIGHT_DIR)
    links.new(geo.outputs["Normal"], dot.inputs[0])
    clamp = nodes.new("ShaderNodeMath")
    clamp.operation = "MAXIMUM"
    clamp.inputs[1].default_value = 0.0
    links.new(dot.outputs["Value"], clamp.inputs[0])
    shade = nodes.new("ShaderNodeMath")
    shade.operation = "MULTIPLY_ADD"
    shade.inputs[1].default_value = key
    shade.inputs[2].default_value = ambient
    links.new(clamp.outputs["Value"], shade.inputs[0])
    mix = nodes.new("ShaderNodeMixRGB")
    mix.blend_type = "MULTIPLY"
    mix.inputs["Fac"].default_value = 1.0
    if isinstance(albedo, tuple):
        mix.inputs["Color1"].default_value = albedo + (1.0,) if len(albedo) == 3 else albedo
    else:
        links.new(albedo(nodes, links), mix.inputs["Color1"])
    links.new(shade.outputs["Value"], mix.inputs["Color2"])
    em = nodes.new("ShaderNodeEmission")
    em.inputs["Strength"].default_value = 1.0
    links.new(mix.outputs["Color"], em.inputs["Color"])
    links.new(em.outputs["Emission"], out.inputs["Surface"])
    return mat


def texture(tex_type, colors=None, scale=1.0, setup=None, coords="Object"):
    """An albedo builder for unlit(): a procedural texture in object coordinates (metres once
    the object's scale is applied)."""
    def build(nodes, links):
        coord = nodes.new("ShaderNodeTexCoord")
        tex = nodes.new(tex_type)
        if "Scale" in tex.inputs:
            tex.inputs["Scale"].default_value = scale
        if colors and "Color1" in tex.inputs:
            tex.inputs["Color1"].default_value = colors[0]
            tex.inputs["Color2"].default_value = colors[1]
        if setup:
            setup(tex)
        links.new(coord.outputs[coords], tex.inputs["Vector"])
        return tex.outputs["Color"]
    return build


def multiply(a, b, fac=1.0):
    """Albedo builder: a * b (MixRGB multiply with factor fac)."""
    def build(nodes, links):
        mix = nodes.new("ShaderNodeMixRGB")
        mix.blend_type = "MULTIPLY"
        mix.inputs["Fac"].default_value = fac
        links.new(a(nodes, links), mix.inputs["Color1"])
        links.new(b(nodes, links), mix.inputs["Color2"])
        return mix.outputs["Color"]
    return build


def checker(c1, c2, scale):
    return texture("ShaderNodeTexChecker", [c1, c2], scale)


def ramp(tex_type, colors, scale, setup=None, detail=None):
    """An albedo builder for unlit(): a procedural texture's Fac (object coordinates, metres)
    through a colour ramp of `colors` (RGB tuples, evenly spaced)."""
    def build(nodes, links):
        coord = nodes.new("ShaderNodeTexCoord")
        tex = nodes.new(tex_type)
        tex.inputs["Scale"].default_value = scale
        if detail is not None and "Detail" in tex.inputs:
            tex.inputs["Detail"].default_value = detail
        if setup:
            setup(tex)
        links.new(coord.outputs["Object"], tex.inputs["Vector"])
        cr = nodes.new("ShaderNodeValToRGB")
        elems = cr.color_ramp.elements
        while len(elems) < len(colors):
            elems.new(0.5)
        for i, c in enumerate(colors):
            elems[i].position = i / (len(colors) - 1)
            elems[i].color = tuple(c) + (1.0,)
        fac = tex.outputs["Fac"] if "Fac" in tex.outputs else tex.outputs["Distance"]
        links.new(fac, cr.inputs["Fac"])
        return cr.outputs["Color"]
    return build


def _rgb(nodes, color):
    node = nodes.new("ShaderNodeRGB")
    node.outputs["Color"].default_value = tuple(color) + (1.0,)
    return node.outputs["Color"]


def emission(name, color, strength):
    mat, nodes, links, out = _new_material(name)
    em = nodes.new("ShaderNodeEmission")
    em.inputs["Color"].default_value = tuple(color[:3]) + (1.0,)
    em.inputs["Strength"].default_value = strength
    links.new(em.outputs["Emission"], out.inputs["Surface"])
    return mat


def bricks(width, height, mortar, mortar_color, offset=0.5):
    def setup(tex):
        tex.inputs["Mortar Size"].default_value = mortar
        tex.inputs["Brick Width"].default_value = width
        tex.inputs["Row Height"].default_value = height
        tex.inputs["Mortar"].default_value = mortar_color
        tex.offset = offset
    return setup


def wave_z(tex):
    tex.bands_direction = "Z"
