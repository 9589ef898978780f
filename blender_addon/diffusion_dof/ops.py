# SPDX-License-Identifier: GPL-3.0-or-later
"""Operators: apply to any two images, set up the passes, pinhole render, reload the library."""

import bpy
from bpy.props import IntProperty, StringProperty

from . import camera as camera_mod
from . import binding, escape_watch, focus_map, frame_inputs, frame_region, images, jobs
from . import library_call, passes, report
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
    output: StringProperty(name="Output", default=images.RESULT_IMAGE,
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
            chosen = []
            for role, name in wanted:
                image = bpy.data.images.get(name)
                if image is None:
                    raise SetupError("There is no %s image named '%s'." % (role, name))
                if role.endswith("depth") and not image.is_float:
                    raise SetupError("The %s image '%s' holds 8-bit values, not distances: "
                                     "load the Depth pass from an OpenEXR file."
                                     % (role, image.name))
                chosen.append(image)
            color_img, depth_img = chosen[:2]
            cam_obj = None
            if self.camera:
                cam_obj = bpy.data.objects.get(self.camera)
                if cam_obj is None:
                    raise SetupError("There is no object named '%s'." % self.camera)
            cam, info = camera_mod.camera_settings(scene, settings, cam_obj=cam_obj)
            color, width, height, channels = images.read_image(color_img)
            depth, dw, dh, dchannels = images.read_image(depth_img)
            if (dw, dh) != (width, height):
                raise SetupError("The colour image is %dx%d but the depth image %dx%d."
                                 % (width, height, dw, dh))
            foreground = None
            if len(chosen) == 4:
                fg_color, fw, fh, fchannels = images.read_image(chosen[2])
                fg_depth, gw, gh, gchannels = images.read_image(chosen[3])
                if (fw, fh, gw, gh) != (width, height, width, height) or fchannels != 4:
                    raise SetupError("The foreground images must be RGBA and %dx%d like the "
                                     "colour image." % (width, height))
                foreground = {"color": fg_color, "depth": fg_depth, "depth_channels": gchannels}
            # Images of the scene's render border (the kept passes) keep their place in the
            # frame; other images are frames of their own.
            region = frame_inputs.scene_region(scene, width, height, strict=False)
            # The kept inputs' object matte, with them (Object Matte not Off).
            matte = None if settings.object_matte == "OFF" else images.kept_matte(
                scene.name, color_img.name, width, height)
            library_call.cancel_event.clear()
            out, stats = library_call.run_region(width, height, color, channels, depth,
                                                 dchannels, cam, foreground, region,
                                                 library_call.library_options(settings), matte)
            images.store_result(self.output or images.RESULT_IMAGE, width, height, channels,
                                out)
        except (SetupError, binding.LibraryError, binding.DdofError) as err:
            self.report({"ERROR"}, str(err))
            return {"CANCELLED"}
        message = "%s -> '%s': %s; %s" % (color_img.name, self.output, report.summary(stats),
                                          camera_mod.describe(cam, info))
        report.reports[scene.name] = {"ok": True, "message": message, "frame": None,
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
        escape_watch.watching["on"] = True
        return {"RUNNING_MODAL"}

    def modal(self, context, event):
        if event.type == "ESC" and event.value == "PRESS":
            library_call.request_cancel()
        if not jobs.busy():
            context.window_manager.event_timer_remove(self._timer)
            escape_watch.watching["on"] = False
            return {"FINISHED"}
        return {"PASS_THROUGH"}


def _kept_passes():
    """(color, depth) of the last frame's kept passes: each (buffer, width, height, channels).
    Raises SetupError when there are none."""
    color_img = bpy.data.images.get(images.INPUT_IMAGE)
    depth_img = bpy.data.images.get(images.DEPTH_IMAGE)
    if color_img is None or depth_img is None:
        raise SetupError("Render a frame with Diffusion DOF on and Output > Keep Inputs "
                         "checked first: the focus tools read its Depth pass.")
    color, depth = images.read_image(color_img), images.read_image(depth_img)
    if color[1:3] != depth[1:3]:
        raise SetupError("The kept colour and depth images differ in size.")
    return color, depth


class DIFFUSION_DOF_OT_focus_map(bpy.types.Operator):
    """Show the focal-plane view of the last rendered frame with the current camera: in focus
    green, near blur orange, far blur blue (the image 'Diffusion DOF Focus Map'; the same as
    `ddof --focus-map`)"""
    bl_idname = "diffusion_dof.focus_map"
    bl_label = "Focal-Plane View"

    def execute(self, context):
        scene = context.scene
        settings = settings_mod.get(scene)
        try:
            (color, w, h, ch), (depth, _, _, dch) = _kept_passes()
            cam, _info = camera_mod.camera_settings(scene, settings)
            lib = binding.get_library()
            region = frame_inputs.scene_region(scene, w, h, strict=False)
            if region is None or region.cropped:
                if region is not None:
                    cam = dict(cam, **region.camera_fields())
                coc = lib.coc(w, h, depth, dch, cam)
                rgb, counts = lib.focus_map(w, h, color, ch, coc, cam)
            else:  # the border's pixels only; the rest of the frame black
                x, y, rw, rh = region.x, region.y, region.width, region.height
                coc = lib.coc(rw, rh, frame_region.crop(depth, w, dch, x, y, rw, rh), dch,
                              dict(cam, **region.camera_fields()))
                part, counts = lib.focus_map(rw, rh, frame_region.crop(color, w, ch, x, y, rw,
                                                                       rh), ch, coc)
                rgb = bytearray(w * h * 3)
                focus_map.paste_rgb(rgb, w, x, y, part, rw, rh)
                lib.focus_map_legend(cam, w, h, rgb)
            image = images.store_result(images.FOCUS_MAP_IMAGE, w, h, 4,
                                        focus_map.rgba_of(rgb, w, h), data=True)
        except (SetupError, binding.LibraryError, binding.DdofError) as err:
            self.report({"ERROR"}, str(err))
            return {"CANCELLED"}
        sharp, near, far = counts
        total = max(sharp + near + far, 1)
        self.report({"INFO"}, "Focal-plane view in '%s': %.0f%% in focus (green), %.0f%% near "
                    "blur (orange), %.0f%% far blur (blue)" % (
                        image.name, 100.0 * sharp / total, 100.0 * near / total,
                        100.0 * far / total))
        if not bpy.app.background:
            images.show_image(image)
        return {"FINISHED"}


class DIFFUSION_DOF_OT_pick_focus(bpy.types.Operator):
    """Click a pixel of the render, the result or the viewer in an image editor: the focus
    distance becomes that pixel's depth (from the last frame's kept Depth pass). Esc or right
    click cancels"""
    bl_idname = "diffusion_dof.pick_focus"
    bl_label = "Pick Focus"
    bl_options = {"REGISTER", "UNDO"}

    x: IntProperty(name="X", default=-1, description="Pixel column (from the left)")
    y: IntProperty(name="Y", default=-1, description="Pixel row (from the bottom)")

    def execute(self, context):
        scene = context.scene
        settings = settings_mod.get(scene)
        try:
            _color, (depth, w, h, dch) = _kept_passes()
        except SetupError as err:
            self.report({"ERROR"}, str(err))
            return {"CANCELLED"}
        z = focus_map.depth_at(depth, w, h, dch, self.x, self.y)
        if z is None:
            self.report({"ERROR"}, "No surface at pixel (%d, %d) of the %dx%d frame (the sky, "
                        "or outside it): pick another pixel." % (self.x, self.y, w, h))
            return {"CANCELLED"}
        cam = scene.camera
        where = "Diffusion DOF's focus override"
        if settings.override_focus or cam is None or cam.type != "CAMERA" or \
                cam.data.dof.focus_object is not None:
            # The camera's focus object would win over its focus distance: use the override.
            settings.override_focus = True
            settings.focus_distance = z
        else:
            cam.data.dof.focus_distance = z
            where = "camera '%s'" % cam.name
        self.report({"INFO"}, "Focus %.4g (scene units) from pixel (%d, %d), set on %s"
                    % (z, self.x, self.y, where))
        return {"FINISHED"}

    def invoke(self, context, _event):
        if images.DEPTH_IMAGE not in bpy.data.images:
            return self.execute(context)  # says what to do
        context.window_manager.modal_handler_add(self)
        if context.area is not None:
            context.area.header_text_set("Pick Focus: click a pixel in an image editor "
                                         "(Esc: cancel)")
        self._area = context.area
        return {"RUNNING_MODAL"}

    def _done(self):
        if getattr(self, "_area", None) is not None:
            try:
                self._area.header_text_set(None)
            except ReferenceError:
                pass

    def modal(self, context, event):
        if event.type in {"ESC", "RIGHTMOUSE"} and event.value == "PRESS":
            self._done()
            return {"CANCELLED"}
        if event.type != "LEFTMOUSE" or event.value != "PRESS":
            return {"PASS_THROUGH"}
        for area in context.window.screen.areas:
            if area.type != "IMAGE_EDITOR":
                continue
            for region in area.regions:
                if region.type == "WINDOW" and region.x <= event.mouse_x < region.x + \
                        region.width and region.y <= event.mouse_y < region.y + region.height:
                    u, v = region.view2d.region_to_view(event.mouse_x - region.x,
                                                        event.mouse_y - region.y)
                    _w, _h = bpy.data.images[images.DEPTH_IMAGE].size
                    pixel = focus_map.pixel_of(u, v, _w, _h)
                    if pixel is None:
                        return {"RUNNING_MODAL"}
                    self.x, self.y = pixel
                    self._done()
                    return self.execute(context)
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
        return images.INPUT_IMAGE in bpy.data.images and images.DEPTH_IMAGE in bpy.data.images

    def execute(self, context):
        fg = {}
        if context.scene.diffusion_dof.foreground_collection is not None and \
                images.FG_INPUT_IMAGE in bpy.data.images:
            fg = {"fg_color": images.FG_INPUT_IMAGE, "fg_depth": images.FG_DEPTH_IMAGE}
        try:
            bpy.ops.diffusion_dof.apply_images(color=images.INPUT_IMAGE, depth=images.DEPTH_IMAGE,
                                               output=images.RESULT_IMAGE, **fg)
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
           DIFFUSION_DOF_OT_focus_map, DIFFUSION_DOF_OT_pick_focus,
           DIFFUSION_DOF_OT_reapply, DIFFUSION_DOF_OT_setup,
           DIFFUSION_DOF_OT_pinhole, DIFFUSION_DOF_OT_reload_library)


# Registers CLASSES in order and unregisters them in reverse (Blender's own helper).
register, unregister = bpy.utils.register_classes_factory(CLASSES)
