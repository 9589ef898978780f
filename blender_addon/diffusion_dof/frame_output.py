# SPDX-License-Identifier: GPL-3.0-or-later
"""What becomes of a frame's result (main thread): cut out of an overscan render, run through
the user's compositing, stored as the result image, kept as inputs, written over the frame
file, reported; and the frame as rendered when the call failed."""

import os

import bpy

from . import camera as camera_mod
from . import composite, images, passes, report
from . import settings as settings_mod
from .errors import SetupError
from .frame_file import write_frame
from .overscan_render import crop_all, crop_frame


def composite_frame(scene, settings, job, out, width, height, channels):
    """The user's compositing run on the depth-of-field image `out` (composite.py), with the
    other passes it reads as rendered (cropped like the frame); returns its pixels."""
    inputs = {composite.DOF_KEY: images.store_result(composite.RAW_IMAGE, width, height,
                                                    channels, out)}
    for slot in job.extra:
        data = images.read_exr(job.files[slot])
        if data is None:
            raise SetupError("a pass your compositing reads (%s) was not written: click Set Up "
                             "Passes and render again" % os.path.basename(job.files[slot]))
        buf, w, h, c = data
        if job.overscan is not None:
            buf, w, h = crop_frame(job.overscan, buf, c), job.overscan.width, \
                job.overscan.height
        inputs[slot] = images.store_result(composite.PASS_IMAGE % slot, w, h, c, buf)
    try:
        path = composite.run(scene, settings, job.frame, inputs, width, height)
    finally:
        for key, image in inputs.items():  # their pixels are in the composited frame now
            if key != composite.DOF_KEY:
                images.retire_image(image)
    try:
        result = images.read_exr(path)
    finally:
        if os.path.exists(path):
            os.remove(path)
    if result is None or result[1:] != (width, height, channels):
        raise SetupError("your compositing gave %s, not a %dx%d image"
                         % ("nothing" if result is None else "%dx%d with %d channels"
                            % result[1:], width, height))
    return result[0]


def _composited(job, settings, out, width, height, channels, worker):
    """composite_frame() as a step of finish(): with the UI it waits for a running render
    (Ctrl F12's next frame), since it is a render itself and two at once share the compositor.
    None when the scene is gone."""
    while worker and bpy.app.is_job_running("RENDER"):
        yield
    scene = bpy.data.scenes.get(job.scene_name)
    if scene is None:
        return None
    return composite_frame(scene, settings, job, out, width, height, channels)


def write_fallback(scene, job, fallback):
    """A grown (overscan) frame that got no depth of field is still written at the frame's size:
    the frame as rendered, cropped (`fallback`, or the Combined pass read now when the frame
    failed before reading it). Returns what it did, as words for the report."""
    plan = job.overscan
    settings = settings_mod.get(scene)
    if plan is None or not job.write or settings is None or not settings.write_frames:
        return ""
    try:
        if fallback is None:
            color = images.read_exr(job.files[passes.SLOT_COLOR])
            if color is None or color[1:3] != (plan.full_width, plan.full_height):
                raise SetupError("no Combined pass of the grown size")
            fallback = (crop_frame(plan, color[0], color[3]), plan.width, plan.height, color[3])
        buf, width, height, channels = fallback
        image = images.store_result(images.RESULT_IMAGE, width, height, channels, buf)
        return " (written as rendered, cropped to the frame: %s)" % write_frame(
            scene, image, job.frame, job.started)
    except Exception as err:  # the report says what failed first; this is the aftermath
        return " (the overscan margin could not be cropped off the written file: %s)" % err


def finish(job, scene, settings, frame, out, stats, worker):
    """The result `out` of the library call on `frame` (frame_inputs.FrameInputs) stored,
    written and reported: a step of frame_steps.job_steps (it waits for a running render before
    compositing, see _composited)."""
    width, height, channels = frame.width, frame.height, frame.color[1]
    color, depth, foreground = frame.color[0], frame.depth, frame.foreground
    matte = frame.matte
    plan = job.overscan
    if plan is not None:  # the frame out of the grown render
        out, color, cropped_depth, foreground = crop_all(
            plan, (out, channels), frame.fallback[0], depth, foreground)
        depth = (cropped_depth, depth[1])
        matte = matte and (crop_frame(plan, *matte), matte[1])
        width, height = plan.width, plan.height
    pixels = out
    if composite.has_compositing(scene, settings):
        pixels = yield from _composited(job, settings, out, width, height, channels, worker)
        if pixels is None:  # the scene was removed meanwhile
            return
    image = images.store_result(images.RESULT_IMAGE, width, height, channels, pixels)
    if settings.keep_inputs:
        images.keep_inputs(width, height, (color, channels), depth, foreground, matte,
                           scene.name)
    path = None
    if job.write and settings.write_frames:
        try:
            path = write_frame(scene, image, job.frame, job.started)
        except SetupError as err:
            raise SetupError("the result is in the '%s' image, but the frame file was "
                             "not replaced: %s" % (image.name, err)) from None
    if not bpy.app.background and settings.show_result:
        images.show_in_render_window(image)
    camera_line = camera_mod.describe(frame.camera, frame.camera_info)
    report.set_report(scene.name, True, "frame %d: %s; %s%s" % (
        job.frame, report.summary(stats), camera_line, (" -> " + path) if path else ""),
        job.frame, stats, camera_line, path)
