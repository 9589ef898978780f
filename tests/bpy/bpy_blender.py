# SPDX-License-Identifier: GPL-3.0-or-later
"""`blender ARGS` for Blender as a Python module (PyPI's bpy has no executable): does what the
arguments the add-on's tests use do, in this order: -b (always background), --factory-startup,
--addons A,B (enable them; an extension's module name, e.g. bl_ext.user_default.diffusion_dof),
FILE.blend (open it), -f N (render frame N), -a (render the animation), --python FILE.

    python bpy_blender.py -b --factory-startup --addons NAME scene.blend -a
"""

import sys


def main(argv):
    import bpy  # first: it puts Blender's script folders on sys.path
    import addon_utils
    i = 0
    status = 0
    while i < len(argv):
        arg = argv[i]
        if arg in ("-b", "--background", "--factory-startup"):
            pass
        elif arg == "--addons":
            i += 1
            for name in argv[i].split(","):
                module = addon_utils.enable(name, default_set=True, handle_error=None)
                if module is None:
                    print("bpy_blender.py: could not enable add-on %s" % name, file=sys.stderr)
                    status = 1
        elif arg.endswith(".blend"):
            bpy.ops.wm.open_mainfile(filepath=arg, load_ui=False)
        elif arg in ("-f", "--render-frame"):
            i += 1
            bpy.context.scene.frame_set(int(argv[i]))
            bpy.ops.render.render(write_still=True)
        elif arg in ("-a", "--render-anim"):
            bpy.ops.render.render(animation=True)
        elif arg == "--python":
            i += 1
            with open(argv[i], encoding="utf-8") as f:
                exec(compile(f.read(), argv[i], "exec"), {"__name__": "__main__"})
        else:
            print("bpy_blender.py: argument %r is not supported" % arg, file=sys.stderr)
            return 2
        i += 1
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
