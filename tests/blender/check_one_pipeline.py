# SPDX-License-Identifier: GPL-3.0-or-later
"""One frame, three callers, one result: the frame tests/exr/test_cli_backends.c (case foreground) ran
through ddof_render_frame and through the `ddof` command, with a foreground element, run once
more through the add-on's binding (Session.depth_of_field). The results must be bit-identical.

    python3 check_one_pipeline.py LIBDDOF.so SCRATCH_DIR_OF_cli_foreground
"""
import array
import os
import sys

# The binding alone (it is bpy-free; the package's __init__ is not).
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..",
                                "blender_addon", "diffusion_dof"))
import binding as b  # noqa: E402
import ddof_abi  # noqa: E402

W, H = 48, 32  # tests/exr/test_cli_backends.c


def read_floats(folder, name, count):
    values = array.array("f")
    with open(os.path.join(folder, name), "rb") as f:
        values.fromfile(f, count)
    return values


def main():
    library, folder = sys.argv[1], sys.argv[2]
    os.environ[b.ENV_VAR] = library
    lib = b.get_library(reload=True)
    n = W * H
    color = read_floats(folder, "one_pipeline_color.f32", n * 4)
    depth = read_floats(folder, "one_pipeline_depth.f32", n)
    fg = {"color": read_floats(folder, "one_pipeline_fg_color.f32", n * 4),
          "depth": read_floats(folder, "one_pipeline_fg_depth.f32", n), "depth_channels": 1}
    want = read_floats(folder, "one_pipeline_out.f32", n * 4)
    # camera_50mm(&camera, 2.0, 3.0) and params.substeps = 2 in test_cli_backends.c.
    camera = {"focal_length_mm": 50.0, "sensor_width_mm": 36.0, "fstop": 2.0,
              "focus_distance_m": 3.0}
    failures = []
    with lib.session(threads=2) as session:
        for attempt in range(2):  # the second frame reuses the context's working memory
            out, stats = session.depth_of_field(W, H, color, 4, depth, 1, camera,
                                                {"substeps": 2}, foreground=fg)
            differ = sum(1 for a, c in zip(out, want) if a != c)
            if differ:
                failures.append("frame %d: %d of %d values differ from the C call"
                                % (attempt, differ, len(want)))
            if not stats["effects"] & ddof_abi.EFFECT_FOREGROUND:
                failures.append("the foreground element did not run: %r" % stats["plan"])
        if out == color:
            failures.append("the frame was not blurred: the test would prove nothing")
    for f in failures:
        print("FAIL:", f)
    print("check_one_pipeline: %d failures" % len(failures))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
