#!/usr/bin/env python3
"""The table of scripts/studies/sun_sweep.sh: OUTDIR/<tree>/threejs.json (from
scripts/studies/threejs_sun.sh with the material cloud first, the baked cloud second)
as Markdown on stdout.

    python3 scripts/studies/sun_sweep_table.py OUTDIR [LABEL]

LABEL names the second cloud's columns (default `--lighting baked`).
"""
import json
import os
import sys


def main():
    if len(sys.argv) not in (2, 3):
        print(__doc__, file=sys.stderr)
        return 1
    out = sys.argv[1]
    label = sys.argv[2] if len(sys.argv) == 3 else "`--lighting baked`"
    rows = []
    for name in sorted(os.listdir(out)):
        path = os.path.join(out, name, "threejs.json")
        if not os.path.isfile(path):
            continue
        with open(path) as f:
            j = json.load(f)
        s = j["summary"]
        albedo = None
        apath = os.path.join(out, name, "albedo.json")
        if os.path.isfile(apath):
            with open(apath) as f:
                albedo = json.load(f)["brightness_ratio"]
        rows.append((name, s[0], s[1] if len(s) > 1 else None, j["options"], albedo))
    if not rows:
        print("no OUTDIR/<tree>/threejs.json", file=sys.stderr)
        return 2
    o = rows[0][3]
    print("# Relighting in three.js: cloud / original luminance\n")
    print(
        "three.js in headless Chromium (scripts/studies/threejs_sun.sh): ambient %s + a directional sun "
        "of %s from 8 azimuths x 2 elevations (15, 50 deg), front and side views, %s px; the "
        "original's materials as glTF metallic-roughness. Per tree: the range of the cloud's "
        "luminance over the original's over the %s renders, and how many fall outside "
        "0.90-1.10.\n" % (o.get("ambient"), o.get("sunIntensity"), o.get("size"),
                          rows[0][1]["renders"]))
    print("| tree | default (material) min | max | mean | outside | "
          "coverage | %s min | max | outside | albedo R G B | result |" % label)
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---|---|")
    fails = 0
    for name, m, b, _, albedo in rows:
        colours_ok = albedo is not None and all(0.9 <= a <= 1.1 for a in albedo)
        ok = m["outside"] == 0 and m["blank"] == 0 and colours_ok
        fails += not ok
        bt = ("%.3f | %.3f | %d" % (b["lumRatio"]["min"], b["lumRatio"]["max"], b["outside"])
              if b else "- | - | -")
        at = " ".join("%.3f" % a for a in albedo) if albedo else "-"
        print("| %s | %.3f | %.3f | %.3f | %d/%d | %.2f-%.2f | %s | %s | %s |" % (
            name, m["lumRatio"]["min"], m["lumRatio"]["max"], m["lumRatio"]["mean"],
            m["outside"], m["renders"], m["coverageRatio"]["min"], m["coverageRatio"]["max"],
            bt, at, "ok" if ok else "FAIL"))
    print("\nalbedo: the material cloud's mean colour over the original's, per channel, unlit "
          "(`bbcgen eval --no-lit --views 32`; within 0.90-1.10 asked).\n")
    print("%d of %d trees inside the band on every render, colours within 10 %%."
          % (len(rows) - fails, len(rows)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
