# SPDX-License-Identifier: GPL-3.0-or-later
"""Image planes as cards (docs/cards.md): the scene's visible mesh faces whose material shows an
image texture (as "Import Images as Planes" makes them) become ddof cards in the scene camera's
space, rendered by ddof_render_cards in one call: depth of field for a 2.5D layout without a
Cycles render. Geometry and images only: no lights, no shading (a card is its image)."""

import array
import time

import bpy

from . import binding, ddof_abi, images, report
from . import camera as camera_mod
from . import settings as settings_mod
from .errors import SetupError

RESULT_IMAGE = "Diffusion DOF Cards"


def plane_image(obj):
    """The image an object's material shows (its node tree's first Image Texture node with an
    image), or None."""
    for slot in obj.material_slots:
        mat = slot.material
        if mat is None or not mat.use_nodes or mat.node_tree is None:
            continue
        for node in mat.node_tree.nodes:
            if node.type == "TEX_IMAGE" and node.image is not None:
                return node.image
    return None


def texture_of(image):
    """(premultiplied linear RGBA floats, row 0 at the top as the library reads it, width,
    height). Byte images in the sRGB colour space are decoded to linear; alpha is multiplied in
    unless the image says it is premultiplied already ('PREMUL'); 'NONE' is opaque. A colour
    conversion, not the blur: numpy (bundled with Blender) does it at once."""
    import numpy as np
    width, height = image.size
    if width == 0 or height == 0:
        raise SetupError("The image '%s' has no pixels (is its file missing?)." % image.name)
    channels = image.channels
    raw = np.empty(width * height * channels, np.float32)
    image.pixels.foreach_get(raw)
    raw = raw.reshape(height, width, channels)
    rgb = raw[..., :3] if channels >= 3 else np.repeat(raw[..., :1], 3, axis=2)
    opaque = channels < 4 or image.alpha_mode == "NONE"
    alpha = np.ones((height, width, 1), np.float32) if opaque else raw[..., 3:4]
    if not image.is_float and image.colorspace_settings.name == "sRGB":
        rgb = np.where(rgb <= 0.04045, rgb / 12.92, ((rgb + 0.055) / 1.055) ** 2.4)
    if image.alpha_mode not in ("PREMUL", "NONE"):
        rgb = rgb * alpha
    rgba = np.concatenate([rgb, alpha], axis=2)[::-1]  # Blender's rows are bottom first
    out = array.array("f")
    out.frombytes(np.ascontiguousarray(rgba, np.float32).tobytes())
    return out, width, height


def image_planes(scene, cam_obj, depsgraph):
    """(cards for Session.render_cards, names of the objects used, faces skipped): every mesh
    face of 3 to 8 vertices the depsgraph shows (and rendering does not hide) whose object's
    material shows an image, in the camera's space (scene units times the unit scale, metres),
    with the face's uv. Faces with a vertex at, behind or within 1e-6 m of the camera's plane
    are skipped (the library refuses them)."""
    unit = scene.unit_settings.scale_length or 1.0
    to_camera = cam_obj.evaluated_get(depsgraph).matrix_world.inverted()
    textures, cards, used, skipped = {}, [], [], 0
    for evaluated in depsgraph.objects:
        if evaluated.type != "MESH" or evaluated.original.hide_render:
            continue
        obj = evaluated
        image = plane_image(obj)
        if image is None:
            continue
        mesh = evaluated.to_mesh()
        try:
            uv_layer = mesh.uv_layers.active
            if uv_layer is None:
                continue
            if image.name not in textures:
                textures[image.name] = texture_of(image)
            pixels, width, height = textures[image.name]
            matrix = to_camera @ obj.matrix_world
            before = len(cards)
            for poly in mesh.polygons:
                if not 3 <= poly.loop_total <= ddof_abi.CARD_MAX_VERTICES:
                    skipped += 1
                    continue
                loops = range(poly.loop_start, poly.loop_start + poly.loop_total)
                positions = [tuple(c * unit for c in matrix @ mesh.vertices[
                    mesh.loops[i].vertex_index].co) for i in loops]
                # the library's DDOF_CARD_MIN_DEPTH_M: nearer than 1e-6 m is refused
                if any(p[2] > -1e-6 for p in positions):
                    skipped += 1
                    continue
                uv = [(uv_layer.data[i].uv[0], uv_layer.data[i].uv[1]) for i in loops]
                cards.append({"positions": positions, "uv": uv, "texture": pixels,
                              "width": width, "height": height, "name": obj.name})
            if len(cards) > before:
                used.append(obj.name)
        finally:
            evaluated.to_mesh_clear()
    return cards, used, skipped


def flipped_rows(pixels, width, height, channels=4):
    """The image upside down (the library's row 0 is the top, Blender's the bottom), a float32
    array."""
    import numpy as np
    rows = np.frombuffer(pixels, np.float32).reshape(height, width * channels)
    return np.ascontiguousarray(rows[::-1]).ravel()


def render_scene(scene, depsgraph):
    """(out, width, height, message): the scene's image planes as cards at its render size,
    out premultiplied RGBA with Blender's rows (bottom first). Raises SetupError, DdofError."""
    settings = settings_mod.get(scene)
    cam, info = camera_mod.camera_settings(scene, settings, depsgraph)
    cam_obj = camera_mod.camera_object(scene, depsgraph)
    cards, used, skipped = image_planes(scene, cam_obj, depsgraph)
    if not cards:
        raise SetupError("No image planes in view: the cards are mesh faces whose material "
                         "has an Image Texture node, in front of the camera.")
    r = scene.render
    width = max(1, r.resolution_x * r.resolution_percentage // 100)
    height = max(1, r.resolution_y * r.resolution_percentage // 100)
    since = time.perf_counter()
    with binding.get_library().session(settings.threads) as session:
        out = session.render_cards(width, height, cam, cards)
    seconds = time.perf_counter() - since
    message = "%d cards from %d image planes in %.0f ms (%s)%s" % (
        len(cards), len(used), 1e3 * seconds, camera_mod.describe(cam, info),
        "; %d face(s) skipped (behind the camera or over 8 vertices)" % skipped
        if skipped else "")
    return flipped_rows(out, width, height), width, height, message


class DIFFUSION_DOF_OT_render_cards(bpy.types.Operator):
    """Render the scene's image planes (mesh faces whose material shows an image texture) as
    cards blurred by their own depth, with the scene camera's lens and the Diffusion DOF
    camera settings: depth of field for a 2.5D layout in one call, without a Cycles render"""
    bl_idname = "diffusion_dof.render_cards"
    bl_label = "Render Image Planes as Cards"
    bl_options = {"REGISTER"}

    def execute(self, context):
        scene = context.scene
        ok, text = binding.library_status()
        if not ok:
            self.report({"ERROR"}, text)
            return {"CANCELLED"}
        try:
            out, width, height, message = render_scene(scene, context.evaluated_depsgraph_get())
        except (SetupError, binding.DdofError, binding.LibraryError, ValueError) as err:
            self.report({"ERROR"}, str(err))
            return {"CANCELLED"}
        image = images.store_result(RESULT_IMAGE, width, height, 4, out)
        image.alpha_mode = "PREMUL"
        report.log(message)
        self.report({"INFO"}, message)
        return {"FINISHED"}


class DIFFUSION_DOF_RE_cards(bpy.types.RenderEngine):
    """The render option: a render engine that renders the scene's image planes as cards
    (Render Properties > Render Engine > Diffusion DOF Cards), so that F12, animations and the
    command line's `blender -b file -a` take milliseconds a frame instead of a Cycles render.
    The Combined pass only; the compositor runs after it as after any engine."""
    bl_idname = "DIFFUSION_DOF_CARDS"
    bl_label = "Diffusion DOF Cards"
    bl_use_preview = False
    bl_use_postprocess = True

    def render(self, depsgraph):
        scene = depsgraph.scene
        try:
            out, width, height, message = render_scene(scene, depsgraph)
        except (SetupError, binding.DdofError, binding.LibraryError, ValueError) as err:
            self.report({"ERROR"}, str(err))
            return
        result = self.begin_result(0, 0, width, height)
        set_rect(result.layers[0].passes["Combined"], out, width * height)
        self.end_result(result)
        report.log(message)


def set_rect(render_pass, pixels, count):
    """A render pass's pixels from a flat RGBA buffer: foreach_set takes it flat in recent
    Blenders and as (pixels, 4) in older ones; assignment is the slow last resort."""
    import numpy as np
    flat = np.frombuffer(pixels, np.float32)
    for shaped in (flat, flat.reshape(count, 4)):
        try:
            render_pass.rect.foreach_set(shaped)
            return
        except (TypeError, ValueError, RuntimeError):
            pass
    render_pass.rect = flat.reshape(count, 4)


CLASSES = (DIFFUSION_DOF_OT_render_cards, DIFFUSION_DOF_RE_cards)


# Registers CLASSES in order and unregisters them in reverse (Blender's own helper).
register, unregister = bpy.utils.register_classes_factory(CLASSES)
