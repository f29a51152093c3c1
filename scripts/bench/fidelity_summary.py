#!/usr/bin/env python3
"""fidelity_summary.py RESULTS.json — from `make bench`'s JSON lines
(bench/results/latest.json), one Markdown row per tree: the default cloud's
mean IoU (all views, side views in brackets) against 3 crossed billboards with
the same texels and against meshoptimizer and gltfpack aimed at 1x and 10x the
cloud's triangles, and whether the cloud wins. A baseline that ends above 1.5x
its triangle target did not simplify to the budget: it is shown but not
counted; a tree whose original has no more triangles than 10x the cloud's has
nothing to simplify at that budget."""
import json
import sys

rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
fid = [r for r in rows if r.get('bench') == 'fidelity']
models = []
for r in fid:
    if r['model'] not in models:
        models.append(r['model'])
print("| model | triangles | cloud: planes / triangles / texels | cloud | 3 crossed, same texels | "
      "meshopt 1x | sloppy 1x | meshopt 10x | sloppy 10x | gltfpack 10x | cloud wins |")
print("|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---|")
for m in models:
    mine = [r for r in fid if r['model'] == m]
    cloud = next((r for r in mine if r['method'] == 'cloud'), None)
    if not cloud:
        continue
    t1, t10 = cloud['triangles'], 10 * cloud['triangles']

    def get(name):
        return next((r for r in mine if r['method'] == name), None)

    def met(r, target):
        return r is not None and r['triangles'] <= 1.5 * target

    x3 = get('crossed 3')
    ms1, sl1 = get(f'meshopt simplify {t1}'), get(f'meshopt sloppy {t1}')
    ms10, sl10 = get(f'meshopt simplify {t10}'), get(f'meshopt sloppy {t10}')
    gp = next((r for r in mine if r['method'].startswith('gltfpack') and
               not r['method'].rstrip().endswith('-sa')), None)

    def cell(r, target=None):
        if not r:
            return '-'
        s = f"{r['iou']:.3f}"
        if target is None:
            return s + f" ({r['iou_side']:.3f})"
        s += f" ({r['triangles']:,})"
        return s if met(r, target) else s + ' missed'
    counted = [r for r in (x3,) if r] + [r for r, t in ((ms1, t1), (sl1, t1), (ms10, t10),
                                                       (sl10, t10), (gp, t10)) if met(r, t)]
    lost = [r['method'].rstrip() for r in counted if r['iou'] >= cloud['iou']]
    if cloud['model_triangles'] <= t10:
        verdict = 'n/a at 10x: the original has %s triangles' % f"{cloud['model_triangles']:,}"
        if lost:
            verdict += '; loses to ' + ', '.join(lost)
    else:
        verdict = 'yes' if not lost else 'no: ' + ', '.join(lost)
    name = m[m.find('shared/data/') + 12:] if 'shared/data/' in m else m
    print(f"| {name} | {cloud['model_triangles']:,} | {cloud['planes']} / {t1} / "
          f"{cloud['texels']:,} | {cell(cloud)} | {cell(x3)} | {cell(ms1, t1)} | {cell(sl1, t1)} | "
          f"{cell(ms10, t10)} | {cell(sl10, t10)} | {cell(gp, t10)} | {verdict} |")
