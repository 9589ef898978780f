# SPDX-License-Identifier: GPL-3.0-or-later
"""Moving pixels between Blender's image datablocks and float buffers (main thread only): the
files the File Output node wrote, the result and kept-input images, the images the add-on is
done with, and showing an image in an editor."""

import os

import bpy

from . import binding
from .errors import SetupError

RESULT_IMAGE = "Diffusion DOF"
INPUT_IMAGE = "Diffusion DOF Input"
DEPTH_IMAGE = "Diffusion DOF Depth"
FG_INPUT_IMAGE = "Diffusion DOF Foreground"
FG_DEPTH_IMAGE = "Diffusion DOF Foreground Depth"
FOCUS_MAP_IMAGE = "Diffusion DOF Focus Map"


def read_image(image):
    """(buffer, width, height, channels) of an image datablock's float pixels."""
    width, height = image.size
    channels = image.channels
    if width == 0 or height == 0:
        raise SetupError("Image '%s' has no pixels (is its file missing?)." % image.name)
    buf = binding.new_buffer(width * height * channels)
    image.pixels.foreach_get(buf)
    return buf, width, height, channels


# Images the add-on is done with: their pixels are freed at once, the datablocks once no render
# runs. Blender 5.2+ re-evaluates an animation's render depsgraph between frames and crashes
# (deg_check_base_in_depsgraph, from RE_RenderAnim) when an image was removed meanwhile, so
# nothing is removed from bpy.data while a render runs; free_spent_images does it afterwards.
SPENT_IMAGE = ".Diffusion DOF spent"  # the leading dot hides them from image lists
SPENT_KEY = "diffusion_dof_spent"
_spent = []  # names of spent images (main thread only)


def retire_image(image):
    """Frees an image's pixels now and removes the datablock after the render (main thread)."""
    image.name = SPENT_IMAGE
    image[SPENT_KEY] = True
    image.buffers_free()
    _spent.append(image.name)


def free_spent_images():
    """Removes the retired images; only when no render runs (main thread)."""
    while _spent:
        image = bpy.data.images.get(_spent.pop())
        if image is not None and image.get(SPENT_KEY):
            bpy.data.images.remove(image)


def forget_spent_images():
    """Forgets the retired images (and kept mattes) of a file that is no longer loaded."""
    _spent.clear()
    _kept_mattes.clear()


def read_exr(path, exact=False):
    """Loads a file the File Output node wrote, raw (no colour transform); None if missing.
    exact: every float as written, bit for bit (Cryptomatte's ids): as data (Non-Color) and
    with its alpha channel packed (never premultiplied or unpremultiplied)."""
    if not os.path.isfile(path):
        return None
    image = bpy.data.images.load(path, check_existing=False)
    try:
        image.colorspace_settings.is_data = True
        if exact:  # set before the pixels are read: they load on first use
            image.colorspace_settings.name = "Non-Color"
            image.alpha_mode = "CHANNEL_PACKED"
        return read_image(image)
    finally:
        retire_image(image)


def store_result(name, width, height, channels, pixels, data=False):
    """Puts pixels into a float image datablock (created or resized as needed); data=True marks
    them as non-colour values (depth)."""
    image = bpy.data.images.get(name)
    if image is not None and (not image.is_float or image.channels != channels):
        image.name = name + ".old"
        image = None
    if image is None:
        image = bpy.data.images.new(name, width, height, alpha=channels == 4, float_buffer=True)
    elif tuple(image.size) != (width, height):
        image.scale(width, height)
    if data and not image.colorspace_settings.is_data:
        image.colorspace_settings.is_data = True
    image.pixels.foreach_set(pixels)
    image.update()
    return image


# The object matte of the kept inputs, by scene name: (buffer, channels, width, height). In
# memory only (an image holds at most 4 channels, and the ids' bits must not go through one):
# Re-apply of the kept inputs uses it; a file loaded again re-applies without it.
_kept_mattes = {}


def kept_matte(scene_name, color_name, width, height):
    """The matte kept with the scene's kept inputs, (buffer, channels), when the colour image
    is the kept input of that size; else None."""
    kept = _kept_mattes.get(scene_name)
    if kept is None or color_name != INPUT_IMAGE or kept[2:] != (width, height):
        return None
    return kept[:2]


def keep_inputs(width, height, color, depth, foreground, matte=None, scene_name=""):
    """Keeps a frame's passes ((buffer, channels) each) for Re-apply and the focus tools, and
    its object matte ((buffer, channels) or None) for Re-apply."""
    if matte is None:
        _kept_mattes.pop(scene_name, None)
    else:
        _kept_mattes[scene_name] = (matte[0], matte[1], width, height)
    store_result(INPUT_IMAGE, width, height, color[1], color[0])
    store_result(DEPTH_IMAGE, width, height, depth[1], depth[0], data=True)
    if foreground is not None:
        store_result(FG_INPUT_IMAGE, width, height, 4, foreground["color"])
        store_result(FG_DEPTH_IMAGE, width, height, foreground["depth_channels"],
                     foreground["depth"], data=True)
    else:
        for name in (FG_INPUT_IMAGE, FG_DEPTH_IMAGE):
            if name in bpy.data.images:
                retire_image(bpy.data.images[name])


def show_image(image):
    """Shows an image in the first image editor of the screen (if there is one)."""
    for window in bpy.context.window_manager.windows:
        for area in window.screen.areas:
            if area.type == "IMAGE_EDITOR":
                area.spaces.active.image = image
                return


def show_in_render_window(image):
    """Shows the image instead of the render result in the editors that show it."""
    for window in bpy.context.window_manager.windows:
        for area in window.screen.areas:
            if area.type != "IMAGE_EDITOR":
                continue
            space = area.spaces.active
            if space.image is not None and space.image.type == "RENDER_RESULT":
                space.image = image
