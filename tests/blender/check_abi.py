# SPDX-License-Identifier: GPL-3.0-or-later
"""The add-on's ctypes mirror of ddof.h matches the C structs, enums and version; the binding
loads the built library and runs one small frame. Plain python3, no Blender:

    python3 tests/blender/check_abi.py ABI_LAYOUT_EXECUTABLE LIBDDOF_SO
"""

import array
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
# The mirror and the binding alone (they are bpy-free; the package's __init__ is not).
sys.path.insert(0, os.path.join(HERE, "..", "..", "blender_addon", "diffusion_dof"))
import binding as b  # noqa: E402
import ddof_abi as abi  # noqa: E402


def addon_ranges():
    """The min and max of the add-on's settings that are ddof_params fields, read from
    settings.py's source (it imports bpy)."""
    import ast
    path = os.path.join(HERE, "..", "..", "blender_addon", "diffusion_dof", "settings.py")
    tree = ast.parse(open(path, encoding="utf-8").read())
    params = {name for name, _ in abi.Params._fields_}
    ranges = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name) and \
                node.target.id in params and isinstance(node.annotation, ast.Call):
            keywords = {k.arg: k.value for k in node.annotation.keywords}
            if "min" in keywords and "max" in keywords:
                ranges[node.target.id] = (ast.literal_eval(keywords["min"]),
                                          ast.literal_eval(keywords["max"]))
    if not ranges:
        raise SystemExit("no ddof_params slider found in settings.py")
    return ranges


def main():
    layout_exe, library = sys.argv[1], sys.argv[2]
    import ctypes

    failures = []
    lines = subprocess.run([layout_exe], check=True, capture_output=True,
                           text=True).stdout.splitlines()
    enums = {}
    version = None
    checked = 0
    for line in lines:
        words = line.split()
        if words[0] == "enum":
            enums[words[1]] = int(words[2])
            continue
        if words[0] == "version":
            version = int(words[1])
            continue
        name, size = words[0], int(words[1])
        cls = abi.STRUCTS.get(name)
        if cls is None:
            failures.append("%s has no ctypes mirror" % name)
            continue
        if ctypes.sizeof(cls) != size:
            failures.append("%s: sizeof C %d, ctypes %d" % (name, size, ctypes.sizeof(cls)))
        c_fields = []
        for item in words[2:]:
            field, offset, fsize = item.split(":")
            c_fields.append(field)
            desc = getattr(cls, field, None)
            if desc is None:
                failures.append("%s.%s missing in ctypes" % (name, field))
                continue
            if desc.offset != int(offset) or desc.size != int(fsize):
                failures.append("%s.%s: C offset %s size %s, ctypes offset %d size %d"
                                % (name, field, offset, fsize, desc.offset, desc.size))
            checked += 1
        py_fields = [f[0] for f in cls._fields_]
        if py_fields != c_fields:
            failures.append("%s: field order C %s, ctypes %s" % (name, c_fields, py_fields))
    if set(abi.STRUCTS) != {l.split()[0] for l in lines if l.split()[0] not in ("enum", "version")}:
        failures.append("the C dump and the binding list different structs")

    expect = {
        "DDOF_OK": abi.DDOF_OK, "DDOF_STATUS_COUNT_": len(abi.STATUS_NAMES),
        "DDOF_LENS_CYCLES": abi.LENS_CYCLES, "DDOF_LENS_THIN_LENS": abi.LENS_THIN_LENS,
        "DDOF_DEPTH_PLANAR": abi.DEPTH_PLANAR, "DDOF_DEPTH_RADIAL": abi.DEPTH_RADIAL,
        "DDOF_SENSOR_FIT_AUTO": abi.SENSOR_FIT_AUTO,
        "DDOF_SENSOR_FIT_HORIZONTAL": abi.SENSOR_FIT_HORIZONTAL,
        "DDOF_SENSOR_FIT_VERTICAL": abi.SENSOR_FIT_VERTICAL,
        "DDOF_SOLVER_THOMAS": abi.SOLVERS["thomas"],
        "DDOF_SOLVER_CYCLIC_REDUCTION": abi.SOLVERS["cr"],
        "DDOF_SOLVER_PCR": abi.SOLVERS["pcr"], "DDOF_SOLVER_JACOBI": abi.SOLVERS["jacobi"],
        "DDOF_SOLVER_REFERENCE_F64": abi.SOLVERS["reference"],
        "DDOF_SOLVER_GRUEN": abi.SOLVERS["gruen"], "DDOF_SOLVER_COUNT_": abi.SOLVER_COUNT,
        "DDOF_METHOD_DIFFUSION": abi.METHODS["diffusion"],
        "DDOF_METHOD_COD4_PREVIEW": abi.METHODS["cod4"],
        "DDOF_PRECISION_FLOAT": abi.PRECISIONS["float"],
        "DDOF_PRECISION_PACKED_HALF": abi.PRECISIONS["packed_half"],
        "DDOF_KERNEL_HEAT": abi.KERNELS["heat"],
        "DDOF_KERNEL_DISC_2X2": abi.KERNELS["disc-2x2"],
        "DDOF_KERNEL_DISC_2X3": abi.KERNELS["disc-2x3"],
        "DDOF_KERNEL_DISC_3X3": abi.KERNELS["disc-3x3"],
        "DDOF_PRESET_PREVIEW": abi.PRESETS["preview"],
        "DDOF_PRESET_DEFAULT": abi.PRESETS["default"],
        "DDOF_PRESET_FINAL": abi.PRESETS["final"], "DDOF_PRESET_COUNT_": abi.PRESET_COUNT,
        "DDOF_BACKEND_CPU": abi.BACKENDS["cpu"], "DDOF_BACKEND_AUTO": abi.BACKENDS["auto"],
        "DDOF_BACKEND_EGL": abi.BACKENDS["egl"], "DDOF_BACKEND_OSMESA": abi.BACKENDS["osmesa"],
        "DDOF_BACKEND_HOST_GL": abi.BACKENDS["host"], "DDOF_BACKEND_COUNT_": abi.BACKEND_COUNT,
        "DDOF_LAYER_AUTO": abi.LAYER_AUTO, "DDOF_LAYER_OFF": abi.LAYER_OFF,
        "DDOF_LAYER_ON": abi.LAYER_ON,
        "DDOF_EFFECT_MIDGROUND": abi.EFFECT_MIDGROUND,
        "DDOF_EFFECT_BACKGROUND": abi.EFFECT_BACKGROUND,
        "DDOF_EFFECT_FOREGROUND": abi.EFFECT_FOREGROUND,
        "DDOF_EFFECT_NEAR_SPREAD": abi.EFFECT_NEAR_SPREAD,
        "DDOF_EFFECT_HIGHLIGHTS": abi.EFFECT_HIGHLIGHTS,
        "DDOF_EFFECT_NEAR_LAYER": abi.EFFECT_NEAR_LAYER,
        "DDOF_EFFECT_FAR_FIELD": abi.EFFECT_FAR_FIELD,
        "DDOF_EFFECT_SILHOUETTES": abi.EFFECT_SILHOUETTES,
        "DDOF_CARDS_EXPAND_OFFSET": abi.CARDS_EXPAND_OFFSET,
        "DDOF_CARDS_EXPAND_CENTROID": abi.CARDS_EXPAND_CENTROID,
        "DDOF_CARD_MAX_VERTICES": abi.CARD_MAX_VERTICES,
        "DDOF_MATTE_MAX_RANKS": abi.MATTE_MAX_RANKS,
    }
    # Every status by name, in order.
    for value, name in enumerate(abi.STATUS_NAMES):
        expect[name] = value
    for name, value in expect.items():
        if enums.get(name) != value:
            failures.append("%s: C %s, binding %s" % (name, enums.get(name), value))
    unchecked = set(enums) - set(expect)
    if unchecked:
        failures.append("C enums the binding does not mirror: %s" % sorted(unchecked))
    if version is None or abi.version_tuple(version)[:2] != abi.BINDING_VERSION:
        failures.append("header version %s, binding %s" % (version, abi.BINDING_VERSION))

    # The add-on's bl_info version follows the library's major.minor.
    sys.path.insert(0, os.path.join(HERE, "..", "..", "blender_addon"))
    import build_zip
    addon_version = tuple(int(v) for v in build_zip.addon_version().split("."))
    if addon_version[:2] != abi.BINDING_VERSION:
        failures.append("bl_info version %s, binding %s" % (addon_version, abi.BINDING_VERSION))

    # Version rule: the same major, a minor at least the binding's.
    major, minor = abi.BINDING_VERSION
    own = major * 10000 + minor * 100
    for number, ok in ((own, True), (own + 5, True), (own + 100, True), (own - 100, False),
                       (own + 10000, False)):
        if abi.version_compatible(number) != ok:
            failures.append("version_compatible(%d) should be %s" % (number, ok))

    # The real library through the binding: names, one frame, and an error message.
    os.environ[b.ENV_VAR] = library
    lib = b.get_library(reload=True)
    if lib.version_number != version:
        failures.append("library %d, header %d" % (lib.version_number, version))
    for name, value in abi.SOLVERS.items():
        if lib.solver_name(value) != name:
            failures.append("solver %d is %r in the library" % (value, lib.solver_name(value)))
    for name, value in abi.BACKENDS.items():
        if lib.backend_name(value) != name:
            failures.append("backend %d is %r in the library" % (value, lib.backend_name(value)))
    for name, value in abi.PRESETS.items():
        if lib.preset_name(value) != name:
            failures.append("preset %d is %r in the library" % (value, lib.preset_name(value)))
    # The add-on's sliders stay within what the library accepts (ddof_param_bounds).
    for field, (lowest, highest) in addon_ranges().items():
        low, high = lib.param_bounds(field)
        if lowest < low or highest > high:
            failures.append("the add-on's %s slider %g..%g leaves the library's %g..%g"
                            % (field, lowest, highest, low, high))
    try:
        lib.param_bounds("solver")
        failures.append("param_bounds('solver') gave a range")
    except KeyError:
        pass
    # Presets are the library's: ddof_params_init_preset through ctypes, default = params_init.
    default = lib.default_params()
    if bytes(lib.preset_params("default")) != bytes(default):
        failures.append("the default preset differs from ddof_params_init")
    try:
        lib.preset_params(abi.PRESET_COUNT)
        failures.append("an unknown preset was accepted")
    except ValueError:
        pass
    w, h = 64, 32
    color = b.new_buffer(w * h * 4)
    depth = b.new_buffer(w * h)
    for y in range(h):
        for x in range(w):
            i = y * w + x
            checker = float((x // 4 + y // 4) % 2)
            color[4 * i:4 * i + 4] = b.array.array("f", [checker, 0.5, 0.25, 1.0])
            depth[i] = 2.0 if x < w // 2 else 20.0
    # 100 mm f/1 focused at 2 m: CoC about 8 px at 20 m on a 64-pixel-wide 36 mm sensor.
    camera = {"lens_model": "CYCLES", "focal_length_mm": 100.0, "sensor_width_mm": 36.0,
              "fstop": 1.0, "focus_distance_m": 2.0, "sensor_fit": "AUTO"}
    out, stats = lib.depth_of_field(w, h, color, 4, depth, 1, camera,
                                    {"substeps": 2, "kernel": "heat"})
    left = [out[4 * (y * w + x)] for y in range(h) for x in range(w // 2 - 4)]
    right = [out[4 * (y * w + x)] for y in range(h) for x in range(w // 2 + 8, w)]
    if left != [color[4 * (y * w + x)] for y in range(h) for x in range(w // 2 - 4)]:
        failures.append("in-focus half changed")
    right_in = [color[4 * (y * w + x)] for y in range(h) for x in range(w // 2 + 8, w)]

    def spread(values):
        mean = sum(values) / len(values)
        return math.sqrt(sum((v - mean) ** 2 for v in values) / len(values))
    if spread(right) > 0.6 * spread(right_in):
        failures.append("out-of-focus half not blurred (spread %g of %g)"
                        % (spread(right), spread(right_in)))
    if "midground: on" not in stats["plan"] or stats["substeps"] != 2:
        failures.append("unexpected stats %r" % stats)
    # The plan comes whole from the context (ddof_context_last_plan), not cut at 512 bytes.
    if not lib.has_last_plan:
        failures.append("the binding does not read the whole plan (ddof_context_last_plan)")
    # depth_of_field(preset=...) is the preset's parameters, with params overriding them.
    final = lib.preset_params("final")
    fields = {name: getattr(final, name) for name, _ in abi.Params._fields_
              if name not in ("struct_size", "progress", "progress_user")}
    out_final, stats_final = lib.depth_of_field(w, h, color, 4, depth, 1, camera, preset="final")
    out_fields, _ = lib.depth_of_field(w, h, color, 4, depth, 1, camera, fields)
    if out_final != out_fields or stats_final["kernel"] != final.kernel:
        failures.append("preset='final' is not ddof_params_init_preset(FINAL)")
    _, stats_over = lib.depth_of_field(w, h, color, 4, depth, 1, camera,
                                       {"kernel": "heat", "substeps": 3}, preset="final")
    if stats_over["substeps"] != 3 or stats_over["kernel_name"] != "heat":
        failures.append("params do not override the preset: %r" % stats_over["substeps"])
    # Backends: cpu reports itself; auto runs somewhere and says where; an explicit GL backend
    # whose plugin is missing is an error with the library's reason, not a crash.
    if stats["backend_name"] != "cpu" or not stats["renderer"].startswith("CPU, ") or \
            stats["backend_note"] or stats["method_name"] != "diffusion":
        failures.append("cpu backend stats: %r" % stats)
    out_auto, stats_auto = lib.depth_of_field(w, h, color, 4, depth, 1, camera,
                                              {"substeps": 2, "kernel": "heat"}, backend="auto")
    if not stats_auto["backend_note"].startswith("auto: ") or not stats_auto["renderer"]:
        failures.append("auto backend stats: %r" % stats_auto)
    if stats_auto["backend_name"] == "cpu" and out_auto != out:
        failures.append("auto on the CPU differs from cpu")
    for kind in ("osmesa", "egl"):
        try:
            lib.depth_of_field(w, h, color, 4, depth, 1, camera, backend=kind,
                               plugin_path="/nonexistent/libddof_gl.so")
            failures.append("%s with a missing plugin ran" % kind)
        except b.DdofError as err:
            if err.status != abi.DDOF_ERROR_BACKEND_UNAVAILABLE or \
                    "/nonexistent/libddof_gl.so" not in str(err):
                failures.append("%s with a missing plugin: %s" % (kind, err))
    try:
        lib.depth_of_field(w, h, color, 4, depth, 1, camera, {"solver": "gruen"})
        failures.append("gruen ran on the CPU")
    except b.DdofError as err:
        if err.status != abi.DDOF_ERROR_UNSUPPORTED:
            failures.append("gruen on the CPU: %s" % err)
    _, stats_cod4 = lib.depth_of_field(w, h, color, 4, depth, 1, camera, {"method": "cod4"})
    if stats_cod4["method_name"] != "cod4" or stats_cod4["backend_name"] != "cpu":
        failures.append("cod4 stats: %r" % stats_cod4)
    depth[5] = -1.0
    try:
        lib.depth_of_field(w, h, color, 4, depth, 1, camera)
        failures.append("negative depth accepted")
    except b.DdofError as err:
        if "depth" not in str(err) or "(5, 0)" not in str(err):
            failures.append("unclear error: %s" % err)
    depth[5] = 2.0
    # Cards through the binding: an in-focus card whose texture's top half is 0.8 and bottom
    # half 0.2 (row 0 at the top) covers the frame's middle: above the middle reads 0.8, below
    # 0.2, a corner nothing; a card behind the camera is an error naming it.
    tex = b.new_buffer(4 * 4 * 4)
    for i in range(16):
        tex[4 * i:4 * i + 4] = b.array.array("f", [0.8 if i < 8 else 0.2, 0.0, 0.0, 1.0])
    half = 0.5 * 36.0 / 100.0 * 2.0 * 0.4  # 40 % of the frame's half width at 2 m
    card = {"positions": [(-half, -half, -2.0), (half, -half, -2.0), (half, half, -2.0),
                          (-half, half, -2.0)],
            "uv": [(0, 0), (1, 0), (1, 1), (0, 1)], "texture": tex, "width": 4, "height": 4}
    with lib.session() as session:
        cards_out = session.render_cards(w, h, camera, [card])
        above, below = cards_out[4 * ((h // 2 - 3) * w + w // 2)], \
            cards_out[4 * ((h // 2 + 2) * w + w // 2)]
        if abs(above - 0.8) > 1e-5 or abs(below - 0.2) > 1e-5 or cards_out[3] != 0.0:
            failures.append("cards: above %g below %g corner alpha %g" % (above, below,
                                                                       cards_out[3]))
        behind = dict(card, positions=[(x, y, 1.0) for x, y, _ in card["positions"]])
        try:
            session.render_cards(w, h, camera, [card, behind])
            failures.append("a card behind the camera was drawn")
        except b.DdofError as err:
            if "card 1" not in str(err):
                failures.append("cards error: %s" % err)
    fg_color = b.new_buffer(w * h * 4)
    fg_depth = b.array.array("f", [1e10] * (w * h))
    for y in range(8, 16):
        for x in range(40, 48):  # a near square in front of the far half
            fg_color[4 * (y * w + x):4 * (y * w + x) + 4] = b.array.array("f", [1, 1, 1, 1])
            fg_depth[y * w + x] = 1.0
    out2, stats2 = lib.depth_of_field(w, h, color, 4, depth, 1, camera, {},
                                      foreground={"color": fg_color, "depth": fg_depth,
                                                  "depth_channels": 1})
    if not stats2["effects"] & abi.EFFECT_FOREGROUND or any(math.isnan(v) for v in out2):
        failures.append("foreground path: %r" % stats2)
    # The CoD4 preview takes no foreground element: the library refuses it (one rule, in C).
    try:
        lib.depth_of_field(w, h, color, 4, depth, 1, camera, {"method": "cod4"},
                           foreground={"color": fg_color, "depth": fg_depth,
                                       "depth_channels": 1})
        failures.append("cod4 with a foreground element ran")
    except b.DdofError as err:
        if err.status != abi.DDOF_ERROR_UNSUPPORTED or "foreground" not in str(err):
            failures.append("cod4 with a foreground element: %s" % err)
    # A session keeps one context for many frames: the same results as fresh contexts.
    with lib.session(threads=2) as session:
        again = [session.depth_of_field(w, h, color, 4, depth, 1, camera,
                                        {"substeps": 2, "kernel": "heat"})[0]
                 for _ in range(2)]
        if again[0] != out or again[1] != out:
            failures.append("a session's frames differ from a fresh context's")
        if session.check_camera(camera) is not None:
            failures.append("a good camera judged bad: %s" % session.check_camera(camera))
        problem = session.check_camera(dict(camera, fstop=0.0))
        if not problem or "f" not in problem:
            failures.append("f/0 not judged bad: %r" % problem)
        if session.check_params({"beta_scale": 5.0}) is None:
            failures.append("beta_scale 5 not judged bad")
        if session.check_params({"solver": "gruen"}) is None:
            failures.append("gruen on the CPU not judged bad")
        # Cancelling from the progress callback: DDOF_ERROR_CANCELLED, and the call stops.
        seen = []
        try:
            session.depth_of_field(w, h, color, 4, depth, 1, camera, {},
                                   cancel=lambda f: seen.append(f) or True)
            failures.append("a cancelled call returned normally")
        except b.DdofError as err:
            if err.status != abi.DDOF_ERROR_CANCELLED or not seen:
                failures.append("cancel: %s after %r" % (err, seen))
    if session._ctx is not None:
        failures.append("the session's context was not freed")

    # The focal-plane view through the binding (tests/test_focus_map.c has the arithmetic):
    # in focus green, near orange, far blue; the bands counted; a hexagon's legend of 514
    # white pixels on a 200x120 map, drawn by the map with a camera and by the legend call.
    if not lib.has_focus_map:
        failures.append("the library has no ddof_focus_map of the binding's version")
    else:
        rgb, counts = lib.focus_map(3, 1, array.array("f", [0.5] * 9),
                                    3, array.array("f", [0.2, -8.0, 8.0]))
        pixels = [tuple(rgb[i:i + 3]) for i in (0, 3, 6)]
        if counts != (1, 1, 1) or not (pixels[0][1] > max(pixels[0][0], pixels[0][2]) and
                                       pixels[1][0] > max(pixels[1][1:]) and
                                       pixels[2][2] > max(pixels[2][:2])):
            failures.append("focus map %r, counts %r" % (pixels, counts))
        hexagon = {"aperture_blades": 6, "aperture_rotation_deg": 15.0}
        rgb, _ = lib.focus_map(200, 120, array.array("f", [0.5] * (200 * 120 * 3)), 3,
                               array.array("f", [5.0] * (200 * 120)), hexagon)
        legend = bytearray(200 * 120 * 3)
        lib.focus_map_legend(hexagon, 200, 120, legend)
        white = sum(1 for i in range(0, len(legend), 3) if legend[i] == 255)
        mapped = sum(1 for i in range(0, len(rgb), 3) if rgb[i] == 255)
        if white != 514 or mapped != 514:
            failures.append("hexagon legend: %d white pixels, the map %d (want 514)"
                            % (white, mapped))
        try:
            lib.focus_map(2, 1, array.array("f", [0.5] * 4), 2, array.array("f", [1.0, 2.0]))
            failures.append("a two-channel colour made a focus map")
        except b.DdofError as err:
            if "RGB" not in str(err):
                failures.append("two-channel focus map: %s" % err)

    # A library that is not ddof.
    os.environ[b.ENV_VAR] = "/nonexistent/libddof.so"
    ok, text = b.library_status(reload=True)
    if ok or "DDOF_LIBRARY" not in text:
        failures.append("missing library message: %s" % text)

    for f in failures:
        print("FAIL:", f)
    print("check_abi: %d fields checked, %d failures" % (checked, len(failures)))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
