# SPDX-License-Identifier: GPL-3.0-or-later
"""Shared by the Blender background-mode tests (imported inside Blender, not a test itself).

The tests run as
    blender -b --factory-startup --python-exit-code 1 --python tests/blender/test_X.py
with DDOF_LIBRARY pointing at the built library (ctest passes $<TARGET_FILE:ddof>) and
DDOF_TEST_SCRATCH at a folder they may write to. Each builds its scene procedurally and renders
with Cycles on the CPU at 160x90 with emission-only materials and no bounces, so a few samples
are enough and nothing depends on lighting noise.
"""

import array
import math
import os
import sys
import tempfile

import bpy

from plain_checks import Checks  # noqa: F401 (the tests use it as u.Checks)

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.abspath(os.path.join(HERE, "..", ".."))
ADDON_DIR = os.path.join(REPO, "blender_addon")
WIDTH, HEIGHT = 160, 90


def scratch_dir(name):
    base = os.environ.get("DDOF_TEST_SCRATCH") or tempfile.mkdtemp(prefix="ddof-blender-")
    path = os.path.join(base, name)
    os.makedirs(path, exist_ok=True)
    return path


# ---------------------------------------------------------------------------------------------
# The Blender the tests run in: the `blender` executable (tests/blender, ctest label `blender`),
# or Blender as a Python module from PyPI (tests/bpy/run_bpy.py sets DDOF_BLENDER_HOST=bpy and
# runs these same scripts with the venv's python; label `bpy`). With the module, the add-on is
# the extension package, validated and installed by Blender's own extension tooling.

BPY_MODULE = os.environ.get("DDOF_BLENDER_HOST") == "bpy"
EXTENSION_REPO = "user_default"
EXTENSION_MODULE = "bl_ext.%s.diffusion_dof" % EXTENSION_REPO


def blender_ext_script():
    """Blender's own extension command-line tool (what `blender --command extension` runs)."""
    for base in bpy.utils.script_paths():
        path = os.path.join(base, "addons_core", "bl_pkg", "cli", "blender_ext.py")
        if os.path.isfile(path):
            return path
    raise RuntimeError("this Blender has no bl_pkg/cli/blender_ext.py")


def build_extension(library, folder):
    """The extension package built as the build builds it; returns its path."""
    if ADDON_DIR not in sys.path:
        sys.path.insert(0, ADDON_DIR)
    import build_zip
    path, _ = build_zip.build_extension(library, os.path.join(folder, "ext"))
    return path


def validate_extension(path):
    """(ok, output) of Blender's extension validator on a package file."""
    import subprocess
    proc = subprocess.run([sys.executable, blender_ext_script(), "validate", path],
                          capture_output=True, text=True, timeout=120)
    return proc.returncode == 0, (proc.stdout + proc.stderr).strip()


def install_extension(enable=True):
    """Builds, validates and installs the extension into the user repository with Blender's
    operator (Preferences > Get Extensions > Install from Disk); returns the module."""
    import importlib
    library = os.environ["DDOF_LIBRARY"]
    path = build_extension(library, scratch_dir("extension"))
    ok, text = validate_extension(path)
    if not ok:
        raise RuntimeError("Blender's validator refused %s: %s" % (path, text))
    result = bpy.ops.extensions.package_install_files(filepath=path, repo=EXTENSION_REPO,
                                                      enable_on_install=enable)
    if result != {"FINISHED"}:
        raise RuntimeError("installing %s: %s" % (path, result))
    return importlib.import_module(EXTENSION_MODULE)


def addon_module():
    """The add-on's package, imported (not registered): from the source tree with the
    executable, the installed extension with the module."""
    if BPY_MODULE:
        return install_extension(enable=False)
    if ADDON_DIR not in sys.path:
        sys.path.insert(0, ADDON_DIR)
    import diffusion_dof
    return diffusion_dof


def load_addon():
    """The add-on, registered: blender_addon/diffusion_dof from the source tree with the
    executable, the installed and enabled extension with the module."""
    if BPY_MODULE:
        return install_extension(enable=True)
    addon = addon_module()
    addon.register()
    return addon


def unload_addon(addon):
    """Unregisters what load_addon() registered (with the module through addon_utils, which
    would otherwise unregister it again at exit)."""
    if BPY_MODULE:
        import addon_utils
        addon_utils.disable(EXTENSION_MODULE, default_set=True)
    else:
        addon.unregister()


def blender_command(*args):
    """The command line of a Blender run in the background: `blender ARGS`, or with the module
    tests/bpy/bpy_blender.py, which does what those arguments do."""
    if BPY_MODULE:
        return [sys.executable, os.path.join(REPO, "tests", "bpy", "bpy_blender.py")] + list(args)
    return [bpy.app.binary_path] + list(args)


def compositor_tree(scene):
    """The scene's compositor tree in this Blender (it differs from 5.0 on)."""
    if hasattr(scene, "compositing_node_group"):
        return scene.compositing_node_group
    return scene.node_tree


def ensure_compositor_tree(scene):
    """The scene's compositor tree, made (and turned on) when it has none."""
    if hasattr(scene, "compositing_node_group"):
        if scene.compositing_node_group is None:
            scene.compositing_node_group = bpy.data.node_groups.new("Compositing",
                                                                    "CompositorNodeTree")
        return scene.compositing_node_group
    scene.use_nodes = True
    return scene.node_tree


def composite_from(scene, socket):
    """Makes the compositor output `socket` (e.g. the render layers' Depth) as the image."""
    tree = ensure_compositor_tree(scene)
    if hasattr(scene, "compositing_node_group"):
        if not any(i.in_out == "OUTPUT" for i in tree.interface.items_tree):
            tree.interface.new_socket("Image", in_out="OUTPUT", socket_type="NodeSocketColor")
        out = next((n for n in tree.nodes if n.bl_idname == "NodeGroupOutput"), None)
        if out is None:
            out = tree.nodes.new("NodeGroupOutput")
    else:
        out = next(n for n in tree.nodes if n.bl_idname == "CompositorNodeComposite")
    tree.links.new(socket, out.inputs[0])
    return out


def render_layers_node(scene):
    """The scene's own Render Layers node (not the add-on's), made if there is none."""
    tree = ensure_compositor_tree(scene)
    node = next((n for n in tree.nodes if n.bl_idname == "CompositorNodeRLayers"
                 and not n.name.startswith("DDOF")), None)
    if node is None:
        node = tree.nodes.new("CompositorNodeRLayers")
    return node


# ---------------------------------------------------------------------------------------------
# Scenes


def clear_scene():
    scene = bpy.context.scene
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    for blocks in (bpy.data.meshes, bpy.data.materials, bpy.data.cameras, bpy.data.lights):
        for block in list(blocks):
            blocks.remove(block)
    world = scene.world or bpy.data.worlds.new("World")
    scene.world = world
    world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (0.3, 0.45, 0.7, 1.0)
    background.inputs["Strength"].default_value = 1.0
    return scene


def emission_checker(name, color1, color2, scale):
    """An emission material with a checker in object coordinates: exact colours, no lights."""
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    out = nodes.new("ShaderNodeOutputMaterial")
    coord = nodes.new("ShaderNodeTexCoord")
    checker = nodes.new("ShaderNodeTexChecker")
    checker.inputs["Scale"].default_value = scale
    checker.inputs["Color1"].default_value = color1
    checker.inputs["Color2"].default_value = color2
    emission = nodes.new("ShaderNodeEmission")
    links.new(coord.outputs["Object"], checker.inputs["Vector"])
    links.new(checker.outputs["Color"], emission.inputs["Color"])
    links.new(emission.outputs["Emission"], out.inputs["Surface"])
    return mat


def add_plane(scene, name, size, location, material, collection=None):
    """A width x height plane facing the camera (which looks along +Y) at `location`; the mesh
    is built at full size, so object-space textures are in metres."""
    mesh = bpy.data.meshes.new(name)
    w, h = 0.5 * size[0], 0.5 * size[1]
    mesh.from_pydata([(-w, 0, -h), (w, 0, -h), (w, 0, h), (-w, 0, h)], [], [(0, 1, 2, 3)])
    mesh.materials.append(material)
    obj = bpy.data.objects.new(name, mesh)
    obj.location = location
    (collection or scene.collection).objects.link(obj)
    return obj


def add_camera(scene, lens=100.0, fstop=1.4, focus=3.0, sensor=36.0, lens_dof=False):
    data = bpy.data.cameras.new("Camera")
    data.lens = lens
    data.sensor_width = sensor
    data.sensor_fit = "AUTO"
    data.clip_start = 0.05
    data.clip_end = 1000.0
    data.dof.use_dof = lens_dof
    data.dof.focus_distance = focus
    data.dof.aperture_fstop = fstop
    data.dof.aperture_blades = 0
    data.dof.aperture_ratio = 1.0
    cam = bpy.data.objects.new("Camera", data)
    cam.location = (0.0, 0.0, 0.0)
    cam.rotation_euler = (math.radians(90.0), 0.0, 0.0)  # looking along +Y
    scene.collection.objects.link(cam)
    scene.camera = cam
    return cam


def configure(scene, samples, seed=1):
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = samples
    c.use_denoising = False
    c.use_adaptive_sampling = False
    c.seed = seed
    c.max_bounces = 0  # emission only: camera rays see exact colours
    if hasattr(c, "use_light_tree"):
        c.use_light_tree = False
    r = scene.render
    r.resolution_x, r.resolution_y, r.resolution_percentage = WIDTH, HEIGHT, 100
    r.pixel_aspect_x = r.pixel_aspect_y = 1.0
    r.film_transparent = False
    r.use_sequencer = False
    r.threads_mode = "AUTO"
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    r.dither_intensity = 0.0
    s = r.image_settings
    s.file_format = "OPEN_EXR"
    s.color_depth = "32"
    s.color_mode = "RGBA"
    s.exr_codec = "ZIP"


# ---------------------------------------------------------------------------------------------
# Pixels


def pixels(image):
    buf = array.array("f", bytes(4 * image.size[0] * image.size[1] * image.channels))
    image.pixels.foreach_get(buf)
    return buf


def load_file(path):
    """(buffer, width, height, channels) of an image file, raw values, no colour transform."""
    image = bpy.data.images.load(path, check_existing=False)
    try:
        image.colorspace_settings.is_data = True
        return pixels(image), image.size[0], image.size[1], image.channels
    finally:
        bpy.data.images.remove(image)


def render_still(scene, path):
    if os.path.exists(path):  # an earlier run's file must not pass for this render's
        os.remove(path)
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    if not os.path.isfile(path):
        raise RuntimeError("Blender did not write %s" % path)
    return load_file(path)


def psnr(a, b, mask=None, channels=4, peak=1.0):
    """PSNR over the RGB channels (of pixels where mask is true)."""
    total = 0.0
    n = 0
    for i in range(len(a) // channels):
        if mask is not None and not mask[i]:
            continue
        for c in range(3):
            d = a[i * channels + c] - b[i * channels + c]
            total += d * d
        n += 3
    if n == 0:
        return float("nan")
    mse = total / n
    return float("inf") if mse == 0 else 10.0 * math.log10(peak * peak / mse)


def detail(buf, mask, width, channels=4):
    """Mean squared difference between horizontal neighbours (green channel) where both are in
    the mask: high for a sharp texture, low once blurred."""
    total = 0.0
    n = 0
    for i, inside in enumerate(mask):
        if inside and (i + 1) % width and mask[i + 1]:
            d = buf[i * channels + 1] - buf[(i + 1) * channels + 1]
            total += d * d
            n += 1
    return total / max(n, 1)


def erode(mask, width, height, r):
    """Pixels whose whole (2r+1)^2 neighbourhood is in the mask."""
    out = [False] * len(mask)
    for y in range(r, height - r):
        for x in range(r, width - r):
            out[y * width + x] = all(mask[(y + dy) * width + x + dx]
                                     for dy in range(-r, r + 1) for dx in range(-r, r + 1))
    return out


def save_png(buf, width, height, path, channels=4):
    """For looking at results: an sRGB PNG of a linear float buffer."""
    image = bpy.data.images.new("png-out", width, height, alpha=True, float_buffer=True)
    if channels != 4:
        raise ValueError("RGBA only")
    image.pixels.foreach_set(buf)
    scene = bpy.context.scene
    saved = (scene.render.image_settings.file_format, scene.render.image_settings.color_depth)
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_depth = "8"
    try:
        image.save_render(path, scene=scene)
    finally:
        scene.render.image_settings.file_format, scene.render.image_settings.color_depth = saved
        bpy.data.images.remove(image)


def save_montage(buffers, width, height, columns, path, gap=4, scale=1):
    """Several RGBA float buffers of one size side by side in one PNG (reading order), each
    pixel repeated scale x scale times, for looking at results."""
    sw, sh = width * scale, height * scale
    rows = (len(buffers) + columns - 1) // columns
    mw, mh = columns * sw + (columns - 1) * gap, rows * sh + (rows - 1) * gap
    out = array.array("f", [1.0]) * (mw * mh * 4)
    for k, buf in enumerate(buffers):
        col, row = k % columns, k // columns
        x0 = col * (sw + gap)
        y0 = (rows - 1 - row) * (sh + gap)  # Blender rows run bottom-up
        for y in range(height):
            line = array.array("f")
            for x in range(width):
                line.extend(buf[(y * width + x) * 4:(y * width + x) * 4 + 4] * scale)
            for r in range(scale):
                start = ((y0 + y * scale + r) * mw + x0) * 4
                out[start:start + sw * 4] = line
    save_png(out, mw, mh, path)
