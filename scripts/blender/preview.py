"""Look at a vdblight bake in Blender: import it as a Volume object whose material shows the
irradiance as colour, and render a preview image.

    blender --python scripts/blender/preview.py -- VOLUME.vdb                 # interactive
    blender -b --factory-startup --python scripts/blender/preview.py -- VOLUME.vdb OUT.png

VOLUME is a volume written by `vdblight bake` or a preview file written by
`vdblight export VOLUME -o DIR --format vdb-preview` (DIR/preview.vdb). A bake without the
preview grids is converted first with `vdblight export --format vdb-preview` (the program is
taken from --cli, else $VDBLIGHT_CLI, else `vdblight` on PATH, else build/bin/vdblight of this
checkout) into a temporary directory.

The material is an emission-only volume: emission colour = the `irradiance_avg` grid (the
mean irradiance over the six axis normals) times a strength. The camera is orthographic and
looks along -z (x to the right, y up) at the whole volume, or along --view. Rendering uses
Cycles on the CPU with a few samples at --size pixels, so it takes a couple of seconds.

The image is saved tone-mapped as vdblight slice does it (docs/engines.md "Slices"): the
linear render is scaled so that its mean luminance over the volume's pixels is 0.18, then
Reinhard x / (1 + x) per channel, then sRGB, 8 bits.
Exit status 0 on success, 1 with a one-line message.
"""
import argparse
import os
import shutil
import subprocess
import sys
import tempfile


class PreviewError(Exception):
    pass


def parse_args():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser(prog="preview.py")
    p.add_argument("volume")
    p.add_argument("output", nargs="?", help="PNG to render into (omitted: only set up the scene)")
    p.add_argument("--cli", help="the vdblight program (for bakes without preview grids)")
    p.add_argument("--size", type=int, default=160, help="pixels along the longer image side")
    p.add_argument("--samples", type=int, default=8)
    p.add_argument("--view", choices=["-z", "+z", "-x", "+x", "-y", "+y"], default="-z",
                   help="direction the camera looks along")
    return p.parse_args(argv)


def find_cli(explicit):
    for c in (explicit, os.environ.get("VDBLIGHT_CLI"), shutil.which("vdblight"),
              os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "build", "bin", "vdblight")):
        if c and os.path.isfile(c) and os.access(c, os.X_OK):
            return c
    raise PreviewError("the volume has no preview grids and no vdblight program was found (give --cli)")


def import_volume(path):
    import bpy
    bpy.ops.object.volume_import(filepath=path)
    obj = bpy.context.active_object
    if obj is None or obj.type != 'VOLUME':
        raise PreviewError("Blender did not import '%s' as a volume" % path)
    grids = obj.data.grids
    if not grids.load():
        raise PreviewError("Blender cannot load the grids of '%s': %s" % (path, grids.error_message))
    return obj, [g.name for g in grids]


def preview_volume(path, cli, workdir):
    """The volume object with the preview grids: `path` itself, or its vdb-preview export."""
    import bpy
    if not os.path.isfile(path):
        raise PreviewError("no such file: %s" % path)
    obj, names = import_volume(path)
    if "irradiance_avg" in names:
        return obj
    bpy.data.objects.remove(obj)
    out = os.path.join(workdir, "preview")
    r = subprocess.run([find_cli(cli), "export", "-q", path, "-o", out, "--format", "vdb-preview"],
                       capture_output=True, text=True)
    if r.returncode != 0:
        raise PreviewError("vdblight export --format vdb-preview failed: %s" % (r.stderr.strip() or r.stdout.strip()))
    obj, names = import_volume(os.path.join(out, "preview.vdb"))
    if "irradiance_avg" not in names:
        raise PreviewError("the preview file has no irradiance_avg grid")
    return obj


def set_material(obj, strength):
    import bpy
    mat = bpy.data.materials.new("vdblight_irradiance")
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    nodes.clear()
    attr = nodes.new("ShaderNodeAttribute")
    attr.attribute_name = "irradiance_avg"
    emission = nodes.new("ShaderNodeEmission")
    emission.inputs["Strength"].default_value = strength
    out = nodes.new("ShaderNodeOutputMaterial")
    links.new(attr.outputs["Color"], emission.inputs["Color"])
    links.new(emission.outputs["Emission"], out.inputs["Volume"])
    obj.data.materials.clear()
    obj.data.materials.append(mat)


def world_box(obj):
    from mathutils import Vector
    corners = [obj.matrix_world @ Vector(c) for c in obj.bound_box]
    lo = [min(c[a] for c in corners) for a in range(3)]
    hi = [max(c[a] for c in corners) for a in range(3)]
    return lo, hi


def set_camera(lo, hi, view, size):
    import bpy
    from mathutils import Vector
    axis = "xyz".index(view[1])
    sign = 1.0 if view[0] == "+" else -1.0
    u, v = {0: (2, 1), 1: (0, 2), 2: (0, 1)}[axis]
    centre = Vector([(lo[a] + hi[a]) / 2 for a in range(3)])
    extent = [hi[a] - lo[a] for a in range(3)]
    pos = centre.copy()
    pos[axis] -= sign * (extent[axis] + 1.0)
    cam_data = bpy.data.cameras.new("vdblight_camera")
    cam_data.type = 'ORTHO'
    cam_data.ortho_scale = max(extent[u], extent[v]) * 1.02
    cam_data.clip_end = extent[axis] + 10.0
    cam = bpy.data.objects.new("vdblight_camera", cam_data)
    bpy.context.scene.collection.objects.link(cam)
    cam.location = pos
    from mathutils import Matrix
    back = Vector([0.0, 0.0, 0.0])
    back[axis] = -sign  # the camera looks along its local -Z
    up = Vector([0.0, 0.0, 0.0])
    up[v] = 1.0
    right = up.cross(back)
    cam.rotation_euler = Matrix((right, up, back)).transposed().to_euler()
    scene = bpy.context.scene
    scene.camera = cam
    w, h = extent[u], extent[v]
    scene.render.resolution_x = max(1, round(size * w / max(w, h)))
    scene.render.resolution_y = max(1, round(size * h / max(w, h)))
    scene.render.resolution_percentage = 100


def configure_render(samples, depth):
    import bpy
    scene = bpy.context.scene
    scene.render.engine = 'CYCLES'
    scene.cycles.device = 'CPU'
    scene.cycles.samples = samples
    scene.cycles.use_denoising = False
    scene.cycles.volume_step_rate = 1.0
    scene.cycles.volume_max_steps = 256
    scene.cycles.max_bounces = 0
    scene.render.film_transparent = True
    scene.view_settings.view_transform = 'Standard'
    scene.view_settings.look = 'None'
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.display_settings.display_device = 'sRGB'
    scene.world = bpy.data.worlds.new("vdblight_black")
    scene.world.color = (0.0, 0.0, 0.0)
    scene.render.threads_mode = 'FIXED'
    scene.render.threads = 2


def render_linear(workdir):
    """Renders to a float EXR and returns (width, height, RGBA floats)."""
    import bpy
    scene = bpy.context.scene
    path = os.path.join(workdir, "render.exr")
    scene.render.image_settings.file_format = 'OPEN_EXR'
    scene.render.image_settings.color_depth = '32'
    scene.render.image_settings.color_mode = 'RGBA'
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    if not os.path.isfile(path):
        raise PreviewError("Blender rendered no image")
    img = bpy.data.images.load(path)
    w, h = img.size
    pixels = list(img.pixels)
    bpy.data.images.remove(img)
    return w, h, pixels


def save_tonemapped(path, w, h, pixels):
    """docs/engines.md tone map, mean luminance of the covered pixels -> 0.18; saved as PNG."""
    import bpy
    lum, count = 0.0, 0
    for i in range(0, len(pixels), 4):
        if pixels[i + 3] > 0.0:
            lum += 0.2126 * pixels[i] + 0.7152 * pixels[i + 1] + 0.0722 * pixels[i + 2]
            count += 1
    mean = lum / count if count else 0.0
    k = 0.18 / mean if mean > 0 else 1.0

    def srgb(x):
        return 12.92 * x if x <= 0.0031308 else 1.055 * x ** (1 / 2.4) - 0.055

    out = []
    for i in range(0, len(pixels), 4):
        for c in range(3):
            x = max(0.0, pixels[i + c] * k)
            out.append(srgb(x / (1.0 + x)))
        out.append(1.0)
    img = bpy.data.images.new("vdblight_preview", w, h, alpha=False)
    img.colorspace_settings.name = 'Non-Color'  # the values are already display-encoded
    img.pixels = out
    img.filepath_raw = path
    img.file_format = 'PNG'
    tmp = os.path.join(os.path.dirname(os.path.abspath(path)), "." + os.path.basename(path) + ".tmp.png")
    img.filepath_raw = tmp
    img.save()
    os.replace(tmp, path)


def main():
    args = parse_args()
    import bpy
    if bpy.app.background:
        bpy.ops.wm.read_factory_settings(use_empty=True)
    else:
        for o in list(bpy.data.objects):
            if o.type in ('MESH', 'LIGHT', 'CAMERA') and o.name in ("Cube", "Light", "Camera"):
                bpy.data.objects.remove(o)
    # In the interactive Blender the converted preview must outlive the script: keep it.
    keep = not bpy.app.background
    with tempfile.TemporaryDirectory() as scratch:
        workdir = tempfile.mkdtemp(prefix="vdblight_preview_") if keep else scratch
        obj = preview_volume(os.path.abspath(args.volume), args.cli, workdir)
        obj.name = "vdblight_irradiance"
        lo, hi = world_box(obj)
        depth = max(hi[a] - lo[a] for a in range(3))
        # Emission integrates along the ray through the volume: 1/depth keeps the image's
        # scale near the irradiance itself (the saved PNG is normalised anyway).
        set_material(obj, 1.0 / max(depth, 1e-9))
        set_camera(lo, hi, args.view, args.size)
        configure_render(args.samples, depth)
        if args.output:
            w, h, pixels = render_linear(workdir)
            save_tonemapped(os.path.abspath(args.output), w, h, pixels)
            print("vdblight preview: wrote %s (%d x %d)" % (args.output, w, h))


if __name__ == "__main__":
    try:
        main()
    except PreviewError as e:
        print("vdblight preview: error: %s" % e, file=sys.stderr)
        sys.exit(1)
    except Exception as e:  # Blender swallows exceptions of --python scripts: exit non-zero
        print("vdblight preview: error: %s: %s" % (type(e).__name__, e), file=sys.stderr)
        sys.exit(1)
