# SPDX-License-Identifier: GPL-3.0-or-later
"""ctypes binding of the ddof shared library (libddof/include/ddof.h, API version 0.7).

This module does not import bpy: it is the add-on's only contact with the C library and can be
used (and is tested) from a plain Python interpreter. The structures mirror ddof.h field by field;
every parameter struct is filled by its *_init_sized function first (at the size of this mirror,
so a newer library never writes past it), so fields the add-on does not set
keep the library's defaults (and the quality presets are the library's: ddof_params_init_preset,
never values of the add-on's own). Pixel buffers are array.array('f') objects (tightly packed floats,
interleaved channels) handed to the library as pointers: Python never touches a pixel.
"""

import array
import ctypes
import ctypes.util
import os
import sys

# The ddof.h these structures mirror. A library is usable when its version is compatible (see
# version_compatible): the same major and a minor >= ours (structs are only appended, and a
# library accepts an older caller's layout: ddof.h, Conventions).
BINDING_VERSION = (0, 8)
# The soname of the ABI line (libddof/CMakeLists.txt), a name the library may be installed under.
SONAME = "libddof.so.0.5"

# ---------------------------------------------------------------------------------------------
# Constants (ddof.h enums and defines)

DDOF_OK = 0
STATUS_NAMES = (
    "DDOF_OK", "DDOF_ERROR_NULL_POINTER", "DDOF_ERROR_BAD_PARAMETER", "DDOF_ERROR_BAD_SIZE",
    "DDOF_ERROR_BAD_STRIDE", "DDOF_ERROR_BAD_CHANNELS", "DDOF_ERROR_SIZE_MISMATCH",
    "DDOF_ERROR_BAD_COLOR", "DDOF_ERROR_BAD_DEPTH", "DDOF_ERROR_BAD_COC",
    "DDOF_ERROR_BAD_CAMERA", "DDOF_ERROR_OUT_OF_MEMORY", "DDOF_ERROR_THREADS",
    "DDOF_ERROR_CANCELLED", "DDOF_ERROR_BACKEND_UNAVAILABLE", "DDOF_ERROR_UNSUPPORTED",
    "DDOF_ERROR_BACKEND_FAILED", "DDOF_ERROR_CONTEXT_BUSY",
)
DDOF_ERROR_BACKEND_UNAVAILABLE = STATUS_NAMES.index("DDOF_ERROR_BACKEND_UNAVAILABLE")
DDOF_ERROR_UNSUPPORTED = STATUS_NAMES.index("DDOF_ERROR_UNSUPPORTED")
DDOF_ERROR_CANCELLED = STATUS_NAMES.index("DDOF_ERROR_CANCELLED")
DDOF_ERROR_BACKEND_FAILED = STATUS_NAMES.index("DDOF_ERROR_BACKEND_FAILED")

# ddof_backend_kind, by ddof_backend_name()
BACKENDS = {"cpu": 0, "auto": 1, "egl": 2, "osmesa": 3, "host": 4}
BACKEND_COUNT = 5

LENS_CYCLES = 0
LENS_THIN_LENS = 1
LENS_MODELS = {"CYCLES": LENS_CYCLES, "THIN_LENS": LENS_THIN_LENS}

DEPTH_PLANAR = 0
DEPTH_RADIAL = 1

SENSOR_FIT_AUTO = 0
SENSOR_FIT_HORIZONTAL = 1
SENSOR_FIT_VERTICAL = 2
SENSOR_FITS = {"AUTO": SENSOR_FIT_AUTO, "HORIZONTAL": SENSOR_FIT_HORIZONTAL,
               "VERTICAL": SENSOR_FIT_VERTICAL}

SOLVERS = {"thomas": 0, "cr": 1, "pcr": 2, "jacobi": 3, "reference": 4, "gruen": 5}
SOLVER_COUNT = 6

# ddof_method: the diffusion, or the Call of Duty 4 preview (fast, approximate, CPU only)
METHODS = {"diffusion": 0, "cod4": 1}
METHOD_DIFFUSION = 0
METHOD_COD4_PREVIEW = 1

# ddof_kernel: the point spread (heat: the soft real diffusion; disc-*: the lens's disc)
KERNELS = {"heat": 0, "disc-2x2": 1, "disc-2x3": 2, "disc-3x3": 3}

# ddof_precision of the GL solvers
PRECISIONS = {"float": 0, "packed_half": 1}

# ddof_preset, by ddof_preset_name(): the settings are the library's (ddof_params_init_preset)
PRESETS = {"preview": 0, "default": 1, "final": 2}
PRESET_COUNT = 3

LAYER_AUTO = 0
LAYER_OFF = 1
LAYER_ON = 2
LAYER_MODES = {"AUTO": LAYER_AUTO, "OFF": LAYER_OFF, "ON": LAYER_ON}

# Cards (the experimental ddof_render_cards, docs/cards.md)
CARD_MAX_VERTICES = 8
CARDS_EXPAND_OFFSET = 0
CARDS_EXPAND_CENTROID = 1

EFFECT_MIDGROUND = 1
EFFECT_BACKGROUND = 2
EFFECT_FOREGROUND = 4
EFFECT_NEAR_SPREAD = 8
EFFECT_HIGHLIGHTS = 16
EFFECT_NEAR_LAYER = 32
EFFECT_FAR_FIELD = 64
EFFECT_SILHOUETTES = 128
EFFECT_NAMES = ((EFFECT_MIDGROUND, "midground"), (EFFECT_BACKGROUND, "background"),
                (EFFECT_FOREGROUND, "foreground"), (EFFECT_NEAR_SPREAD, "near spread"),
                (EFFECT_HIGHLIGHTS, "highlights"), (EFFECT_NEAR_LAYER, "near layer"),
                (EFFECT_FAR_FIELD, "far field"), (EFFECT_SILHOUETTES, "silhouettes"))

# ---------------------------------------------------------------------------------------------
# Structures. C enums are int-sized on every platform Blender runs on.

_enum = ctypes.c_int


class Image(ctypes.Structure):
    """ddof_image: caller-owned float pixels, interleaved channels."""
    _fields_ = [("pixels", ctypes.POINTER(ctypes.c_float)),
                ("width", ctypes.c_uint32),
                ("height", ctypes.c_uint32),
                ("channels", ctypes.c_uint32),
                ("row_stride", ctypes.c_size_t)]


class ImageIn(ctypes.Structure):
    """ddof_image_in: the same, read only."""
    _fields_ = Image._fields_


class Allocator(ctypes.Structure):
    _fields_ = [("alloc", ctypes.CFUNCTYPE(ctypes.c_void_p, ctypes.c_void_p, ctypes.c_size_t)),
                ("free", ctypes.CFUNCTYPE(None, ctypes.c_void_p, ctypes.c_void_p)),
                ("user", ctypes.c_void_p)]


PROGRESS_FN = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_void_p, ctypes.c_float)


class ContextOptions(ctypes.Structure):
    _fields_ = [("struct_size", ctypes.c_uint32),
                ("thread_count", ctypes.c_uint32),
                ("allocator", ctypes.POINTER(Allocator))]


class Camera(ctypes.Structure):
    _fields_ = [("struct_size", ctypes.c_uint32),
                ("lens_model", _enum),
                ("depth_kind", _enum),
                ("sensor_fit", _enum),
                ("focal_length_mm", ctypes.c_double),
                ("sensor_width_mm", ctypes.c_double),
                ("fstop", ctypes.c_double),
                ("focus_distance_m", ctypes.c_double),
                ("pixel_aspect", ctypes.c_double),
                ("depth_unit_m", ctypes.c_double),
                ("signed_coc", ctypes.c_uint32),
                # version 0.5 of this struct: a crop of the full frame (a render border)
                ("frame_width", ctypes.c_uint32),
                ("frame_height", ctypes.c_uint32),
                ("window_x", ctypes.c_int32),
                ("window_y", ctypes.c_int32),
                # version 0.7: the aperture's shape (Blender's Blades, Rotation, Ratio)
                ("aperture_blades", ctypes.c_uint32),
                ("aperture_rotation_deg", ctypes.c_double),
                ("aperture_ratio", ctypes.c_double),
                ("aperture_catseye", ctypes.c_double),
                ("aperture_image", ctypes.POINTER(ctypes.c_float)),
                ("aperture_image_width", ctypes.c_uint32),
                ("aperture_image_height", ctypes.c_uint32)]


class Curve(ctypes.Structure):
    _fields_ = [("struct_size", ctypes.c_uint32),
                ("near_blur_px", ctypes.c_double),
                ("near_start", ctypes.c_double),
                ("near_end", ctypes.c_double),
                ("far_start", ctypes.c_double),
                ("far_end", ctypes.c_double),
                ("far_blur_px", ctypes.c_double),
                ("signed_coc", ctypes.c_uint32)]


class Params(ctypes.Structure):
    _fields_ = [("struct_size", ctypes.c_uint32),
                ("solver", _enum),
                ("substeps", ctypes.c_uint32),
                ("beta_scale", ctypes.c_float),
                ("pixel_aspect", ctypes.c_float),
                ("jacobi_iterations", ctypes.c_uint32),
                ("progress", PROGRESS_FN),
                ("progress_user", ctypes.c_void_p),
                # version 0.2: layers
                ("coc_signed", ctypes.c_uint32),
                ("background", _enum),
                ("background_threshold_px", ctypes.c_float),
                ("background_ramp_start_px", ctypes.c_float),
                ("background_levels", ctypes.c_uint32),
                ("near_spread", _enum),
                ("near_spread_threshold_px", ctypes.c_float),
                # version 0.3
                ("method", _enum),
                ("precision", _enum),
                # version 0.4
                ("kernel", _enum),
                # version 0.5
                ("in_focus_threshold_px", ctypes.c_float),
                ("highlights", _enum),
                ("highlight_threshold", ctypes.c_float),
                # version 0.6
                ("near_layer", _enum),
                ("near_layer_threshold_px", ctypes.c_float),
                # version 0.8
                ("far_field", _enum),
                ("silhouettes", _enum)]


class Stats(ctypes.Structure):
    _fields_ = [("struct_size", ctypes.c_uint32),
                ("solver", ctypes.c_uint32),
                ("threads", ctypes.c_uint32),
                ("substeps", ctypes.c_uint32),
                ("lines_solved", ctypes.c_uint64),
                ("lines_skipped", ctypes.c_uint64),
                ("max_coc_px", ctypes.c_float),
                ("copied_only", ctypes.c_uint32),
                ("seconds_total", ctypes.c_double),
                ("seconds_coc", ctypes.c_double),
                ("seconds_rows", ctypes.c_double),
                ("seconds_columns", ctypes.c_double),
                # version 0.2: layers
                ("effects", ctypes.c_uint32),
                ("seconds_plan", ctypes.c_double),
                ("seconds_background", ctypes.c_double),
                ("seconds_foreground", ctypes.c_double),
                ("plan", ctypes.c_char * 512),
                # version 0.3
                ("backend", ctypes.c_uint32),
                ("method", ctypes.c_uint32),
                ("device_bytes", ctypes.c_uint64),
                ("host_bytes", ctypes.c_uint64),
                # version 0.4
                ("kernel", ctypes.c_uint32),
                # version 0.5
                ("device_uploads", ctypes.c_uint32),
                ("device_readbacks", ctypes.c_uint32),
                ("seconds_highlights", ctypes.c_double),
                # version 0.6
                ("seconds_near_layer", ctypes.c_double),
                # version 0.8
                ("seconds_far_field", ctypes.c_double),
                ("seconds_silhouettes", ctypes.c_double)]


class Foreground(ctypes.Structure):
    _fields_ = [("struct_size", ctypes.c_uint32),
                ("color", ImageIn),
                ("coc", ImageIn),
                ("premultiplied", ctypes.c_uint32)]


class Frame(ctypes.Structure):
    """ddof_frame: what ddof_render_frame takes; images with pixels NULL are absent."""
    _fields_ = [("struct_size", ctypes.c_uint32),
                ("color", ImageIn),
                ("depth", ImageIn),
                ("camera", ctypes.POINTER(Camera)),
                ("curve", ctypes.POINTER(Curve)),
                ("coc", ImageIn),
                ("foreground_color", ImageIn),
                ("foreground_depth", ImageIn),
                ("foreground_coc", ImageIn),
                ("foreground_premultiplied", ctypes.c_uint32),
                ("coc_out", Image)]


class BackendInfo(ctypes.Structure):
    """ddof_backend_info: the backend a context runs on, its renderer, why AUTO chose it."""
    _fields_ = [("struct_size", ctypes.c_uint32),
                ("kind", ctypes.c_uint32),
                ("hardware", ctypes.c_uint32),
                ("renderer", ctypes.c_char * 128),
                ("note", ctypes.c_char * 256)]


class Card(ctypes.Structure):
    """ddof_card: a convex polygon in camera space (metres, looking down -z), its uv (0, 0 the
    texture's bottom-left) and its premultiplied RGBA texture, row 0 at the top."""
    _fields_ = [("vertex_count", ctypes.c_uint32),
                ("position", (ctypes.c_float * 3) * CARD_MAX_VERTICES),
                ("uv", (ctypes.c_float * 2) * CARD_MAX_VERTICES),
                ("texture", ImageIn)]


class CardsParams(ctypes.Structure):
    """ddof_cards_params."""
    _fields_ = [("struct_size", ctypes.c_uint32),
                ("expansion", _enum),
                ("strips", ctypes.c_uint32)]


# Every struct by its C name, for the ABI check (tests/blender/check_abi.py).
STRUCTS = {"ddof_image": Image, "ddof_image_in": ImageIn, "ddof_allocator": Allocator,
           "ddof_context_options": ContextOptions, "ddof_camera": Camera, "ddof_curve": Curve,
           "ddof_params": Params, "ddof_stats": Stats, "ddof_foreground": Foreground,
           "ddof_frame": Frame, "ddof_backend_info": BackendInfo, "ddof_card": Card,
           "ddof_cards_params": CardsParams}

_c_ctx = ctypes.c_void_p  # ddof_context *

# name: (restype, argtypes)
_PROTOTYPES = {
    "ddof_version_number": (ctypes.c_uint, []),
    "ddof_version_string": (ctypes.c_char_p, []),
    "ddof_status_string": (ctypes.c_char_p, [_enum]),
    "ddof_context_options_init_sized": (None, [ctypes.POINTER(ContextOptions), ctypes.c_size_t]),
    "ddof_context_create": (_enum, [ctypes.POINTER(ContextOptions), ctypes.POINTER(_c_ctx)]),
    "ddof_context_free": (None, [_c_ctx]),
    "ddof_context_thread_count": (ctypes.c_uint32, [_c_ctx]),
    "ddof_context_last_error": (ctypes.c_char_p, [_c_ctx]),
    "ddof_backend_name": (ctypes.c_char_p, [_enum]),
    "ddof_context_set_backend": (_enum, [_c_ctx, _enum, ctypes.c_char_p]),
    "ddof_context_backend_info": (_enum, [_c_ctx, ctypes.POINTER(BackendInfo)]),
    "ddof_camera_init_sized": (None, [ctypes.POINTER(Camera), ctypes.c_size_t]),
    "ddof_coc_from_camera": (_enum, [_c_ctx, ctypes.POINTER(Camera), ctypes.POINTER(ImageIn),
                                     ctypes.POINTER(Image)]),
    "ddof_solver_name": (ctypes.c_char_p, [_enum]),
    "ddof_params_init_sized": (None, [ctypes.POINTER(Params), ctypes.c_size_t]),
    "ddof_params_init_preset_sized": (_enum, [ctypes.POINTER(Params), ctypes.c_size_t, _enum]),
    "ddof_param_bounds": (_enum, [ctypes.c_char_p, ctypes.POINTER(ctypes.c_double),
                                  ctypes.POINTER(ctypes.c_double)]),
    "ddof_preset_name": (ctypes.c_char_p, [_enum]),
    "ddof_params_check": (_enum, [_c_ctx, ctypes.POINTER(Params)]),
    "ddof_camera_check": (_enum, [_c_ctx, ctypes.POINTER(Camera)]),
    "ddof_frame_init_sized": (None, [ctypes.POINTER(Frame), ctypes.c_size_t]),
    "ddof_render_frame": (_enum, [_c_ctx, ctypes.POINTER(Params), ctypes.POINTER(Frame),
                                  ctypes.POINTER(Image), ctypes.POINTER(Stats)]),
    "ddof_cards_params_init": (None, [ctypes.POINTER(CardsParams)]),
    "ddof_render_cards": (_enum, [_c_ctx, ctypes.POINTER(CardsParams), ctypes.POINTER(Camera),
                                  ctypes.POINTER(Card), ctypes.c_uint32, ctypes.POINTER(Image)]),
}

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


def version_tuple(number):
    """DDOF_VERSION_NUMBER (MAJOR * 10000 + MINOR * 100 + PATCH) as (major, minor, patch)."""
    return number // 10000, (number // 100) % 100, number % 100


def version_compatible(number, binding=BINDING_VERSION):
    """Whether a library of this ddof_version_number() fits structures written for `binding`."""
    major, minor, _ = version_tuple(number)
    return major == binding[0] and minor >= binding[1]


# ---------------------------------------------------------------------------------------------
# Finding and loading the library

ENV_VAR = "DDOF_LIBRARY"
_HERE = os.path.dirname(os.path.abspath(__file__))


def _library_file_names():
    if sys.platform.startswith("win"):
        return ["ddof.dll", "libddof.dll"]
    if sys.platform == "darwin":
        return ["libddof.dylib"]
    return ["libddof.so", SONAME]


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


def _buffer_pointer(buf):
    """A float pointer to the first element of an array.array('f') (or any writable buffer)."""
    if len(buf) == 0:
        return ctypes.POINTER(ctypes.c_float)()
    return (ctypes.c_float * len(buf)).from_buffer(buf)


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
            fn.restype, fn.argtypes = _PROTOTYPES[name]
        self.version_number = dll.ddof_version_number()
        self.version = (dll.ddof_version_string() or b"?").decode("ascii", "replace")
        if not version_compatible(self.version_number):
            raise LibraryError(
                "The ddof library '%s' is version %s, but this add-on was written for %d.%d "
                "(it needs the same major version and at least that minor). Install the add-on "
                "and library from the same build." % (path, self.version, BINDING_VERSION[0],
                                                       BINDING_VERSION[1]))
        for name, (restype, argtypes) in _PROTOTYPES.items():
            if not hasattr(dll, name):
                raise LibraryError("'%s' (version %s) is not a usable ddof library: it has no "
                                   "function %s" % (path, self.version, name))
            fn = getattr(dll, name)
            fn.restype = restype
            fn.argtypes = argtypes
        self._dll = dll

    # -- small wrappers ----------------------------------------------------------------------

    def status_string(self, status):
        return self._dll.ddof_status_string(status).decode("utf-8", "replace")

    def solver_name(self, solver):
        name = self._dll.ddof_solver_name(solver)
        return name.decode("ascii") if name else "?"

    def default_camera(self):
        cam = Camera()
        self._dll.ddof_camera_init_sized(ctypes.byref(cam), ctypes.sizeof(cam))
        return cam

    def default_params(self):
        params = Params()
        self._dll.ddof_params_init_sized(ctypes.byref(params), ctypes.sizeof(params))
        return params

    def param_bounds(self, field):
        """(lowest, highest) that the library accepts for a numeric ddof_params field, inclusive
        (ddof_param_bounds). Raises KeyError for a name that has no range."""
        lowest, highest = ctypes.c_double(), ctypes.c_double()
        status = self._dll.ddof_param_bounds(field.encode("ascii"), ctypes.byref(lowest),
                                             ctypes.byref(highest))
        if status != DDOF_OK:
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
        value = PRESETS[preset] if isinstance(preset, str) else int(preset)
        params = Params()
        status = self._dll.ddof_params_init_preset_sized(ctypes.byref(params),
                                                         ctypes.sizeof(params), value)
        if status != DDOF_OK:
            raise ValueError("the ddof library has no preset %r (%s)"
                             % (preset, self.status_string(status)))
        return params

    def preset_summary(self, preset):
        """A preset's settings as names, for the UI: method, kernel, solver, substeps,
        beta_scale, background, background_levels, near_spread."""
        p = self.preset_params(preset)
        modes = {v: k for k, v in LAYER_MODES.items()}
        methods = {v: k for k, v in METHODS.items()}
        kernels = {v: k for k, v in KERNELS.items()}
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
        options = ContextOptions()
        self._dll.ddof_context_options_init_sized(ctypes.byref(options), ctypes.sizeof(options))
        options.thread_count = max(0, int(threads))
        ctx = _c_ctx()
        status = self._dll.ddof_context_create(ctypes.byref(options), ctypes.byref(ctx))
        if status != DDOF_OK:
            raise DdofError(status, "could not create a ddof context: %s"
                            % self.status_string(status))
        kind = BACKENDS[backend] if isinstance(backend, str) else int(backend)
        if kind != BACKENDS["cpu"]:
            path = plugin_path.encode() if isinstance(plugin_path, str) else plugin_path
            status = self._dll.ddof_context_set_backend(ctx, kind, path)
            if status != DDOF_OK:
                detail = self._dll.ddof_context_last_error(ctx).decode("utf-8", "replace")
                self._dll.ddof_context_free(ctx)
                raise DdofError(status, "the %s backend is not available: %s"
                                % (self.backend_name(kind), detail))
        return ctx

    def _backend_info(self, ctx):
        info = BackendInfo()
        info.struct_size = ctypes.sizeof(BackendInfo)
        if self._dll.ddof_context_backend_info(ctx, ctypes.byref(info)) != DDOF_OK:
            return {"kind": BACKENDS["cpu"], "hardware": 0, "renderer": "", "note": ""}
        return {"kind": info.kind, "hardware": info.hardware,
                "renderer": info.renderer.decode("utf-8", "replace"),
                "note": info.note.decode("utf-8", "replace")}

    def _check(self, ctx, status, what):
        if status == DDOF_ERROR_CANCELLED:
            raise Cancelled(status, "%s: cancelled" % what)
        if status != DDOF_OK:
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
        depth_in = ImageIn(_buffer_pointer(depth), width, height, depth_channels, 0)
        coc_img = Image(_buffer_pointer(out), width, height, 1, 0)
        ctx = self._context(threads)
        try:
            self._check(ctx, self._dll.ddof_coc_from_camera(ctx, ctypes.byref(cam),
                                                           ctypes.byref(depth_in),
                                                           ctypes.byref(coc_img)),
                        "circle of confusion")
        finally:
            self._dll.ddof_context_free(ctx)
        return out

    def session(self, threads=0, backend="cpu", plugin_path=None):
        """A Session: one context kept for many frames (its threads, working memory and, on a
        GL backend, the loaded plugin and GL context). Close it, or use it in a with block."""
        return Session(self, threads, backend, plugin_path)

    def depth_of_field(self, width, height, color, color_channels, depth, depth_channels,
                       camera, params=None, threads=0, foreground=None, preset=None,
                       backend="cpu", plugin_path=None, cancel=None):
        """One frame with a context of its own: Session.depth_of_field (see there)."""
        with self.session(threads, backend, plugin_path) as session:
            return session.depth_of_field(width, height, color, color_channels, depth,
                                          depth_channels, camera, params, foreground, preset,
                                          cancel)

    def make_camera(self, camera):
        """A ddof_camera from a dict of its fields (lens_model, sensor_fit as names)."""
        cam = self.default_camera()
        for key, value in camera.items():
            if key == "lens_model":
                value = LENS_MODELS[value] if isinstance(value, str) else value
            elif key == "sensor_fit":
                value = SENSOR_FITS[value] if isinstance(value, str) else value
            setattr(cam, key, value)
        return cam

    def make_params(self, params=None, preset=None):
        """ddof_params: the preset's (None: ddof_params_init), then the dict's fields over them
        (solver, background, near_spread, method, precision, kernel may be names)."""
        p = self.default_params() if preset is None else self.preset_params(preset)
        names = {"solver": SOLVERS, "background": LAYER_MODES, "near_spread": LAYER_MODES,
                 "method": METHODS, "precision": PRECISIONS, "kernel": KERNELS}
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
        return None if status == DDOF_OK else self._last_error()

    def check_params(self, params=None, preset=None):
        """None when the library accepts the params on this context's backend, else why."""
        p = self.library.make_params(params, preset)
        status = self._dll.ddof_params_check(self._ctx, ctypes.byref(p))
        return None if status == DDOF_OK else self._last_error()

    def depth_of_field(self, width, height, color, color_channels, depth, depth_channels,
                       camera, params=None, foreground=None, preset=None, cancel=None):
        """Diffusion depth of field of one frame, in one ddof_render_frame call.

        color, depth: array.array('f') of width * height * channels floats (the depth's first
        channel is read). camera: a dict of ddof_camera fields (Library.make_camera). preset:
        None (ddof_params_init, the default preset) or a name in PRESETS; params: a dict of
        ddof_params fields over the preset's (Library.make_params). foreground: None, or a dict
        with 'color' (4 channels, RGB premultiplied by alpha) and 'depth' (+ 'depth_channels')
        of the same size: the separately rendered foreground element. cancel: None, or a
        function of the fraction done in [0, 1] returning True to stop (ddof_params.progress):
        the call then raises Cancelled.
        Returns (out, stats): out an array.array('f') like color, stats a dict of ddof_stats
        plus 'backend_name', 'renderer', 'hardware', 'backend_note', 'method_name'. Raises
        DdofError with the library's message on bad input or combinations it refuses.
        """
        count = width * height
        if len(color) != count * color_channels or len(depth) != count * depth_channels:
            raise ValueError("buffer sizes do not match %dx%d" % (width, height))
        cam = self.library.make_camera(camera)
        p = self.library.make_params(params, preset)
        frame = Frame()
        self._dll.ddof_frame_init_sized(ctypes.byref(frame), ctypes.sizeof(frame))
        frame.color = ImageIn(_buffer_pointer(color), width, height, color_channels, 0)
        frame.depth = ImageIn(_buffer_pointer(depth), width, height, depth_channels, 0)
        frame.camera = ctypes.pointer(cam)
        if foreground is not None:
            fg_color, fg_depth = foreground["color"], foreground["depth"]
            fg_depth_channels = foreground.get("depth_channels", depth_channels)
            if len(fg_color) != count * 4 or len(fg_depth) != count * fg_depth_channels:
                raise ValueError("foreground buffers do not match %dx%d" % (width, height))
            frame.foreground_color = ImageIn(_buffer_pointer(fg_color), width, height, 4, 0)
            frame.foreground_depth = ImageIn(_buffer_pointer(fg_depth), width, height,
                                             fg_depth_channels, 0)
        callback = None
        if cancel is not None:
            # Kept referenced until the call returns: ctypes frees an unreferenced callback.
            callback = PROGRESS_FN(lambda _user, fraction: 1 if _ask_cancel(cancel, fraction)
                                   else 0)
            p.progress = callback
        out = new_buffer(count * color_channels)
        out_img = Image(_buffer_pointer(out), width, height, color_channels, 0)
        stats = Stats()
        stats.struct_size = ctypes.sizeof(Stats)
        status = self._dll.ddof_render_frame(self._ctx, ctypes.byref(p), ctypes.byref(frame),
                                             ctypes.byref(out_img), ctypes.byref(stats))
        del callback
        self.library._check(self._ctx, status, "depth of field")
        return out, self._stats_dict(stats)

    def render_cards(self, width, height, camera, cards, strips=None):
        """Cards (docs/cards.md) seen through `camera` (a dict, Library.make_camera) into a
        width x height premultiplied RGBA image, in one ddof_render_cards call.

        cards: a list of dicts with 'positions' (3 to 8 (x, y, z) in camera space, metres,
        every z < 0), 'uv' (as many (u, v), (0, 0) the texture's bottom-left) and 'texture'
        (array.array('f'), premultiplied RGBA, row 0 at the top) with 'width' and 'height'.
        Returns an array.array('f') of width * height * 4, row 0 at the top. Raises DdofError
        with the library's message (naming the card) on bad input.
        """
        c_cards = (Card * max(1, len(cards)))()
        for card, c in zip(cards, c_cards):
            n = len(card["positions"])
            if not 3 <= n <= CARD_MAX_VERTICES or len(card["uv"]) != n:
                raise ValueError("a card needs 3 to %d positions and as many uv"
                                 % CARD_MAX_VERTICES)
            if len(card["texture"]) != card["width"] * card["height"] * 4:
                raise ValueError("a card's texture does not match %dx%d RGBA"
                                 % (card["width"], card["height"]))
            c.vertex_count = n
            for k in range(n):
                for a in range(3):
                    c.position[k][a] = card["positions"][k][a]
                c.uv[k][0], c.uv[k][1] = card["uv"][k]
            c.texture = ImageIn(_buffer_pointer(card["texture"]), card["width"],
                                card["height"], 4, 0)
        params = CardsParams()
        self._dll.ddof_cards_params_init(ctypes.byref(params))
        if strips is not None:
            params.strips = strips
        cam = self.library.make_camera(camera)
        out = new_buffer(width * height * 4)
        out_img = Image(_buffer_pointer(out), width, height, 4, 0)
        status = self._dll.ddof_render_cards(self._ctx, ctypes.byref(params), ctypes.byref(cam),
                                             c_cards, len(cards), ctypes.byref(out_img))
        self.library._check(self._ctx, status, "cards")
        return out

    def _stats_dict(self, stats):
        info = self._info
        result = {name: getattr(stats, name) for name, _ in Stats._fields_
                  if name not in ("struct_size", "plan")}
        result["plan"] = stats.plan.decode("utf-8", "replace")
        result["solver_name"] = self.library.solver_name(stats.solver)
        result["effect_names"] = [name for bit, name in EFFECT_NAMES if stats.effects & bit]
        result["method_name"] = {v: k for k, v in METHODS.items()}.get(stats.method, "?")
        result["kernel_name"] = {v: k for k, v in KERNELS.items()}.get(stats.kernel, "?")
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
