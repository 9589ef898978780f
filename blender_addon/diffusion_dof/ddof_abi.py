# SPDX-License-Identifier: GPL-3.0-or-later
"""The ctypes mirror of ddof.h (libddof/include/ddof.h, API version 0.9): its enums and defines,
its structures field by field, the prototypes of the functions the add-on calls, and the version
rule. No bpy and no loaded library: binding.py loads the library and calls it with these
structures; tests/blender/check_abi.py compares them with the C header's.
"""

import ctypes

# The ddof.h these structures mirror. A library is usable when its version is compatible (see
# version_compatible): the same major and a minor >= ours (structs are only appended, and a
# library accepts an older caller's layout: ddof.h, Conventions).
BINDING_VERSION = (0, 9)
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
                ("silhouettes", _enum),
                # version 0.9
                ("blurred_edges", _enum)]


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

c_ctx = ctypes.c_void_p  # ddof_context *

# name: (restype, argtypes)
PROTOTYPES = {
    "ddof_version_number": (ctypes.c_uint, []),
    "ddof_version_string": (ctypes.c_char_p, []),
    "ddof_status_string": (ctypes.c_char_p, [_enum]),
    "ddof_context_options_init_sized": (None, [ctypes.POINTER(ContextOptions), ctypes.c_size_t]),
    "ddof_context_create": (_enum, [ctypes.POINTER(ContextOptions), ctypes.POINTER(c_ctx)]),
    "ddof_context_free": (None, [c_ctx]),
    "ddof_context_thread_count": (ctypes.c_uint32, [c_ctx]),
    "ddof_context_last_error": (ctypes.c_char_p, [c_ctx]),
    "ddof_backend_name": (ctypes.c_char_p, [_enum]),
    "ddof_context_set_backend": (_enum, [c_ctx, _enum, ctypes.c_char_p]),
    "ddof_context_backend_info": (_enum, [c_ctx, ctypes.POINTER(BackendInfo)]),
    "ddof_camera_init_sized": (None, [ctypes.POINTER(Camera), ctypes.c_size_t]),
    "ddof_coc_from_camera": (_enum, [c_ctx, ctypes.POINTER(Camera), ctypes.POINTER(ImageIn),
                                     ctypes.POINTER(Image)]),
    "ddof_solver_name": (ctypes.c_char_p, [_enum]),
    "ddof_params_init_sized": (None, [ctypes.POINTER(Params), ctypes.c_size_t]),
    "ddof_params_init_preset_sized": (_enum, [ctypes.POINTER(Params), ctypes.c_size_t, _enum]),
    "ddof_param_bounds": (_enum, [ctypes.c_char_p, ctypes.POINTER(ctypes.c_double),
                                  ctypes.POINTER(ctypes.c_double)]),
    "ddof_preset_name": (ctypes.c_char_p, [_enum]),
    "ddof_params_check": (_enum, [c_ctx, ctypes.POINTER(Params)]),
    "ddof_camera_check": (_enum, [c_ctx, ctypes.POINTER(Camera)]),
    "ddof_frame_init_sized": (None, [ctypes.POINTER(Frame), ctypes.c_size_t]),
    "ddof_render_frame": (_enum, [c_ctx, ctypes.POINTER(Params), ctypes.POINTER(Frame),
                                  ctypes.POINTER(Image), ctypes.POINTER(Stats)]),
    "ddof_cards_params_init": (None, [ctypes.POINTER(CardsParams)]),
    "ddof_render_cards": (_enum, [c_ctx, ctypes.POINTER(CardsParams), ctypes.POINTER(Camera),
                                  ctypes.POINTER(Card), ctypes.c_uint32, ctypes.POINTER(Image)]),
}

# Experimental functions (ddof.h's DDOF_EXPERIMENTAL section: they may change between minor
# versions): used only when the library has them and is of the binding's own minor version.
EXPERIMENTAL_PROTOTYPES = {
    # Cryptomatte ranks for the silhouettes' split
    "ddof_render_frame_with_matte": (_enum, [c_ctx, ctypes.POINTER(Params), ctypes.POINTER(Frame),
                                             ctypes.POINTER(ImageIn), ctypes.POINTER(Image),
                                             ctypes.POINTER(Stats)]),
    # the focal-plane view and its aperture legend
    "ddof_focus_map": (_enum, [c_ctx, ctypes.POINTER(ImageIn), ctypes.POINTER(ImageIn),
                               ctypes.POINTER(Camera), ctypes.POINTER(ctypes.c_uint8),
                               ctypes.c_size_t, ctypes.POINTER(ctypes.c_uint64)]),
    "ddof_focus_map_legend": (_enum, [c_ctx, ctypes.POINTER(Camera), ctypes.c_uint32,
                                      ctypes.c_uint32, ctypes.POINTER(ctypes.c_uint8),
                                      ctypes.c_size_t]),
    # the last call's plan, whole (Stats.plan is cut at 512 bytes)
    "ddof_context_last_plan": (ctypes.c_char_p, [c_ctx]),
}

# ddof_render_frame_with_matte: the most (id, coverage) ranks a matte may hold per pixel.
MATTE_MAX_RANKS = 16


def version_tuple(number):
    """DDOF_VERSION_NUMBER (MAJOR * 10000 + MINOR * 100 + PATCH) as (major, minor, patch)."""
    return number // 10000, (number // 100) % 100, number % 100


def version_compatible(number, binding=BINDING_VERSION):
    """Whether a library of this ddof_version_number() fits structures written for `binding`."""
    major, minor, _ = version_tuple(number)
    return major == binding[0] and minor >= binding[1]
