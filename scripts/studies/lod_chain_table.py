#!/usr/bin/env python3
"""lod_chain_table.py OUTDIR: the table of scripts/studies/lod_chain.sh from each
OUTDIR/<tree>/r.json (the report: per level epsilon, billboards, triangles,
texels, texres, screen size) and eval.json (bbcgen eval's levels: side
coverage ratio and side block IoU at the level's screen size)."""
import json
import os
import sys

out = sys.argv[1]
print("| tree | level | screen px | epsilon used | billboards | triangles | texels | texres |"
      " side coverage | side block IoU | result |")
print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|")
worst = [9.0, 0.0]
for name in sorted(os.listdir(out)):
    r_path, e_path = os.path.join(out, name, "r.json"), os.path.join(out, name, "eval.json")
    if not (os.path.exists(r_path) and os.path.exists(e_path)):
        continue
    lods = json.load(open(r_path))["lods"]
    levels = json.load(open(e_path)).get("levels", [])
    ok = len(levels) == len(lods)
    for k, lv in enumerate(lods):
        if k and not (lv["texels"] < lods[k - 1]["texels"] and
                      lv["triangles"] < lods[k - 1]["triangles"]):
            ok = False
        ev = levels[k] if k < len(levels) else {}
        cov = ev.get("coverage_ratio_side_mean")
        if cov is None or not 0.85 <= cov <= 1.15:
            ok = False
        if cov is not None:
            worst = [min(worst[0], cov), max(worst[1], cov)]
    for k, lv in enumerate(lods):
        ev = levels[k] if k < len(levels) else {}
        cov, blk = ev.get("coverage_ratio_side_mean"), ev.get("block_iou_side_mean")
        print("| %s | %d | %s | %.3g | %d | %d | %d | %d | %s | %s | %s |" % (
            name if k == 0 else "", k, "%g" % lv.get("screen_px", 0),
            lv["epsilon_pct_used"], lv["billboards"], lv["triangles"], lv["texels"],
            lv["texres_used"], "%.3f" % cov if cov is not None else "n/a",
            "%.3f" % blk if blk is not None else "n/a",
            ("ok" if ok else "FAIL") if k == 0 else ""))
print()
print("Side coverage ratio over all levels: %.3f .. %.3f" % (worst[0], worst[1]))
