# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's session with the ddof shared library: finding and loading it (version-checked),
the calls it makes (a frame, the CoC for the focus tools, cards, checks without pixels) and
their errors, through ctypes with the mirror of ddof.h in ddof_abi.py.

This module does not import bpy: it is the add-on's only contact with the C library and can be
used (and is tested) from a plain Python interpreter. Every parameter struct is filled by its
*_init_sized function first (at the size of the mirror, so a newer library never writes past
it), so fields the add-on does not set keep the library's defaults (and the quality presets are
the library's: ddof_params_init_preset, never values of the add-on's own). Pixel buffers are
array.array('f') objects (tightly packed floats, interleaved channels) handed to the library as
pointers: Python never touches a pixel.
"""

import array
import ctypes
import ctypes.util
import os
import sys

if __package__:
    from . import ddof_abi as abi
else:  # loaded as a plain module by a python3 without the package (tests/blender): beside it
    import ddof_abi as abi


# ---------------------------------------------------------------------------------------------
# Errors


def _ask_cancel(cancel, fraction):
    try:
        return bool(cancel(fraction))
    except Exception:  # a broken callback stops the call rather than raising through C
        return True


class LibraryError(Exception):
    """The library is missing, is not a ddof library, or has an incompatible version."""


class DdofError(Exception):
    """A ddof call returned an error status; str() is the library's own explanation."""

    def __init__(self, status, message):
        super().__init__(message)
        self.status = status


class Cancelled(DdofError):
    """The cancel function asked the library to stop (DDOF_ERROR_CANCELLED)."""


# ---------------------------------------------------------------------------------------------
# Finding and loading the library

ENV_VAR = "DDOF_LIBRARY"
_HERE = os.path.dirname(os.path.abspath(__file__))


def _library_file_names():
    if sys.platform.startswith("win"):
        return ["ddof.dll", "libddof.dll"]
    if sys.platform == "darwin":
        return ["libddof.dylib"]
    return ["libddof.so", abi.SONAME]


def find_library():
    """The path of the library to load: $DDOF_LIBRARY if set, else the one shipped next to this
    file (inside the installed add-on), else one installed system-wide. Raises LibraryError."""
    env = os.environ.get(ENV_VAR, "").strip()
    if env:
        if not os.path.isfile(env):
            raise LibraryError("%s is set to '%s', which is not a file. Point it at the built "
                               "libddof.so (e.g. build/libddof/libddof.so) or unset it."
                               % (ENV_VAR, env))
        return env
    for name in _library_file_names():
        path = os.path.join(_HERE, name)
        if os.path.isfile(path):
            return path
    system = ctypes.util.find_library("ddof")
    if system:
        return system
    raise LibraryError("The ddof library (%s) is not in the add-on folder %s and %s is not set. "
                       "Install the add-on from the zip made by blender_addon/build_zip.py (it "
                       "carries the library), or set %s to the path of a built libddof.so."
                       % (_library_file_names()[0], _HERE, ENV_VAR, ENV_VAR))


def _buffer_pointer(buf, start=0):
    """A float pointer to element `start` of an array.array('f') (or any writable buffer of
    floats)."""
    if len(buf) <= start:
        return ctypes.POINTER(ctypes.c_float)()
    return (ctypes.c_float * (len(buf) - start)).from_buffer(buf, 4 * start)


def _byte_pointer(buf):
    """A uint8 pointer to a bytearray (or any writable buffer of bytes)."""
    return (ctypes.c_uint8 * len(buf)).from_buffer(buf)


def _window_image(cls, buf, width, height, channels, window):
    """A ddof_image (cls Image) or ddof_image_in (ImageIn) of a tightly packed buffer, or with a
    window (x, y, frame width, frame height), of the buffer's width x height pixels at (x, y)
    through the library's row stride."""
    if window is None:
        return cls(_buffer_pointer(buf), width, height, channels, 0)
    x, y, frame_width, _frame_height = window
    return cls(_buffer_pointer(buf, (y * frame_width + x) * channels), width, height, channels,
               frame_width * channels * 4)


def _copy_buffer(buf):
    """A new float buffer with buf's values."""
    out = new_buffer(len(buf))
    if len(buf):
        ctypes.memmove(_buffer_pointer(out), _buffer_pointer(buf), 4 * len(buf))
    return out


def new_buffer(count):
    """A zero-filled float buffer of `count` elements."""
    return array.array("f", bytes(4 * count))


class Library:
    """A loaded, version-checked ddof library."""

    def __init__(self, path):
        self.path = path
        try:
            dll = ctypes.CDLL(path)
        except OSError as err:
            raise LibraryError("Could not load the ddof library '%s': %s" % (path, err)) from None
        # The version first: an older or newer library may lack (or change) other functions,
        # and its version says more than a missing symbol.
        for name in ("ddof_version_number", "ddof_version_string"):
            if not hasattr(dll, name):
                raise LibraryError("'%s' is not a ddof library: it has no function %s"
                                   % (path, name))
            fn = getattr(dll, name)
            fn.restype, fn.argtypes = abi.PROTOTYPES[name]
        self.version_number = dll.ddof_version_number()
        self.version = (dll.ddof_version_string() or b"?").decode("ascii", "replace")
        if not abi.version_compatible(self.version_number):
            raise LibraryError(
                "The ddof library '%s' is version %s, but this add-on was written for %d.%d "
                "(it needs the same major version and at least that minor). Install the add-on "
                "and library from the same build."
                % (path, self.version, abi.BINDING_VERSION[0], abi.BINDING_VERSION[1]))
        for name, (restype, argtypes) in abi.PROTOTYPES.items():
            if not hasattr(dll, name):
                raise LibraryError("'%s' (version %s) is not a usable ddof library: it has no "
                                   "function %s" % (path, self.version, name))
            fn = getattr(dll, name)
            fn.restype = restype
            fn.argtypes = argtypes
        self._dll = dll
        # Experimental calls may change between minor versions: only the binding's own.
        same_minor = abi.version_tuple(self.version_number)[:2] == abi.BINDING_VERSION
        for name, (restype, argtypes) in abi.EXPERIMENTAL_PROTOTYPES.items():
            if same_minor and hasattr(dll, name):
                fn = getattr(dll, name)
                fn.restype, fn.argtypes = restype, argtypes
        self.has_matte = same_minor and hasattr(dll, "ddof_render_frame_with_matte")
        self.has_last_plan = same_minor and hasattr(dll, "ddof_context_last_plan")
        self.has_focus_map = same_minor and hasattr(dll, "ddof_focus_map") and \
            hasattr(dll, "ddof_focus_map_legend")

    # -- small wrappers ----------------------------------------------------------------------

    def status_string(self, status):
        return self._dll.ddof_status_string(status).decode("utf-8", "replace")

    def solver_name(self, solver):
        name = self._dll.ddof_solver_name(solver)
        return name.decode("ascii") if name else "?"

    def default_camera(self):
        cam = abi.Camera()
        self._dll.ddof_camera_init_sized(ctypes.byref(cam), ctypes.sizeof(cam))
        return cam

    def default_params(self):
        params = abi.Params()
        self._dll.ddof_params_init_sized(ctypes.byref(params), ctypes.sizeof(params))
        return params

    def param_bounds(self, field):
        """(lowest, highest) that the library accepts for a numeric ddof_params field, inclusive
        (ddof_param_bounds). Raises KeyError for a name that has no range."""
        lowest, highest = ctypes.c_double(), ctypes.c_double()
        status = self._dll.ddof_param_bounds(field.encode("ascii"), ctypes.byref(lowest),
                                             ctypes.byref(highest))
        if status != abi.DDOF_OK:
            raise KeyError("ddof_params has no numeric field %r" % field)
        return lowest.value, highest.value

    def backend_name(self, kind):
        name = self._dll.ddof_backend_name(kind)
        return name.decode("ascii") if name else "?"

    def preset_name(self, preset):
        name = self._dll.ddof_preset_name(preset)
        return name.decode("ascii") if name else None

    def preset_params(self, preset):
        """The ddof_params of a preset ('preview', 'default', 'final' or its ddof_preset value),
        from ddof_params_init_preset: the values are the library's, chosen by its accuracy
        study. Raises ValueError for an unknown preset."""
        value = abi.PRESETS[preset] if isinstance(preset, str) else int(preset)
        params = abi.Params()
        status = self._dll.ddof_params_init_preset_sized(ctypes.byref(params),
                                                         ctypes.sizeof(params), value)
        if status != abi.DDOF_OK:
            raise ValueError("the ddof library has no preset %r (%s)"
                             % (preset, self.status_string(status)))
        return params

    def preset_summary(self, preset):
        """A preset's settings as names, for the UI: method, kernel, solver, substeps,
        beta_scale, background, background_levels, near_spread."""
        p = self.preset_params(preset)
        modes = {v: k for k, v in abi.LAYER_MODES.items()}
        methods = {v: k for k, v in abi.METHODS.items()}
        kernels = {v: k for k, v in abi.KERNELS.items()}
        return {"method": methods.get(p.method, "?"), "kernel": kernels.get(p.kernel, "?"),
                "solver": self.solver_name(p.solver),
                "substeps": p.substeps, "beta_scale": p.beta_scale,
                "background": modes.get(p.background, "?"),
                "background_levels": p.background_levels,
                "near_spread": modes.get(p.near_spread, "?")}

    def _context(self, threads, backend="cpu", plugin_path=None):
        """A new context with `threads` threads on `backend` (a name in BACKENDS). 'auto' never
        fails for want of a GPU (it runs on the CPU and says why); 'egl' or 'osmesa' that cannot
        be had raise DdofError with the library's reason."""
        options = abi.ContextOptions()
        self._dll.ddof_context_options_init_sized(ctypes.byref(options), ctypes.sizeof(options))
        options.thread_count = max(0, int(threads))
        ctx = abi.c_ctx()
        status = self._dll.ddof_context_create(ctypes.byref(options), ctypes.byref(ctx))
        if status != abi.DDOF_OK:
            raise DdofError(status, "could not create a ddof context: %s"
                            % self.status_string(status))
        kind = abi.BACKENDS[backend] if isinstance(backend, str) else int(backend)
        if kind != abi.BACKENDS["cpu"]:
            path = plugin_path.encode() if isinstance(plugin_path, str) else plugin_path
            status = self._dll.ddof_context_set_backend(ctx, kind, path)
            if status != abi.DDOF_OK:
                detail = self._dll.ddof_context_last_error(ctx).decode("utf-8", "replace")
                self._dll.ddof_context_free(ctx)
                raise DdofError(status, "the %s backend is not available: %s"
                                % (self.backend_name(kind), detail))
        return ctx

    def _backend_info(self, ctx):
        info = abi.BackendInfo()
        info.struct_size = ctypes.sizeof(abi.BackendInfo)
        if self._dll.ddof_context_backend_info(ctx, ctypes.byref(info)) != abi.DDOF_OK:
            return {"kind": abi.BACKENDS["cpu"], "hardware": 0, "renderer": "", "note": ""}
        return {"kind": info.kind, "hardware": info.hardware,
                "renderer": info.renderer.decode("utf-8", "replace"),
                "note": info.note.decode("utf-8", "replace")}

    def _check(self, ctx, status, what):
        if status == abi.DDOF_ERROR_CANCELLED:
            raise Cancelled(status, "%s: cancelled" % what)
        if status != abi.DDOF_OK:
            detail = self._dll.ddof_context_last_error(ctx).decode("utf-8", "replace")
            raise DdofError(status, "%s: %s%s" % (what, self.status_string(status),
                                                  (" (" + detail + ")") if detail else ""))

    # -- the job -------------------------------------------------------------------------------

    def coc(self, width, height, depth, depth_channels, camera, threads=0):
        """The signed CoC (px, negative in front of the focus) of a depth buffer for a camera
        dict (as depth_of_field takes): an array.array('f') of width * height, for the focus
        tools (the focus picker, the focal-plane view). Raises DdofError."""
        if len(depth) != width * height * depth_channels:
            raise ValueError("the depth buffer does not match %dx%d" % (width, height))
        cam = self.make_camera(camera)
        cam.signed_coc = 1
        out = new_buffer(width * height)
        depth_in = abi.ImageIn(_buffer_pointer(depth), width, height, depth_channels, 0)
        coc_img = abi.Image(_buffer_pointer(out), width, height, 1, 0)
        ctx = self._context(threads)
        try:
            self._check(ctx, self._dll.ddof_coc_from_camera(ctx, ctypes.byref(cam),
                                                           ctypes.byref(depth_in),
                                                           ctypes.byref(coc_img)),
                        "circle of confusion")
        finally:
            self._dll.ddof_context_free(ctx)
        return out

    def _need_focus_map(self):
        if not self.has_focus_map:
            raise LibraryError("The ddof library '%s' (version %s) has no focal-plane view of "
                               "this add-on's version (ddof_focus_map): install the add-on and "
                               "library from the same build." % (self.path, self.version))

    def focus_map(self, width, height, color, color_channels, coc, camera=None, threads=0):
        """The focal-plane view (ddof_focus_map): (rgb, (in focus, near, far)), rgb a bytearray
        of width * height * 3 bytes, rows top first, of a colour buffer (3 or 4 channels) and
        its signed CoC; with the aperture's legend when a camera dict is given. Raises
        DdofError, or LibraryError when the library has no such call."""
        self._need_focus_map()
        if len(color) != width * height * color_channels or len(coc) != width * height:
            raise ValueError("the colour or CoC buffer does not match %dx%d" % (width, height))
        rgb = bytearray(width * height * 3)
        counts = (ctypes.c_uint64 * 3)()
        color_in = abi.ImageIn(_buffer_pointer(color), width, height, color_channels, 0)
        coc_in = abi.ImageIn(_buffer_pointer(coc), width, height, 1, 0)
        cam = ctypes.byref(self.make_camera(camera)) if camera else None
        ctx = self._context(threads)
        try:
            self._check(ctx, self._dll.ddof_focus_map(ctx, ctypes.byref(color_in),
                                                      ctypes.byref(coc_in), cam,
                                                      _byte_pointer(rgb), len(rgb), counts),
                        "focal-plane view")
        finally:
            self._dll.ddof_context_free(ctx)
        return rgb, tuple(counts)

    def focus_map_legend(self, camera, width, height, rgb):
        """Draws the camera's aperture legend into a width x height RGB bytearray in place
        (ddof_focus_map_legend): for a view of a render border shown in the whole frame."""
        self._need_focus_map()
        ctx = self._context(1)
        try:
            self._check(ctx, self._dll.ddof_focus_map_legend(
                ctx, ctypes.byref(self.make_camera(camera)), width, height, _byte_pointer(rgb),
                len(rgb)), "focal-plane view's legend")
        finally:
            self._dll.ddof_context_free(ctx)

    def session(self, threads=0, backend="cpu", plugin_path=None):
        """A Session: one context kept for many frames (its threads, working memory and, on a
        GL backend, the loaded plugin and GL context). Close it, or use it in a with block."""
        return Session(self, threads, backend, plugin_path)

    def depth_of_field(self, width, height, color, color_channels, depth, depth_channels,
                       camera, params=None, threads=0, foreground=None, preset=None,
                       backend="cpu", plugin_path=None, cancel=None, matte=None):
        """One frame with a context of its own: Session.depth_of_field (see there)."""
        with self.session(threads, backend, plugin_path) as session:
            return session.depth_of_field(width, height, color, color_channels, depth,
                                          depth_channels, camera, params, foreground, preset,
                                          cancel, matte=matte)

    def make_camera(self, camera):
        """A ddof_camera from a dict of its fields (lens_model, sensor_fit as names)."""
        cam = self.default_camera()
        for key, value in camera.items():
            if key == "lens_model":
                value = abi.LENS_MODELS[value] if isinstance(value, str) else value
            elif key == "sensor_fit":
                value = abi.SENSOR_FITS[value] if isinstance(value, str) else value
            setattr(cam, key, value)
        return cam

    def make_params(self, params=None, preset=None):
        """ddof_params: the preset's (None: ddof_params_init), then the dict's fields over them
        (solver, background, near_spread, method, precision, kernel may be names)."""
        p = self.default_params() if preset is None else self.preset_params(preset)
        names = {"solver": abi.SOLVERS, "background": abi.LAYER_MODES,
                 "near_spread": abi.LAYER_MODES, "method": abi.METHODS,
                 "precision": abi.PRECISIONS, "kernel": abi.KERNELS}
        for key, value in (params or {}).items():
            if key in names and isinstance(value, str):
                value = names[key][value]
            setattr(p, key, value)
        return p


class Session:
    """One ddof context for the frames of a render: created once, freed by close()."""

    def __init__(self, library, threads=0, backend="cpu", plugin_path=None):
        self.library = library
        self.key = (max(0, int(threads)), backend, plugin_path)
        self._dll = library._dll
        self._ctx = library._context(threads, backend, plugin_path)
        self._info = library._backend_info(self._ctx)

    def close(self):
        if self._ctx:
            self._dll.ddof_context_free(self._ctx)
            self._ctx = None

    def __enter__(self):
        return self

    def __exit__(self, *_exc):
        self.close()

    def _last_error(self):
        return self._dll.ddof_context_last_error(self._ctx).decode("utf-8", "replace")

    def check_camera(self, camera):
        """None when the library accepts the camera (a dict), else its sentence."""
        status = self._dll.ddof_camera_check(self._ctx, ctypes.byref(self.library.make_camera(
            camera)))
        return None if status == abi.DDOF_OK else self._last_error()

    def check_params(self, params=None, preset=None):
        """None when the library accepts the params on this context's backend, else why."""
        p = self.library.make_params(params, preset)
        status = self._dll.ddof_params_check(self._ctx, ctypes.byref(p))
        return None if status == abi.DDOF_OK else self._last_error()

    def depth_of_field(self, width, height, color, color_channels, depth, depth_channels,
                       camera, params=None, foreground=None, preset=None, cancel=None,
                       window=None, matte=None):
        """Diffusion depth of field of one frame, in one ddof_render_frame call.

        color, depth: array.array('f') of width * height * channels floats (the depth's first
        channel is read). camera: a dict of ddof_camera fields (Library.make_camera). preset:
        None (ddof_params_init, the default preset) or a name in PRESETS; params: a dict of
        ddof_params fields over the preset's (Library.make_params). foreground: None, or a dict
        with 'color' (4 channels, RGB premultiplied by alpha) and 'depth' (+ 'depth_channels')
        of the same size: the separately rendered foreground element. cancel: None, or a
        function of the fraction done in [0, 1] returning True to stop (ddof_params.progress):
        the call then raises Cancelled. window: None, or (x, y, frame width, frame height): the
        buffers are frames of that size and the call covers their width x height pixels at
        (x, y), read and written through the library's row stride; out is then the colour
        frame with the window's result in it. matte: None (ddof_render_frame), or (buffer,
        channels) of the same size: per pixel channels / 2 ranks of (id, coverage) interleaved,
        Cryptomatte's ids bit for bit (ddof_render_frame_with_matte, experimental: used only
        with a library of the binding's own minor version, Library.has_matte; else ignored).
        Returns (out, stats): out an array.array('f') like color, stats a dict of ddof_stats
        plus 'backend_name', 'renderer', 'hardware', 'backend_note', 'method_name'. Raises
        DdofError with the library's message on bad input or combinations it refuses.
        """
        if window is not None and (min(window[:2]) < 0 or window[0] + width > window[2]
                                   or window[1] + height > window[3]):
            raise ValueError("the window %dx%d at (%d, %d) is outside its %dx%d frame"
                             % ((width, height) + tuple(window)))
        count = width * height if window is None else window[2] * window[3]
        if len(color) != count * color_channels or len(depth) != count * depth_channels:
            raise ValueError("buffer sizes do not match %dx%d" % (width, height))
        cam = self.library.make_camera(camera)
        p = self.library.make_params(params, preset)
        frame = abi.Frame()
        self._dll.ddof_frame_init_sized(ctypes.byref(frame), ctypes.sizeof(frame))
        frame.color = _window_image(abi.ImageIn, color, width, height, color_channels, window)
        frame.depth = _window_image(abi.ImageIn, depth, width, height, depth_channels, window)
        frame.camera = ctypes.pointer(cam)
        if foreground is not None:
            fg_color, fg_depth = foreground["color"], foreground["depth"]
            fg_depth_channels = foreground.get("depth_channels", depth_channels)
            if len(fg_color) != count * 4 or len(fg_depth) != count * fg_depth_channels:
                raise ValueError("foreground buffers do not match %dx%d" % (width, height))
            frame.foreground_color = _window_image(abi.ImageIn, fg_color, width, height, 4,
                                                   window)
            frame.foreground_depth = _window_image(abi.ImageIn, fg_depth, width, height,
                                                   fg_depth_channels, window)
        callback = None
        if cancel is not None:
            # Kept referenced until the call returns: ctypes frees an unreferenced callback.
            callback = abi.PROGRESS_FN(lambda _user, fraction:
                                       1 if _ask_cancel(cancel, fraction) else 0)
            p.progress = callback
        out = new_buffer(count * color_channels) if window is None else _copy_buffer(color)
        out_img = _window_image(abi.Image, out, width, height, color_channels, window)
        stats = abi.Stats()
        stats.struct_size = ctypes.sizeof(abi.Stats)
        matte_img = self._matte_image(matte, width, height, count, window)
        if matte_img is None:
            status = self._dll.ddof_render_frame(self._ctx, ctypes.byref(p), ctypes.byref(frame),
                                                 ctypes.byref(out_img), ctypes.byref(stats))
        else:
            status = self._dll.ddof_render_frame_with_matte(
                self._ctx, ctypes.byref(p), ctypes.byref(frame), ctypes.byref(matte_img),
                ctypes.byref(out_img), ctypes.byref(stats))
        del callback
        self.library._check(self._ctx, status, "depth of field")
        result = self._stats_dict(stats)
        result["matte_ranks"] = 0 if matte_img is None else matte_img.channels // 2
        return out, result

    def _matte_image(self, matte, width, height, count, window):
        """The ddof_image_in of a (buffer, channels) matte, or None (no matte, or a library
        without the experimental call of this binding's version)."""
        if matte is None or not self.library.has_matte:
            return None
        buf, channels = matte
        if len(buf) != count * channels:
            raise ValueError("the matte buffer does not match %dx%d" % (width, height))
        return _window_image(abi.ImageIn, buf, width, height, channels, window)

    def render_cards(self, width, height, camera, cards, strips=None):
        """Cards (docs/cards.md) seen through `camera` (a dict, Library.make_camera) into a
        width x height premultiplied RGBA image, in one ddof_render_cards call.

        cards: a list of dicts with 'positions' (3 to 8 (x, y, z) in camera space, metres,
        every z < 0), 'uv' (as many (u, v), (0, 0) the texture's bottom-left) and 'texture'
        (array.array('f'), premultiplied RGBA, row 0 at the top) with 'width' and 'height'.
        Returns an array.array('f') of width * height * 4, row 0 at the top. Raises DdofError
        with the library's message (naming the card) on bad input.
        """
        c_cards = (abi.Card * max(1, len(cards)))()
        for card, c in zip(cards, c_cards):
            n = len(card["positions"])
            if not 3 <= n <= abi.CARD_MAX_VERTICES or len(card["uv"]) != n:
                raise ValueError("a card needs 3 to %d positions and as many uv"
                                 % abi.CARD_MAX_VERTICES)
            if len(card["texture"]) != card["width"] * card["height"] * 4:
                raise ValueError("a card's texture does not match %dx%d RGBA"
                                 % (card["width"], card["height"]))
            c.vertex_count = n
            for k in range(n):
                for a in range(3):
                    c.position[k][a] = card["positions"][k][a]
                c.uv[k][0], c.uv[k][1] = card["uv"][k]
            c.texture = abi.ImageIn(_buffer_pointer(card["texture"]), card["width"],
                                    card["height"], 4, 0)
        params = abi.CardsParams()
        self._dll.ddof_cards_params_init(ctypes.byref(params))
        if strips is not None:
            params.strips = strips
        cam = self.library.make_camera(camera)
        out = new_buffer(width * height * 4)
        out_img = abi.Image(_buffer_pointer(out), width, height, 4, 0)
        status = self._dll.ddof_render_cards(self._ctx, ctypes.byref(params), ctypes.byref(cam),
                                             c_cards, len(cards), ctypes.byref(out_img))
        self.library._check(self._ctx, status, "cards")
        return out

    def _stats_dict(self, stats):
        info = self._info
        result = {name: getattr(stats, name) for name, _ in abi.Stats._fields_
                  if name not in ("struct_size", "plan")}
        # The whole plan where the library keeps it; Stats.plan is cut at 512 bytes.
        plan = self._dll.ddof_context_last_plan(self._ctx) if self.library.has_last_plan \
            else stats.plan
        result["plan"] = plan.decode("utf-8", "replace")
        result["solver_name"] = self.library.solver_name(stats.solver)
        result["effect_names"] = [name for bit, name in abi.EFFECT_NAMES if stats.effects & bit]
        result["method_name"] = {v: k for k, v in abi.METHODS.items()}.get(stats.method, "?")
        result["kernel_name"] = {v: k for k, v in abi.KERNELS.items()}.get(stats.kernel, "?")
        result["backend_name"] = self.library.backend_name(stats.backend)
        # The context's renderer, unless the call ran elsewhere (the CoD4 preview: the CPU).
        if stats.backend == info["kind"]:
            result["renderer"] = info["renderer"]
            result["hardware"] = bool(info["hardware"])
        else:
            result["renderer"] = "CPU, %d thread%s" % (stats.threads,
                                                       "" if stats.threads == 1 else "s")
            result["hardware"] = False
        result["backend_note"] = info["note"]
        return result


# ---------------------------------------------------------------------------------------------
# One library per process, loaded on first use.

_loaded = None
_load_error = None


def get_library(reload=False):
    """The loaded Library, or raises LibraryError (the same one again until reload=True)."""
    global _loaded, _load_error
    if reload:
        _loaded = _load_error = None
    if _loaded is not None:
        return _loaded
    if _load_error is not None:
        raise _load_error
    try:
        _loaded = Library(find_library())
    except LibraryError as err:
        _load_error = err
        raise
    return _loaded


def library_status(reload=False):
    """(ok, text): 'ddof 0.3.0 (path)' or the error message; never raises."""
    try:
        lib = get_library(reload)
    except LibraryError as err:
        return False, str(err)
    return True, "ddof %s (%s)" % (lib.version, lib.path)


def forget_library():
    """Drops the cached library (the add-on calls this when it is unregistered)."""
    global _loaded, _load_error
    _loaded = _load_error = None
