#!/usr/bin/env python3
"""How bright a model and its Billboard Cloud look in a third-party lit viewer.

Renders ORIGINAL and CLOUD with view3dscene (Castle Game Engine) under Xvfb,
with the same camera and the same light (the viewer's headlight), and compares
the mean colour of the pixels each covers.

    python3 scripts/studies/viewer_brightness.py ORIGINAL CLOUD [--views 4] [--size 256]
        [--json OUT.json] [--keep DIR] [--bbcgen PATH] [--elevation 10]
        [--fov 30] [--frame MODEL] [--jobs 1] [--timeout 300]

How it works
  * The camera frames the ORIGINAL's bounding sphere (`bbcgen info --json`:
    "center", "radius"; models are Y-up) from --views azimuths around the up
    axis at --elevation degrees. For every view and file a small X3D wrapper
    scene Inlines the file by absolute path with that Viewpoint,
    `NavigationInfo { headlight TRUE }` and a flat Background, so both files
    get exactly the same camera and light. Anything view3dscene loads can be
    compared (OBJ, glTF .glb/.gltf, X3D, VRML).
  * Every view is rendered twice, on a magenta and on a green background
    (no anti-aliasing). Opaque pixels come out identical in both; a pixel
    the model covers only partly (alpha blending: view3dscene blends OBJ
    textures whose alpha is not just 0/255) is a mix, final = C + t * KEY, so
    the two renders give the transmittance t and the model's own premultiplied
    colour C exactly ("difference matting"). Coverage = sum of (1 - t) over
    the pixels and the mean colour = sum C / coverage; no colour tolerance is
    needed and a tree pixel that happens to be magenta is still counted.
  * Means are of the 8-bit sRGB values the viewer shows (0-255); luminance is
    Rec. 709 luma of those (0.2126 R + 0.7152 G + 0.0722 B). Overall figures
    pool the pixels of every view.

Pitfalls handled here
  * view3dscene exits 0 and still writes a screenshot when a file fails to
    load; its log (in $XDG_CONFIG_HOME/view3dscene/, one folder per render)
    is read and errors fail the run.
  * view3dscene (FPC) locks the files it reads: two renders opening the
    same model or texture at once fail with EAGAIN ("Try again"); --jobs > 1
    retries those renders, the default --jobs 1 avoids them.
  * The viewer draws OBJ with X3D Phong Material (two-sided, plus 0.2 x
    ambientIntensity x diffuse, where it maps MTL Ka to ambientIntensity =
    Ka/Kd, and Ks specular) and glTF with PBR PhysicalMaterial (about
    1/pi of the Phong diffuse in linear light, gamma-corrected), and
    KHR_materials_unlit as UnlitMaterial: the figures compare what that
    viewer shows, not albedos.

Exit status: 0 success; 1 bad command line; 2 a tool (view3dscene, xvfb-run,
bbcgen) or an input file is missing; 3 a render failed (view3dscene error,
a warning about a file it could not load, or a blank image: no covered pixel).
"""

import argparse
import concurrent.futures
import json
import math
import os
import random
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import zlib

KEYS = ((255, 0, 255), (0, 255, 0))      # magenta and green backgrounds
LUMA = (0.2126, 0.7152, 0.0722)


class Failure(Exception):
    def __init__(self, msg, code=3):
        super().__init__(msg)
        self.code = code


# --------------------------------------------------------------------- PNG --

def _png_pure(path):
    """Minimal PNG reader: 8-bit grey/RGB/grey-alpha/RGBA, not interlaced."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise Failure("%s: not a PNG" % path)
    pos, idat, hdr = 8, [], None
    while pos < len(data):
        n, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + n]
        pos += 12 + n
        if kind == b"IHDR":
            hdr = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
    w, h, depth, ctype, _, _, interlace = hdr
    chans = {0: 1, 2: 3, 4: 2, 6: 4}.get(ctype)
    if depth != 8 or chans is None or interlace:
        raise Failure("%s: unsupported PNG (depth %d, colour type %d)"
                      % (path, depth, ctype))
    raw = zlib.decompress(b"".join(idat))
    stride, bpp = w * chans, chans
    out = bytearray(h * stride)
    prev = bytearray(stride)
    for y in range(h):
        ft = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        if ft == 1:
            for i in range(bpp, stride):
                line[i] = (line[i] + line[i - bpp]) & 255
        elif ft == 2:
            for i in range(stride):
                line[i] = (line[i] + prev[i]) & 255
        elif ft == 3:
            for i in range(stride):
                a = line[i - bpp] if i >= bpp else 0
                line[i] = (line[i] + ((a + prev[i]) >> 1)) & 255
        elif ft == 4:
            for i in range(stride):
                a = line[i - bpp] if i >= bpp else 0
                b = prev[i]
                c = prev[i - bpp] if i >= bpp else 0
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pr = a if (pa <= pb and pa <= pc) else (b if pb <= pc else c)
                line[i] = (line[i] + pr) & 255
        out[y * stride:(y + 1) * stride] = line
        prev = line
    rgb = bytearray(w * h * 3)
    for i in range(w * h):
        px = out[i * chans:(i + 1) * chans]
        rgb[i * 3:i * 3 + 3] = px[:3] if chans >= 3 else bytes([px[0]] * 3)
    return w, h, bytes(rgb)


def read_rgb(path):
    """(width, height, bytes RGB RGB ...). PIL, else ImageMagick, else pure."""
    try:
        from PIL import Image
        im = Image.open(path).convert("RGB")
        return im.size[0], im.size[1], im.tobytes()
    except ImportError:
        pass
    conv = shutil.which("magick") or shutil.which("convert")
    if conv:
        try:
            ident = subprocess.run([conv, path, "-format", "%w %h", "info:"],
                                   capture_output=True, text=True, check=True)
            w, h = (int(v) for v in ident.stdout.split()[:2])
            raw = subprocess.run([conv, path, "-depth", "8", "rgb:-"],
                                 capture_output=True, check=True).stdout
            if len(raw) == w * h * 3:
                return w, h, raw
        except (subprocess.CalledProcessError, ValueError):
            pass
    return _png_pure(path)


# ---------------------------------------------------------------- geometry --

def qmul(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return (aw * bw - ax * bx - ay * by - az * bz,
            aw * bx + ax * bw + ay * bz - az * by,
            aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw)


def camera(center, dist, az_deg, el_deg):
    """Position and X3D orientation (axis, angle) looking at center from
    azimuth az (0 = +Z, 90 = +X) and elevation el (degrees), Y up."""
    az, el = math.radians(az_deg), math.radians(el_deg)
    d = (math.sin(az) * math.cos(el), math.sin(el), math.cos(az) * math.cos(el))
    pos = [center[i] + dist * d[i] for i in range(3)]
    qy = (math.cos(az / 2), 0.0, math.sin(az / 2), 0.0)
    qx = (math.cos(-el / 2), math.sin(-el / 2), 0.0, 0.0)
    w, x, y, z = qmul(qy, qx)
    angle = 2 * math.acos(max(-1.0, min(1.0, w)))
    s = math.sqrt(max(0.0, 1 - w * w))
    axis = (x / s, y / s, z / s) if s > 1e-9 else (0.0, 1.0, 0.0)
    return pos, axis, angle


def x3d_string(s):
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def wrapper_scene(model, pos, axis, angle, fov, key, near, far):
    k = " ".join("%.6g" % (c / 255.0) for c in key)
    return """#X3D V3.2 utf8
PROFILE Interchange
NavigationInfo {
  headlight TRUE
  type "EXAMINE"
  avatarSize [ %.9g 1.6 0.75 ]
  visibilityLimit %.9g
}
Background { skyColor [ %s ] }
Viewpoint {
  position %.9g %.9g %.9g
  orientation %.9g %.9g %.9g %.9g
  fieldOfView %.9g
  description "viewer_brightness"
}
Inline { url [ %s ] }
""" % (near, far, k, pos[0], pos[1], pos[2], axis[0], axis[1], axis[2],
       angle, fov, x3d_string(os.path.abspath(model)))


# ------------------------------------------------------------------- tools --

def find_bbcgen(given):
    if given:
        if not (os.path.isfile(given) and os.access(given, os.X_OK)):
            raise Failure("bbcgen not found or not executable: %s" % given, 2)
        return given
    here = os.path.dirname(os.path.abspath(__file__))
    cand = os.path.join(here, "..", "..", "build", "bin", "bbcgen")
    if os.path.isfile(cand) and os.access(cand, os.X_OK):
        return os.path.normpath(cand)
    found = shutil.which("bbcgen")
    if found:
        return found
    raise Failure("bbcgen not found (build it, or pass --bbcgen PATH): it "
                  "gives the ORIGINAL's bounding sphere", 2)


def bounding_sphere(bbcgen, model):
    r = subprocess.run([bbcgen, "info", "--json", "--no-textures", model],
                       capture_output=True, text=True)
    if r.returncode != 0:
        raise Failure("`bbcgen info` failed on %s (exit %d): %s"
                      % (model, r.returncode, r.stderr.strip()[-400:]), 2)
    info = json.loads(r.stdout)
    c, rad = info.get("center"), info.get("radius")
    if not c or not rad or rad <= 0:
        bb = info["bbox"]
        c = [(a + b) / 2 for a, b in zip(bb["min"], bb["max"])]
        rad = 0.5 * math.dist(bb["min"], bb["max"])
    return [float(v) for v in c], float(rad), info


def render_batch(jobs_path):
    """Runs inside xvfb-run: every job of the JSON list, a few at a time."""
    with open(jobs_path) as f:
        spec = json.load(f)

    def one(job):
        env = dict(os.environ, XDG_CONFIG_HOME=job["cfg"])
        os.makedirs(job["cfg"], exist_ok=True)
        lp = os.path.join(job["cfg"], "view3dscene", "view3dscene.log")
        for attempt in range(8):
            try:
                r = subprocess.run(job["cmd"], capture_output=True, text=True,
                                   env=env, timeout=spec["timeout"])
                rc, err = r.returncode, (r.stdout + r.stderr)
            except subprocess.TimeoutExpired:
                rc, err = 124, "timed out after %d s" % spec["timeout"]
            log = ""
            if os.path.exists(lp):
                with open(lp, errors="replace") as f:
                    log = f.read()
            # view3dscene (FPC) locks the files it reads: a second process
            # opening the same model or texture at that moment gets EAGAIN
            # ("Try again") and draws without it. Run it again.
            if "Try again" not in err + log:
                break
            time.sleep(0.2 + random.random() * (attempt + 1))
        return {"png": job["png"], "rc": rc, "stderr": err[-2000:],
                "log": log[-6000:]}

    with concurrent.futures.ThreadPoolExecutor(spec["jobs"]) as ex:
        res = list(ex.map(one, spec["list"]))
    with open(spec["result"], "w") as f:
        json.dump(res, f)
    return 0


# Log lines that mean a render is wrong (a file not loaded, a crash); other
# warnings are only reported.
FATAL_WORDS = ("error", "exception", "try again", "no such file",
               "not found", "cannot load", "cannot open", "could not")
IGNORED_WARNINGS = ("ApplicationConfig(", "OpenAL",
                    "Loaded data from an absolute filename")


def problems_of(res):
    """(fatal problems, other warnings) of one render."""
    bad, notes = [], []
    if res["rc"] != 0:
        bad.append("exit status %d" % res["rc"])
    for line in (res["stderr"] + "\n" + res["log"]).splitlines():
        low = line.lower().strip()
        if any(s in line for s in IGNORED_WARNINGS):
            continue
        if any(w in low for w in FATAL_WORDS):
            bad.append(line.strip())
        elif low.startswith("warning"):
            notes.append(line.strip())
    if not os.path.exists(res["png"]):
        bad.append("no screenshot written")
    return bad, notes


# ---------------------------------------------------------------- analysis --

def matte(path_a, path_b):
    """Difference matting of the magenta (a) and green (b) renders.
    Returns coverage (sum of alpha), opaque pixel count and sums of the
    premultiplied R, G, B."""
    wa, ha, a = read_rgb(path_a)
    wb, hb, b = read_rgb(path_b)
    if (wa, ha) != (wb, hb):
        raise Failure("renders differ in size: %s %dx%d, %s %dx%d"
                      % (path_a, wa, ha, path_b, wb, hb))
    k1, k2 = KEYS
    dk = [k1[c] - k2[c] for c in range(3)]
    cov = 0.0
    opaque = 0
    s = [0.0, 0.0, 0.0]
    for i in range(0, len(a), 3):
        pa = a[i:i + 3]
        pb = b[i:i + 3]
        if pa == pb:            # opaque: the same on both backgrounds
            cov += 1.0
            opaque += 1
            s[0] += pa[0]
            s[1] += pa[1]
            s[2] += pa[2]
            continue
        t = ((pa[0] - pb[0]) / dk[0] + (pa[1] - pb[1]) / dk[1]
             + (pa[2] - pb[2]) / dk[2]) / 3.0
        t = min(1.0, max(0.0, t))
        al = 1.0 - t
        if al < 1.0 / 255:
            continue
        cov += al
        for c in range(3):
            # premultiplied colour, from both renders
            v = 0.5 * ((pa[c] - t * k1[c]) + (pb[c] - t * k2[c]))
            s[c] += min(255.0 * al, max(0.0, v))
    return {"w": wa, "h": ha, "coverage": cov, "opaque": opaque, "sum": s}


def summary(m):
    cov = m["coverage"]
    rgb = [v / cov for v in m["sum"]] if cov > 0 else [0.0, 0.0, 0.0]
    return {"covered_px": round(cov, 1), "opaque_px": m["opaque"],
            "mean_rgb": [round(v, 2) for v in rgb],
            "luminance": round(sum(LUMA[c] * rgb[c] for c in range(3)), 2)}


def ratio(x, y):
    return round(x / y, 4) if y > 0 else None


def compare(o, c):
    return {"ratio_rgb": [ratio(c["mean_rgb"][i], o["mean_rgb"][i])
                          for i in range(3)],
            "ratio_luminance": ratio(c["luminance"], o["luminance"]),
            "coverage_ratio": ratio(c["covered_px"], o["covered_px"])}


# -------------------------------------------------------------------- main --

def main(argv):
    if len(argv) == 2 and argv[0] == "--render-batch":
        return render_batch(argv[1])
    ap = argparse.ArgumentParser(
        description="Compare how bright ORIGINAL and CLOUD look in "
                    "view3dscene (same camera, same headlight).")
    ap.add_argument("original")
    ap.add_argument("cloud")
    ap.add_argument("--views", type=int, default=4,
                    help="azimuths around the up axis (4)")
    ap.add_argument("--size", type=int, default=256,
                    help="screenshot side in pixels (256)")
    ap.add_argument("--elevation", type=float, default=10.0,
                    help="camera elevation in degrees (10)")
    ap.add_argument("--fov", type=float, default=30.0,
                    help="field of view in degrees (30)")
    ap.add_argument("--json", metavar="OUT.json")
    ap.add_argument("--keep", metavar="DIR",
                    help="keep screenshots and wrapper scenes in DIR")
    ap.add_argument("--bbcgen", metavar="PATH",
                    help="bbcgen for the bounding sphere "
                         "(default: build/bin/bbcgen next to this script, "
                         "else PATH)")
    ap.add_argument("--frame", metavar="MODEL",
                    help="take the bounding sphere from MODEL instead of "
                         "ORIGINAL (when bbcgen cannot read ORIGINAL, e.g. "
                         "an X3D file)")
    ap.add_argument("--jobs", type=int, default=1,
                    help="view3dscene processes at a time (1)")
    ap.add_argument("--timeout", type=int, default=300,
                    help="seconds per render (300)")
    args = ap.parse_args(argv)
    if args.views < 1 or args.size < 16 or not 1 <= args.fov < 170 \
            or args.jobs < 1 or not -89 <= args.elevation <= 89:
        ap.error("bad --views/--size/--fov/--jobs/--elevation")

    try:
        return run(args)
    except Failure as e:
        print("viewer_brightness: error: %s" % e, file=sys.stderr)
        return e.code


def run(args):
    for tool in ("view3dscene", "xvfb-run"):
        if not shutil.which(tool):
            raise Failure("%s not found on PATH (Debian: apt-get install "
                          "view3dscene xvfb xauth)" % tool, 2)
    for p in (args.original, args.cloud):
        if not os.path.isfile(p):
            raise Failure("no such file: %s" % p, 2)
    bbcgen = find_bbcgen(args.bbcgen)
    if args.frame and not os.path.isfile(args.frame):
        raise Failure("no such file: %s" % args.frame, 2)
    center, radius, _ = bounding_sphere(bbcgen, args.frame or args.original)
    half = math.radians(args.fov) / 2
    dist = 1.05 * radius / math.sin(half)
    near, far = max(dist - 2 * radius, dist * 1e-3) * 0.5, dist + 4 * radius

    work = tempfile.mkdtemp(prefix="viewer_brightness_")
    out_dir = os.path.abspath(args.keep) if args.keep else work
    os.makedirs(out_dir, exist_ok=True)
    try:
        files = (("original", args.original), ("cloud", args.cloud))
        jobs, views = [], []
        geom = "%dx%d" % (args.size, args.size)
        for v in range(args.views):
            az = 360.0 * v / args.views
            pos, axis, angle = camera(center, dist, az, args.elevation)
            views.append({"azimuth": az, "elevation": args.elevation,
                          "position": [round(p, 6) for p in pos]})
            for tag, model in files:
                for ki, key in enumerate(KEYS):
                    base = "v%d_%s_%s" % (v, tag, ("magenta", "green")[ki])
                    scene = os.path.join(out_dir, base + ".x3dv")
                    with open(scene, "w") as f:
                        f.write(wrapper_scene(model, pos, axis, angle,
                                              math.radians(args.fov), key,
                                              near, far))
                    png = os.path.join(out_dir, base + ".png")
                    if os.path.exists(png):
                        os.remove(png)
                    jobs.append({
                        "png": png, "cfg": os.path.join(work, "cfg_" + base),
                        "cmd": ["view3dscene", scene, "--geometry", geom,
                                "--hide-extras", "--hide-menu",
                                "--anti-alias", "0", "--no-sound",
                                "--screenshot", "0", png]})
        spec = {"list": jobs, "jobs": args.jobs, "timeout": args.timeout,
                "result": os.path.join(work, "result.json")}
        with open(os.path.join(work, "jobs.json"), "w") as f:
            json.dump(spec, f)
        screen = "-screen 0 %dx%dx24" % (max(1280, args.size + 64),
                                         max(1024, args.size + 64))
        r = subprocess.run(["xvfb-run", "-a", "-s", screen, sys.executable,
                            os.path.abspath(__file__), "--render-batch",
                            os.path.join(work, "jobs.json")],
                           capture_output=True, text=True)
        if r.returncode != 0 or not os.path.exists(spec["result"]):
            raise Failure("xvfb-run failed (exit %d): %s"
                          % (r.returncode, (r.stdout + r.stderr)[-800:]))
        with open(spec["result"]) as f:
            results = json.load(f)
        warnings = []
        for res in results:
            bad, notes = problems_of(res)
            if bad:
                raise Failure("render %s: %s"
                              % (os.path.basename(res["png"]),
                                 "; ".join(bad[:6])))
            for n in notes:
                if n not in warnings:
                    warnings.append(n)
        for n in warnings:
            print("viewer_brightness: view3dscene: %s" % n, file=sys.stderr)

        tot = {t: {"coverage": 0.0, "opaque": 0, "sum": [0.0] * 3}
               for t, _ in files}
        for v, view in enumerate(views):
            for tag, _ in files:
                a = os.path.join(out_dir, "v%d_%s_magenta.png" % (v, tag))
                b = os.path.join(out_dir, "v%d_%s_green.png" % (v, tag))
                m = matte(a, b)
                if m["coverage"] < 1.0:
                    raise Failure("view %d (azimuth %g): the %s render is "
                                  "blank, no covered pixel (%s)"
                                  % (v, view["azimuth"], tag,
                                     a if args.keep else
                                     "rerun with --keep DIR to see it"))
                view[tag] = summary(m)
                tot[tag]["coverage"] += m["coverage"]
                tot[tag]["opaque"] += m["opaque"]
                for c in range(3):
                    tot[tag]["sum"][c] += m["sum"][c]
            view.update(compare(view["original"], view["cloud"]))
        overall_o, overall_c = summary(tot["original"]), summary(tot["cloud"])
        report = {
            "original": os.path.abspath(args.original),
            "cloud": os.path.abspath(args.cloud),
            "viewer": "view3dscene, headlight, no anti-aliasing",
            "size": args.size, "fov_deg": args.fov,
            "bounding_sphere": {"center": center, "radius": radius},
            "camera_distance": dist,
            "original_overall": overall_o, "cloud_overall": overall_c,
        }
        report.update(compare(overall_o, overall_c))
        report["views"] = views
        report["viewer_warnings"] = warnings
    finally:
        shutil.rmtree(work, ignore_errors=True)

    print_table(report)
    if args.json:
        with open(args.json, "w") as f:
            json.dump(report, f, indent=2)
            f.write("\n")
    return 0


def print_table(rep):
    def fmt(v):
        return "   -  " if v is None else "%6.3f" % v
    print("original: %s" % rep["original"])
    print("cloud:    %s" % rep["cloud"])
    print("view3dscene, headlight, %dx%d px, fov %g deg; mean sRGB over "
          "covered pixels (0-255)" % (rep["size"], rep["size"],
                                      rep["fov_deg"]))
    hdr = ("%-9s %-22s %-22s %8s %8s  %-20s %6s %6s"
           % ("view", "original R G B", "cloud R G B", "orig Y", "cloud Y",
              "ratio R G B", "ratioY", "cover"))
    print(hdr)
    print("-" * len(hdr))

    def row(name, o, c, r):
        print("%-9s %-22s %-22s %8.1f %8.1f  %-20s %6s %6s"
              % (name, " ".join("%6.1f" % x for x in o["mean_rgb"]),
                 " ".join("%6.1f" % x for x in c["mean_rgb"]),
                 o["luminance"], c["luminance"],
                 " ".join(fmt(x) for x in r["ratio_rgb"]),
                 fmt(r["ratio_luminance"]), fmt(r["coverage_ratio"])))
    for v in rep["views"]:
        row("az %g" % v["azimuth"], v["original"], v["cloud"], v)
    print("-" * len(hdr))
    row("overall", rep["original_overall"], rep["cloud_overall"], rep)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
