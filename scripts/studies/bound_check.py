#!/usr/bin/env python3
# bound_check.py MODEL.obj|MODEL.ply PLANES.json — the error bound checked
# without the project's code: reads the model's faces (OBJ, polygons as
# fans) or points (PLY, binary or ASCII) itself, and the planes of
# `bbcgen planes MODEL --json PLANES.json`, and counts the faces (all their
# vertices) or points within epsilon of no plane of the set, and, where the
# JSON's face_plane follows the file's faces, those beyond epsilon of their
# own plane and those not on the limbs mesh (face_plane -1) that no plane
# holds. Needs numpy (Debian python3-numpy). bench/results/bound.md.
import json
import sys

import numpy as np
path, js = sys.argv[1], sys.argv[2]
j = json.load(open(js))
P = [p for p in j['planes'] if p['kind'] != 'cardboard']
N = np.array([p['normal'] for p in P]); D = np.array([p['d'] for p in P])
eps = max(pt['epsilon_abs'] for pt in j['parts'])
def read_obj(p):
    V=[];F=[]
    for line in open(p, errors='replace'):
        if line.startswith('v '): V.append([float(x) for x in line.split()[1:4]])
        elif line.startswith('f '):
            ids=[int(t.split('/')[0]) for t in line.split()[1:]]
            ids=[i-1 if i>0 else len(V)+i for i in ids]
            for k in range(1,len(ids)-1): F.append([ids[0],ids[k],ids[k+1]])
    return np.array(V), np.array(F)
def read_ply(p):
    b=open(p,'rb').read(); h=b[:b.index(b'end_header')+11].decode(); body=b[len(h):].lstrip(b'\r\n') if 'ascii' in h else b[len(h):]
    lines=h.split('\n'); nv=0; props=[]; fmt=None; cur=None
    for l in lines:
        t=l.split()
        if not t: continue
        if t[0]=='format': fmt=t[1]
        if t[0]=='element': cur=t[1]; n=int(t[2]); nv = n if cur=='vertex' else nv
        if t[0]=='property' and cur=='vertex': props.append((t[2],t[1]))
    if fmt=='ascii':
        a=np.array([list(map(float,l.split()[:len(props)])) for l in body.decode().split('\n')[:nv]])
    else:
        tm={'float':'f4','float32':'f4','double':'f8','float64':'f8','uchar':'u1','uint8':'u1','int':'i4','int32':'i4','short':'i2','ushort':'u2'}
        dt=np.dtype([(nm,('<' if 'little' in fmt else '>')+tm[ty]) for nm,ty in props])
        a=np.frombuffer(body[:dt.itemsize*nv],dtype=dt); a=np.stack([a['x'],a['y'],a['z']],1).astype(float)
    return a[:,:3], None
V,F = read_obj(path) if path.endswith('.obj') else read_ply(path)
best = np.full(len(F) if F is not None else len(V), np.inf)
for k in range(len(P)):
    d = np.abs(V @ N[k] - D[k])
    m = d[F].max(1) if F is not None else d
    best = np.minimum(best, m)
tol = eps*(1+1e-6)
out = best > tol
nolimbs = sum(1 for x in j['face_plane'] if x is None or x == -1 or (isinstance(x,int) and x >= len(j['planes'])))
print(f"{path}: {len(best)} {'faces' if F is not None else 'points'}, eps {eps:.4g}, {len(P)} planes: {out.sum()} within eps of no plane (farthest {best.max()/eps:.2f} eps); on no plane in the set (limbs): {nolimbs}")
if F is not None and len(j['face_plane']) == len(F):
    fp = np.array(j['face_plane']); idx = np.nonzero(fp >= 0)[0]
    Nn = np.array([p['normal'] for p in j['planes']]); Dd = np.array([p['d'] for p in j['planes']])
    dist = np.abs(np.einsum('fvk,fk->fv', V[F[idx]], Nn[fp[idx]]) - Dd[fp[idx]][:,None]).max(1)
    lim = fp < 0
    print(f"  in file order: {(dist > tol).sum()} of {len(idx)} faces beyond eps of their own plane (farthest {dist.max()/eps:.2f} eps); faces within eps of no plane that are not limbs: {(out & ~lim).sum()}")
