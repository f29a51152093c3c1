"""How bright a Billboard Cloud looks beside its original under a sun, Blender.

Renders ORIGINAL and every CLOUD with Blender's EEVEE (headless, Blender 3.4)
under the same sun(s), world light and camera(s), and compares the mean
colour of the pixels each file covers. Run it through the wrapper

    scripts/studies/blender_sun.sh [options] ORIGINAL CLOUD...

or by hand (EEVEE needs an OpenGL context, hence Xvfb):

    xvfb-run -a blender -b --factory-startup --python-exit-code 4 \\
        --python scripts/studies/blender_sun.py -- [options] ORIGINAL CLOUD...

Options (after `--`)
  ORIGINAL            .obj (Blender's OBJ importer, axis_forward -Z, axis_up Y:
                      the Y-up file becomes Blender's Z-up) or .glb/.gltf
  CLOUD...            .glb/.gltf (Blender's glTF importer, Y-up to Z-up the
                      same way, so original and clouds overlap exactly)
  --suns AZ:EL,...    sun directions in degrees in the MODEL's Y-up frame:
                      azimuth about the up axis, 0 = from the model's +Z
                      side, 90 = from +X; elevation above the horizon
                      (default 30:60,210:60,120:30)
  --views V,...       camera azimuths: front (0, the +Z side), side (90, +X),
                      back (180), left (270) or a number of degrees
                      (default front,side)
  --elevation DEG     camera elevation (default 10)
  --fov DEG           perspective camera field of view (default 30); the
                      camera frames the ORIGINAL's bounding sphere (centre of
                      its bounding box, farthest vertex) with 5% margin
  --size N            square image size in pixels (default 256)
  --samples N         EEVEE taa_render_samples (default 16)
  --sun-strength W    sun strength, W/m^2 (default 3.0)
  --ambient S         world background: white, this strength (default 0.4)
  --shadow-map N      EEVEE sun shadow cascade size, 512/1024/2048/4096
                      (default 1024, Blender's; 2048 costs about 4x the
                      render time in software OpenGL and moves luminance
                      by under 1%)
  --kd MODE           OBJ originals: how MTL Kd scales map_Kd (Blender's
                      importer drops it, see below): srgb (default; texel x
                      Kd on 8-bit sRGB values, as OpenGL viewers and bbcgen
                      do), linear (texel x Kd in linear light) or off
  --json OUT          write every figure to OUT
  --keep DIR          keep one PNG per render in DIR, plus sheet.png (every
                      render over grey: one row per file)
  --verbose           let Blender's own log (imports, render progress) through

What it measures
  Per file and per (sun, view): covered pixels (alpha > 0.5), the mean R, G,
  B of those pixels in 8-bit sRGB as written to the PNG, their luminance
  0.2126 R + 0.7152 G + 0.0722 B, their saturation (the mean of max - min
  of R, G, B over them), and for clouds the IoU of the covered
  pixels with the original's (a check that the two overlap: framing and axes).
  Per cloud: luminance ratio cloud / original for every (sun, view), and
  their min / max / mean. Each file is rendered alone (the others get
  hide_render, so they cast no shadow either) in the same scene.

Settings a user must know (Blender 3.4, Debian package)
  * The glTF importer needs numpy (`apt-get install python3-numpy`; Debian's
    blender package does not pull it in), and Blender 3.4's importer still
    uses `np.bool`, which numpy >= 1.24 (Debian 12 ships 1.24) removed: it
    fails with "module 'numpy' has no attribute 'bool'". This script puts
    the old aliases back on numpy before importing.
  * EEVEE renders need an OpenGL context even with -b: run under
    `xvfb-run -a` (Debian: apt-get install xvfb).
  * An uncaught Python error in a --python script still exits 0 unless
    Blender is given `--python-exit-code N`; the wrapper passes 4.
  * Render settings used: engine BLENDER_EEVEE, film_transparent = True (so
    alpha is coverage), view transform 'Standard' with look None, exposure
    0, gamma 1 (the default 'Filmic' would compress and desaturate colours),
    dither_intensity 0 (the default 1.0 adds noise to 8-bit output), PNG
    RGBA 8-bit.
  * OBJ materials with an alpha texture: the OBJ importer links map_d's
    alpha (a second, Non-Color image node) to the Principled BSDF's Alpha
    but sets blend_method 'BLEND' and leaves shadow_method 'OPAQUE'. Here
    every original material whose Alpha is linked gets blend_method and
    shadow_method 'CLIP', alpha_threshold 0.5; a map_Kd texture with real
    alpha but no map_d gets its Alpha linked too. use_backface_culling is
    False for all original materials. A constant MTL `d` < 1 is ignored
    (made opaque), as a Billboard Cloud generator treats it.
  * The OBJ importer drops MTL Kd when map_Kd is given (Base Color is the
    texture alone; Kd stays only as the socket's unused default value),
    while OpenGL viewers and bbcgen multiply the texture by Kd: a MULTIPLY
    node is inserted here (--kd), otherwise an original with Kd 0.8 renders
    25% brighter than bbcgen sees it. Ks and Ns become Specular and
    Roughness as the importer sets them (listed per material in --json).
  * glTF alphaMode MASK imports as blend_method 'CLIP' with the cutoff as
    alpha_threshold, but shadow_method stays 'OPAQUE', so each quad would
    cast a solid rectangular shadow: every MASK material gets shadow_method
    'CLIP' here (alphaMode BLEND: 'HASHED'); the same holds for a glTF
    ORIGINAL, whose materials are otherwise left as imported. doubleSided
    false imports as use_backface_culling True and is kept (a cloud written
    with one-sided quads shows nothing from behind). A lit glTF material
    gets Principled Specular 0.5 (glTF's F0 0.04), while the OBJ importer
    turns a missing Ks into Specular 0: a little white sheen the original
    lacks. KHR_materials_unlit imports as an
    Emission shader (strength 1, mixed with Transparent by "Is Camera Ray"):
    it ignores the sun and the world, so a "baked" cloud looks the same
    under every sun; that is expected and is one thing this tool shows.
  * Scale: Blender takes file units as metres, so a model in centimetres
    is hundreds of metres tall. EEVEE's sun shadow cascades stop at
    shadow_cascade_max_distance (default 200 m) and nothing beyond casts or
    receives a sun shadow (measured: the scopia pine, 545 cm tall and so
    545 m to Blender, gets no self-shadow at all with the default and
    renders 11% brighter); the
    camera's clip range and the cascade distance are set here from the
    original's bounding sphere, so any unit works.
  * Speed: EEVEE runs on Mesa's software OpenGL (llvmpipe) under Xvfb, and
    soft shadows re-render the cascades every sample: at the defaults a
    render takes 10-25 s on 2 cores (more for many overlapping alpha-
    tested quads than for a 100k-triangle mesh; the first one also
    compiles shaders), so ORIGINAL + 2 clouds x 3 suns x 2 views take 4-5
    minutes; --shadow-map 2048 is about 4x slower. --size 128 --samples 4
    is a quick check.
  * Pixels are read back from the 8-bit PNG with bpy.data.images.load:
    for a byte image, Image.pixels holds the stored sRGB values / 255
    (straight alpha, not linearised), which is what is averaged.
  * The world colour lights the model unoccluded (no AO in EEVEE by
    default), equally for every file.

Exit status: 0 success; 1 bad command line; 2 an input file is missing;
3 a tool is missing (no numpy, no OpenGL display); 4 an import or a render
failed (importer error, missing texture, nothing covered in a render).
"""

import json
import math
import os
import shutil
import sys
import tempfile
import time

LUMA = (0.2126, 0.7152, 0.0722)
VIEW_NAMES = {"front": 0.0, "side": 90.0, "back": 180.0, "left": 270.0}


class Failure(Exception):
    def __init__(self, msg, code=4):
        super().__init__(msg)
        self.code = code


def log(msg):
    sys.stderr.write("blender_sun: %s\n" % msg)
    sys.stderr.flush()


# ------------------------------------------------------------ command line --

def parse_args(argv):
    import argparse

    class Parser(argparse.ArgumentParser):
        def error(self, message):           # exit 1, not argparse's 2
            self.print_usage(sys.stderr)
            sys.stderr.write("blender_sun: %s\n" % message)
            sys.exit(1)

    p = Parser(prog="blender_sun.sh",
               description="Compare a model and its Billboard Clouds under a "
                           "sun in Blender EEVEE.")
    p.add_argument("original")
    p.add_argument("clouds", nargs="+", metavar="cloud")
    p.add_argument("--suns", default="30:60,210:60,120:30")
    p.add_argument("--views", default="front,side")
    p.add_argument("--elevation", type=float, default=10.0)
    p.add_argument("--fov", type=float, default=30.0)
    p.add_argument("--size", type=int, default=256)
    p.add_argument("--samples", type=int, default=16)
    p.add_argument("--sun-strength", type=float, default=3.0)
    p.add_argument("--ambient", type=float, default=0.4)
    p.add_argument("--shadow-map", default="1024",
                   choices=["512", "1024", "2048", "4096"])
    p.add_argument("--kd", default="srgb", choices=["srgb", "linear", "off"])
    p.add_argument("--json")
    p.add_argument("--keep")
    p.add_argument("--verbose", action="store_true")
    a = p.parse_args(argv)

    suns = []
    for item in a.suns.split(","):
        try:
            az, el = (float(v) for v in item.split(":"))
        except ValueError:
            p.error("--suns: %r is not AZ:EL" % item)
        if not -90.0 <= el <= 90.0:
            p.error("--suns: elevation %g outside -90..90" % el)
        suns.append((az, el))
    views = []
    for item in a.views.split(","):
        item = item.strip()
        if item in VIEW_NAMES:
            views.append((item, VIEW_NAMES[item]))
        else:
            try:
                views.append(("az%g" % float(item), float(item)))
            except ValueError:
                p.error("--views: %r is not front, side, back, left or "
                        "degrees" % item)
    if not 1 <= a.size <= 8192:
        p.error("--size must be 1..8192")
    if a.samples < 1:
        p.error("--samples must be >= 1")
    if not 1.0 <= a.fov <= 170.0:
        p.error("--fov must be 1..170")
    if not -89.0 <= a.elevation <= 89.0:
        p.error("--elevation must be -89..89")
    if a.sun_strength < 0 or a.ambient < 0:
        p.error("--sun-strength and --ambient must be >= 0")

    def ext(path):
        return os.path.splitext(path)[1].lower()
    if ext(a.original) not in (".obj", ".glb", ".gltf"):
        p.error("ORIGINAL must be .obj, .glb or .gltf: %s" % a.original)
    for c in a.clouds:
        if ext(c) not in (".glb", ".gltf"):
            p.error("CLOUD must be .glb or .gltf: %s" % c)
    a.sun_list, a.view_list = suns, views
    return a


# ---------------------------------------------- Blender stdout noise --

class Quiet:
    """Sends the process's stdout (Blender's C-level progress lines) to
    /dev/null while active; our own report goes out after."""

    def __init__(self, on):
        self.on = on

    def __enter__(self):
        if self.on:
            sys.stdout.flush()
            self.saved = os.dup(1)
            null = os.open(os.devnull, os.O_WRONLY)
            os.dup2(null, 1)
            os.close(null)

    def __exit__(self, *exc):
        if self.on:
            sys.stdout.flush()
            os.dup2(self.saved, 1)
            os.close(self.saved)


# --------------------------------------------------------------- geometry --

def model_to_blender(v):
    """Model Y-up (x, y, z) -> Blender Z-up (x, -z, y), as both importers."""
    return (v[0], -v[2], v[1])


def blender_to_model(v):
    return (v[0], v[2], -v[1])


def direction(az_deg, el_deg):
    """Unit vector in Blender's frame pointing from the model towards
    azimuth az (0 = model +Z, 90 = model +X) at elevation el."""
    az, el = math.radians(az_deg), math.radians(el_deg)
    d = (math.sin(az) * math.cos(el), math.sin(el),
         math.cos(az) * math.cos(el))
    return model_to_blender(d)


def world_vertices(objs, np):
    """All mesh vertices of objs in world coordinates, as an (n, 3) array."""
    parts = []
    for o in objs:
        if o.type != "MESH" or len(o.data.vertices) == 0:
            continue
        co = np.empty(len(o.data.vertices) * 3, dtype=np.float64)
        o.data.vertices.foreach_get("co", co)
        co = co.reshape(-1, 3)
        m = np.array(o.matrix_world, dtype=np.float64)
        parts.append(co @ m[:3, :3].T + m[:3, 3])
    if not parts:
        return np.zeros((0, 3))
    return np.concatenate(parts)


# -------------------------------------------------------------- materials --

def image_has_alpha(img, np):
    if img is None or img.depth not in (32, 64, 128) or img.size[0] == 0:
        return False
    px = np.empty(img.size[0] * img.size[1] * 4, dtype=np.float32)
    img.pixels.foreach_get(px)
    return bool(px[3::4].min() < 0.999)


def principled(mat):
    for n in mat.node_tree.nodes:
        if n.type == "BSDF_PRINCIPLED":
            return n
    return None


def check_textures(mat, label):
    if not mat.use_nodes:
        return
    for n in mat.node_tree.nodes:
        if n.type != "TEX_IMAGE":
            continue
        img = n.image
        if img is None or img.size[0] == 0 or img.size[1] == 0:
            name = img.filepath if img is not None else "(none)"
            raise Failure("%s: material %s: texture %s did not load"
                          % (label, mat.name, name))


def setup_original_material(mat, np, notes, kd_mode="srgb"):
    mat.use_backface_culling = False
    if not mat.use_nodes:
        return
    bsdf = principled(mat)
    if bsdf is None:
        notes.append("original material %s has no Principled BSDF; left as "
                      "imported" % mat.name)
        return
    base = bsdf.inputs["Base Color"]
    kd = tuple(base.default_value)[:3]      # the importer keeps MTL Kd here
    if (kd_mode != "off" and base.is_linked
            and base.links[0].from_node.type == "TEX_IMAGE"
            and any(abs(k - 1.0) > 1e-6 for k in kd)):
        # "srgb": texel x Kd on the 8-bit sRGB values (OpenGL GL_MODULATE
        # viewers, bbcgen), which in linear light is a factor Kd^2.2.
        factor = tuple(max(k, 0.0) ** 2.2 for k in kd) if kd_mode == "srgb" \
            else kd
        tex = base.links[0].from_node
        mix = mat.node_tree.nodes.new("ShaderNodeMixRGB")
        mix.name = mix.label = "blender_sun Kd"
        mix.blend_type = "MULTIPLY"
        mix.inputs["Fac"].default_value = 1.0
        mix.inputs["Color2"].default_value = factor + (1.0,)
        mat.node_tree.links.new(tex.outputs["Color"], mix.inputs["Color1"])
        mat.node_tree.links.new(mix.outputs["Color"], base)
        notes.append("original material %s: map_Kd multiplied by Kd %s "
                     "(--kd %s)" % (mat.name, "/".join("%g" % round(k, 4)
                                                      for k in kd), kd_mode))
    alpha = bsdf.inputs["Alpha"]
    if not alpha.is_linked:
        if base.is_linked and base.links[0].from_node.type == "TEX_IMAGE":
            tex = base.links[0].from_node
            if image_has_alpha(tex.image, np):
                mat.node_tree.links.new(tex.outputs["Alpha"], alpha)
                notes.append("original material %s: linked the colour "
                             "texture's alpha to Alpha" % mat.name)
    if alpha.is_linked:
        mat.blend_method = "CLIP"
        mat.shadow_method = "CLIP"
        mat.alpha_threshold = 0.5
    else:
        if alpha.default_value < 1.0:
            notes.append("original material %s: constant alpha %.3g ignored "
                         "(opaque)" % (mat.name, alpha.default_value))
            alpha.default_value = 1.0
        mat.blend_method = "OPAQUE"
        mat.shadow_method = "OPAQUE"


def material_info(mat):
    info = {"name": mat.name, "blend_method": mat.blend_method,
            "shadow_method": mat.shadow_method,
            "alpha_threshold": round(mat.alpha_threshold, 4),
            "backface_culling": mat.use_backface_culling}
    if mat.use_nodes:
        types = set(n.type for n in mat.node_tree.nodes)
        bsdf = principled(mat)
        if bsdf is not None:
            info["shading"] = "principled"
            for k in ("Metallic", "Specular", "Roughness"):
                i = bsdf.inputs[k]
                info[k.lower()] = ("texture" if i.is_linked
                                   else round(i.default_value, 4))
            info["normal_map"] = "NORMAL_MAP" in types
        elif "EMISSION" in types:
            info["shading"] = "emission (unlit)"
    return info


def setup_gltf_material(mat):
    """As the glTF importer made it, but shadows that honour alpha."""
    if mat.blend_method == "CLIP":          # alphaMode MASK
        mat.shadow_method = "CLIP"
    elif mat.blend_method in ("BLEND", "HASHED"):
        mat.shadow_method = "HASHED"


# ------------------------------------------------------------------ scene --

def reset_scene(bpy):
    for o in list(bpy.data.objects):
        bpy.data.objects.remove(o, do_unlink=True)
    for c in list(bpy.data.collections):
        bpy.data.collections.remove(c)


def import_file(bpy, path, index, np):
    scene = bpy.context.scene
    coll = bpy.data.collections.new("file%d" % index)
    scene.collection.children.link(coll)
    vl = bpy.context.view_layer
    vl.active_layer_collection = vl.layer_collection.children[coll.name]
    before = set(bpy.data.objects)
    ext = os.path.splitext(path)[1].lower()
    try:
        if ext == ".obj":
            r = bpy.ops.import_scene.obj(filepath=path, axis_forward="-Z",
                                         axis_up="Y")
        else:
            r = bpy.ops.import_scene.gltf(filepath=path)
    except RuntimeError as e:
        raise Failure("%s: import failed: %s" % (path, str(e).strip()[-600:]))
    if "FINISHED" not in r:
        raise Failure("%s: import failed (%s)" % (path, r))
    objs = [o for o in bpy.data.objects if o not in before]
    for o in objs:                          # importers may link elsewhere
        if coll not in o.users_collection:
            coll.objects.link(o)
        for c in list(o.users_collection):
            if c is not coll:
                c.objects.unlink(o)
    meshes = [o for o in objs if o.type == "MESH"]
    if not meshes or sum(len(o.data.polygons) for o in meshes) == 0:
        raise Failure("%s: no geometry imported" % path)
    mats = []
    for o in meshes:
        for s in o.material_slots:
            if s.material is not None and s.material not in mats:
                mats.append(s.material)
    return coll, meshes, mats


def setup_scene(bpy, a, center, radius):
    scene = bpy.context.scene
    scene.render.engine = "BLENDER_EEVEE"
    scene.eevee.taa_render_samples = a.samples
    scene.render.resolution_x = a.size
    scene.render.resolution_y = a.size
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = scene.render.pixel_aspect_y = 1.0
    scene.render.film_transparent = True
    scene.render.dither_intensity = 0.0
    scene.render.use_compositing = False
    scene.render.use_sequencer = False
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "RGBA"
    scene.render.image_settings.color_depth = "8"
    scene.render.image_settings.compression = 15
    scene.display_settings.display_device = "sRGB"
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    scene.eevee.use_bloom = False
    scene.eevee.use_ssr = False
    scene.eevee.use_gtao = False
    scene.eevee.shadow_cascade_size = a.shadow_map
    scene.eevee.use_soft_shadows = True

    world = bpy.data.worlds.new("blender_sun_world")
    world.use_nodes = True
    bg = world.node_tree.nodes.get("Background")
    bg.inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    bg.inputs["Strength"].default_value = a.ambient
    scene.world = world

    half = math.radians(a.fov) / 2.0
    dist = radius / math.sin(half) * 1.05
    cam_data = bpy.data.cameras.new("blender_sun_camera")
    cam_data.type = "PERSP"
    cam_data.sensor_fit = "AUTO"
    cam_data.angle = math.radians(a.fov)
    cam_data.clip_start = max(dist - 1.5 * radius, 0.02 * dist)
    cam_data.clip_end = dist + 1.5 * radius
    cam = bpy.data.objects.new("blender_sun_camera", cam_data)
    scene.collection.objects.link(cam)
    scene.camera = cam

    sun_data = bpy.data.lights.new("blender_sun_sun", type="SUN")
    sun_data.energy = a.sun_strength
    sun_data.color = (1.0, 1.0, 1.0)
    sun_data.use_shadow = True
    sun_data.shadow_cascade_count = 4
    sun_data.shadow_cascade_max_distance = cam_data.clip_end
    sun = bpy.data.objects.new("blender_sun_sun", sun_data)
    scene.collection.objects.link(sun)
    return cam, sun, dist


def aim(obj, pos, z_axis, mathutils):
    """Place obj at pos with its local +Z along z_axis (world Z as up)."""
    obj.location = pos
    obj.rotation_mode = "QUATERNION"
    obj.rotation_quaternion = mathutils.Vector(z_axis).to_track_quat("Z", "Y")


# --------------------------------------------------------------- measuring --

def read_png(bpy, path, np):
    img = bpy.data.images.load(path, check_existing=False)
    try:
        w, h = img.size
        px = np.empty(w * h * 4, dtype=np.float32)
        img.pixels.foreach_get(px)
    finally:
        bpy.data.images.remove(img)
    return px.reshape(h, w, 4)


def measure(px, np):
    mask = px[:, :, 3] > 0.5
    n = int(mask.sum())
    if n == 0:
        return mask, {"covered": 0, "rgb": None, "luminance": None,
                      "saturation": None}
    rgb = [float(px[:, :, c][mask].mean() * 255.0) for c in range(3)]
    lum = sum(k * v for k, v in zip(LUMA, rgb))
    cov = px[:, :, :3][mask]
    sat = float((cov.max(axis=1) - cov.min(axis=1)).mean() * 255.0)
    return mask, {"covered": n, "rgb": [round(v, 2) for v in rgb],
                  "luminance": round(lum, 3), "saturation": round(sat, 3)}


def write_sheet(bpy, np, path, rows, size):
    """rows: list of lists of (h, w, 4) float arrays; composited over grey."""
    nr, nc = len(rows), max(len(r) for r in rows)
    gap = 2
    H, W = nr * size + (nr - 1) * gap, nc * size + (nc - 1) * gap
    sheet = np.ones((H, W, 4), dtype=np.float32)
    sheet[:, :, :3] = 0.15
    for i, row in enumerate(rows):
        for j, px in enumerate(row):
            y0 = H - (i + 1) * size - i * gap   # Blender rows go bottom-up
            x0 = j * (size + gap)
            a = px[:, :, 3:4]
            sheet[y0:y0 + size, x0:x0 + size, :3] = (px[:, :, :3] * a
                                                     + 0.5 * (1 - a))
    img = bpy.data.images.new("blender_sun_sheet", W, H, alpha=True)
    img.pixels.foreach_set(sheet.ravel())
    img.filepath_raw = path
    img.file_format = "PNG"
    img.save()
    bpy.data.images.remove(img)


# -------------------------------------------------------------------- main --

def run(a, bpy, mathutils, np):
    t_start = time.time()
    files = [a.original] + list(a.clouds)
    labels, seen = [], {}
    for f in files:
        base = os.path.basename(f)
        seen[base] = seen.get(base, 0) + 1
        labels.append(base if seen[base] == 1
                      else "%s#%d" % (base, seen[base]))

    quiet = Quiet(not a.verbose)
    notes = []
    reset_scene(bpy)
    imported = []
    for i, f in enumerate(files):
        t0 = time.time()
        with quiet:
            coll, meshes, mats = import_file(bpy, os.path.abspath(f), i, np)
        for m in mats:
            check_textures(m, f)
            if i == 0 and f.lower().endswith(".obj"):
                setup_original_material(m, np, notes, a.kd)
            else:                           # clouds, glTF originals
                setup_gltf_material(m)
        v = world_vertices(meshes, np)
        lo, hi = v.min(axis=0), v.max(axis=0)
        imported.append({
            "coll": coll, "verts": v, "import_s": time.time() - t0,
            "triangles": sum(sum(len(p.vertices) - 2 for p in o.data.polygons)
                             for o in meshes),
            "bbox_blender": (lo, hi),
            "materials": [material_info(m) for m in mats]})

    v0 = imported[0]["verts"]
    lo, hi = imported[0]["bbox_blender"]
    center = (lo + hi) / 2.0
    radius = float(np.sqrt(((v0 - center) ** 2).sum(axis=1)).max())
    if radius <= 0:
        raise Failure("%s: degenerate model (zero radius)" % a.original)
    cam, sun, dist = setup_scene(bpy, a, center, radius)
    c = mathutils.Vector(center.tolist())

    outdir = a.keep if a.keep else tempfile.mkdtemp(prefix="blender_sun.")
    os.makedirs(outdir, exist_ok=True)
    scene = bpy.context.scene
    results = []
    sheet_rows = []
    try:
        for i, f in enumerate(files):
            for j, info in enumerate(imported):
                info["coll"].hide_render = (j != i)
            t0 = time.time()
            renders, row = [], []
            for (saz, sel) in a.sun_list:
                aim(sun, c, direction(saz, sel), mathutils)
                for (vname, vaz) in a.view_list:
                    d = mathutils.Vector(direction(vaz, a.elevation))
                    aim(cam, c + d * dist, d, mathutils)
                    stem = os.path.splitext(os.path.basename(f))[0]
                    png = os.path.join(outdir, "%d_%s_sun%g-%g_%s.png"
                                       % (i, stem, saz, sel, vname))
                    scene.render.filepath = png
                    with quiet:
                        r = bpy.ops.render.render(write_still=True)
                    if "FINISHED" not in r or not os.path.isfile(png):
                        raise Failure("%s: render failed (%s)" % (f, r))
                    px = read_png(bpy, png, np)
                    mask, m = measure(px, np)
                    if m["covered"] == 0:
                        raise Failure("%s: nothing covered in render %s"
                                      % (f, png))
                    m.update({"sun": [saz, sel], "view": vname,
                              "view_azimuth": vaz, "_mask": mask})
                    if a.keep:
                        m["png"] = os.path.abspath(png)
                    renders.append(m)
                    row.append(px)
            lo_b, hi_b = imported[i]["bbox_blender"]
            mlo = blender_to_model(lo_b.tolist())
            mhi = blender_to_model(hi_b.tolist())
            results.append({
                "file": os.path.abspath(f), "label": labels[i],
                "role": "original" if i == 0 else "cloud",
                "triangles": imported[i]["triangles"],
                "bbox_model_yup": {
                    "min": [round(min(p, q), 4) for p, q in zip(mlo, mhi)],
                    "max": [round(max(p, q), 4) for p, q in zip(mlo, mhi)]},
                "materials": imported[i]["materials"],
                "import_s": round(imported[i]["import_s"], 2),
                "render_s": round(time.time() - t0, 2),
                "renders": renders})
            sheet_rows.append(row)
        if a.keep:
            write_sheet(bpy, np, os.path.join(outdir, "sheet.png"),
                        sheet_rows, a.size)
    finally:
        if not a.keep:
            shutil.rmtree(outdir, ignore_errors=True)

    orig = results[0]["renders"]
    for res in results:
        for k, m in enumerate(res["renders"]):
            m0 = orig[k]
            inter = int((m["_mask"] & m0["_mask"]).sum())
            union = int((m["_mask"] | m0["_mask"]).sum())
            m["iou_with_original"] = round(inter / union, 4) if union else None
            if res["role"] == "cloud":
                m["ratio"] = (round(m["luminance"] / m0["luminance"], 4)
                              if m0["luminance"] else None)
                m["saturation_ratio"] = (
                    round(m["saturation"] / m0["saturation"], 4)
                    if m0["saturation"] else None)
    for res in results:
        for m in res["renders"]:
            del m["_mask"]
        if res["role"] == "cloud":
            rs = [m["ratio"] for m in res["renders"] if m["ratio"] is not None]
            ious = [m["iou_with_original"] for m in res["renders"]]
            res["ratio_min"] = round(min(rs), 4) if rs else None
            res["ratio_max"] = round(max(rs), 4) if rs else None
            res["ratio_mean"] = round(sum(rs) / len(rs), 4) if rs else None
            ss = [m["saturation_ratio"] for m in res["renders"]
                  if m["saturation_ratio"] is not None]
            res["saturation_ratio_min"] = round(min(ss), 4) if ss else None
            res["saturation_ratio_max"] = round(max(ss), 4) if ss else None
            res["iou_min"] = round(min(ious), 4)
            if min(ious) < 0.5:
                notes.append("%s: covered pixels overlap the original's "
                             "poorly (IoU %.2f): wrong axes or scale?"
                             % (res["label"], min(ious)))

    report = {
        "tool": "blender_sun.py",
        "blender": bpy.app.version_string,
        "engine": "BLENDER_EEVEE",
        "settings": {
            "suns": [list(s) for s in a.sun_list],
            "views": [{"name": n, "azimuth": z} for n, z in a.view_list],
            "elevation": a.elevation, "fov": a.fov, "size": a.size,
            "samples": a.samples, "shadow_map": int(a.shadow_map),
            "sun_strength": a.sun_strength,
            "ambient": a.ambient, "kd": a.kd, "view_transform": "Standard",
            "film_transparent": True},
        "frame": {"center_model_yup": [round(v, 4) for v in
                                       blender_to_model(center.tolist())],
                  "radius": round(radius, 4),
                  "camera_distance": round(dist, 4)},
        "files": results,
        "notes": notes,
        "seconds": round(time.time() - t_start, 2),
    }
    return report


def print_table(rep):
    out = []
    out.append("blender_sun: Blender %s EEVEE, %dpx, %d samples, sun %g, "
               "ambient %g, radius %.4g" % (
                   rep["blender"], rep["settings"]["size"],
                   rep["settings"]["samples"], rep["settings"]["sun_strength"],
                   rep["settings"]["ambient"], rep["frame"]["radius"]))
    out.append("%-24s %-10s %-6s %7s %6s %6s %6s %6s %6s %5s" % (
        "file", "sun", "view", "covered", "R", "G", "B", "lum", "ratio",
        "IoU"))
    for res in rep["files"]:
        for m in res["renders"]:
            ratio = m.get("ratio")
            out.append("%-24s %-10s %-6s %7d %6.1f %6.1f %6.1f %6.1f %6s %5.2f"
                       % (res["label"][:24], "%g:%g" % tuple(m["sun"]),
                          m["view"], m["covered"], m["rgb"][0], m["rgb"][1],
                          m["rgb"][2], m["luminance"],
                          "-" if ratio is None else "%.3f" % ratio,
                          m["iou_with_original"]))
    out.append("")
    for res in rep["files"]:
        if res["role"] == "cloud":
            out.append("%-24s ratio min %.3f max %.3f mean %.3f  saturation "
                       "%s  IoU min %.2f  (%d tris, %.1fs)" % (
                           res["label"][:24], res["ratio_min"],
                           res["ratio_max"], res["ratio_mean"],
                           "-" if res["saturation_ratio_min"] is None else
                           "%.3f-%.3f" % (res["saturation_ratio_min"],
                                          res["saturation_ratio_max"]),
                           res["iou_min"],
                           res["triangles"],
                           res["import_s"] + res["render_s"]))
        else:
            out.append("%-24s original (%d tris, %.1fs)" % (
                res["label"][:24], res["triangles"],
                res["import_s"] + res["render_s"]))
    for n in rep["notes"]:
        out.append("note: " + n)
    out.append("total %.1fs" % rep["seconds"])
    sys.stdout.write("\n".join(out) + "\n")
    sys.stdout.flush()


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    a = parse_args(argv)
    for f in [a.original] + list(a.clouds):
        if not os.path.isfile(f):
            log("no such file: %s" % f)
            return 2
    try:
        import bpy
        import mathutils
    except ImportError:
        log("run this inside Blender: blender -b --factory-startup --python "
            "scripts/studies/blender_sun.py -- ARGS (or scripts/studies/blender_sun.sh ARGS)")
        return 3
    try:
        import numpy as np
    except ImportError:
        log("Blender's Python has no numpy (its glTF importer needs it): "
            "apt-get install python3-numpy")
        return 3
    # Blender 3.4's glTF importer uses aliases that numpy 1.24 removed.
    for name, typ in (("bool", np.bool_), ("int", int), ("float", float),
                      ("complex", complex), ("object", object), ("str", str)):
        if name not in np.__dict__:
            setattr(np, name, typ)
    if sys.platform.startswith("linux") and not (
            os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY")):
        log("EEVEE needs an OpenGL display: run under xvfb-run -a "
            "(apt-get install xvfb), e.g. via scripts/studies/blender_sun.sh")
        return 3
    try:
        rep = run(a, bpy, mathutils, np)
    except Failure as e:
        log(str(e))
        return e.code
    print_table(rep)
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(rep, fh, indent=1)
            fh.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
