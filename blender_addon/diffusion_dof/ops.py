# SPDX-License-Identifier: GPL-3.0-or-later
"""Operators: apply to any two images, set up the passes, pinhole render, reload the library."""

import bpy
from bpy.props import StringProperty

from . import camera as camera_mod
from . import binding, passes, render
from . import settings as settings_mod
from .errors import SetupError


class DIFFUSION_DOF_OT_apply_images(bpy.types.Operator):
    """Apply diffusion depth of field to a colour image and a depth image, with the scene's
    camera and Diffusion DOF settings; the result goes to the output image"""
    bl_idname = "diffusion_dof.apply_images"
    bl_label = "Apply Diffusion DOF to Images"
    bl_options = {"REGISTER", "UNDO"}

    color: StringProperty(name="Colour", description="Name of the colour image (linear, float)")
    depth: StringProperty(name="Depth",
                          description="Name of the depth image: planar camera Z in scene units "
                                      "(Blender's Depth pass), first channel")
    output: StringProperty(name="Output", default=render.RESULT_IMAGE,
                           description="Name of the image that receives the result (created "
                                       "or resized as needed)")
    camera: StringProperty(name="Camera",
                           description="Camera object whose settings drive the blur (empty: the "
                                       "scene camera)")
    fg_color: StringProperty(name="Foreground Colour",
                             description="Optional: a separately rendered foreground element, "
                                         "RGBA premultiplied, blurred on top")
    fg_depth: StringProperty(name="Foreground Depth",
                             description="The foreground element's depth (with Foreground "
                                         "Colour)")

    def execute(self, context):
        scene = context.scene
        settings = settings_mod.get(scene)
        ok, text = binding.library_status()
        if not ok:
            self.report({"ERROR"}, text)
            return {"CANCELLED"}
        try:
            wanted = [("colour", self.color), ("depth", self.depth)]
            if self.fg_color or self.fg_depth:
                wanted += [("foreground colour", self.fg_color),
                           ("foreground depth", self.fg_depth)]
            images = []
            for role, name in wanted:
                image = bpy.data.images.get(name)
                if image is None:
                    raise SetupError("There is no %s image named '%s'." % (role, name))
                if role.endswith("depth") and not image.is_float:
                    raise SetupError("The %s image '%s' holds 8-bit values, not distances: "
                                     "load the Depth pass from an OpenEXR file."
                                     % (role, image.name))
                images.append(image)
            color_img, depth_img = images[:2]
            cam_obj = None
            if self.camera:
                cam_obj = bpy.data.objects.get(self.camera)
                if cam_obj is None:
                    raise SetupError("There is no object named '%s'." % self.camera)
            cam, info = camera_mod.camera_settings(scene, settings, cam_obj=cam_obj)
            color, width, height, channels = render.read_image(color_img)
            depth, dw, dh, dchannels = render.read_image(depth_img)
            if (dw, dh) != (width, height):
                raise SetupError("The colour image is %dx%d but the depth image %dx%d."
                                 % (width, height, dw, dh))
            foreground = None
            if len(images) == 4:
                fg_color, fw, fh, fchannels = render.read_image(images[2])
                fg_depth, gw, gh, gchannels = render.read_image(images[3])
                if (fw, fh, gw, gh) != (width, height, width, height) or fchannels != 4:
                    raise SetupError("The foreground images must be RGBA and %dx%d like the "
                                     "colour image." % (width, height))
                foreground = {"color": fg_color, "depth": fg_depth, "depth_channels": gchannels}
            # Images of the scene's render border (the kept passes) keep their place in the
            # frame; other images are frames of their own.
            region = render.scene_region(scene, width, height, strict=False)
            render.cancel_event.clear()
            out, stats = render.run_region(scene, settings, width, height, color, channels,
                                           depth, dchannels, cam, foreground, region)
            render.store_result(self.output or render.RESULT_IMAGE, width, height, channels,
                                out)
        except (SetupError, binding.LibraryError, binding.DdofError) as err:
            self.report({"ERROR"}, str(err))
            return {"CANCELLED"}
        message = "%s -> '%s': %s; %s" % (color_img.name, self.output, render.summary(stats),
                                          camera_mod.describe(cam, info))
        render.reports[scene.name] = {"ok": True, "message": message, "frame": None,
                                      "stats": stats, "camera": camera_mod.describe(cam, info),
                                      "path": None, "time": 0.0}
        self.report({"INFO"}, message)
        return {"FINISHED"}


class DIFFUSION_DOF_OT_watch_escape(bpy.types.Operator):
    """Esc cancels the Diffusion DOF call that is running (the frame is left as rendered)"""
    bl_idname = "diffusion_dof.watch_escape"
    bl_label = "Cancel Diffusion DOF"
    bl_options = {"INTERNAL"}

    def invoke(self, context, _event):
        self._timer = context.window_manager.event_timer_add(0.1, window=context.window)
        context.window_manager.modal_handler_add(self)
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type == "ESC" and event.value == "PRESS":
            render.request_cancel()
        if not render.busy():
            context.window_manager.event_timer_remove(self._timer)
            return {"FINISHED"}
        return {"PASS_THROUGH"}


class DIFFUSION_DOF_OT_reapply(bpy.types.Operator):
    """Apply Diffusion DOF again to the last rendered frame's passes (kept as 'Diffusion DOF
    Input' and 'Diffusion DOF Depth', and the foreground element's) with the current settings
    and camera, without rendering"""
    bl_idname = "diffusion_dof.reapply"
    bl_label = "Re-apply"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return render.INPUT_IMAGE in bpy.data.images and render.DEPTH_IMAGE in bpy.data.images

    def execute(self, context):
        fg = {}
        if context.scene.diffusion_dof.foreground_collection is not None and \
                render.FG_INPUT_IMAGE in bpy.data.images:
            fg = {"fg_color": render.FG_INPUT_IMAGE, "fg_depth": render.FG_DEPTH_IMAGE}
        try:
            bpy.ops.diffusion_dof.apply_images(color=render.INPUT_IMAGE, depth=render.DEPTH_IMAGE,
                                               output=render.RESULT_IMAGE, **fg)
        except RuntimeError as err:
            self.report({"ERROR"}, str(err))
            return {"CANCELLED"}
        return {"FINISHED"}


class DIFFUSION_DOF_OT_setup(bpy.types.Operator):
    """Turn on the Depth pass and add the compositor nodes that hand the passes to Diffusion
    DOF (and the foreground companion scene when a foreground collection is set)"""
    bl_idname = "diffusion_dof.setup"
    bl_label = "Set Up Passes"
    bl_options = {"REGISTER", "UNDO"}

    def execute(self, context):
        try:
            changes = passes.ensure_setup(context.scene)
        except SetupError as err:
            self.report({"ERROR"}, str(err))
            return {"CANCELLED"}
        self.report({"INFO"}, "; ".join(changes) if changes else "Everything was already set up")
        return {"FINISHED"}


class DIFFUSION_DOF_OT_pinhole(bpy.types.Operator):
    """Turn off the camera's lens depth of field, so the render is sharp and Diffusion DOF does
    the blurring (the camera's focus and f-stop still drive it)"""
    bl_idname = "diffusion_dof.pinhole"
    bl_label = "Use Pinhole Render"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        cam = context.scene.camera
        return cam is not None and cam.type == "CAMERA"

    def execute(self, context):
        context.scene.camera.data.dof.use_dof = False
        return {"FINISHED"}


class DIFFUSION_DOF_OT_reload_library(bpy.types.Operator):
    """Look for the ddof library again (after installing it or setting DDOF_LIBRARY)"""
    bl_idname = "diffusion_dof.reload_library"
    bl_label = "Reload Library"

    def execute(self, _context):
        ok, text = binding.library_status(reload=True)
        self.report({"INFO"} if ok else {"ERROR"}, text)
        return {"FINISHED"} if ok else {"CANCELLED"}


CLASSES = (DIFFUSION_DOF_OT_apply_images, DIFFUSION_DOF_OT_watch_escape,
           DIFFUSION_DOF_OT_reapply, DIFFUSION_DOF_OT_setup,
           DIFFUSION_DOF_OT_pinhole, DIFFUSION_DOF_OT_reload_library)


# Registers CLASSES in order and unregisters them in reverse (Blender's own helper).
register, unregister = bpy.utils.register_classes_factory(CLASSES)
