"""blender_import.py — what Blender's importers make of files: run as
`blender -b --factory-startup --python scripts/studies/blender_import.py -- FILE...`
(scripts/studies/blender_import.sh). For each file, in a fresh scene: the objects
(mesh objects and their names), triangles, materials, whether each material
has an image texture with pixels, whether its alpha reaches the shader
(an image's alpha linked into the Principled BSDF's Alpha) and its blend
mode (CLIP = alpha test). One JSON object per file on stdout, prefixed
"BBC_IMPORT ". Importers: .glb/.gltf (glTF 2.0), .fbx, .obj."""
import json
import sys

import bpy

try:  # Blender 3.4's glTF importer uses aliases numpy 1.24 removed
    import numpy as np
    for alias, typ in (("bool", np.bool_), ("int", int), ("float", float),
                       ("object", object)):
        if not hasattr(np, alias):
            setattr(np, alias, typ)
except ImportError:
    pass

files = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
for path in files:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    low = path.lower()
    try:
        if low.endswith((".glb", ".gltf")):
            bpy.ops.import_scene.gltf(filepath=path)
        elif low.endswith(".fbx"):
            bpy.ops.import_scene.fbx(filepath=path)
        elif low.endswith(".obj"):
            bpy.ops.import_scene.obj(filepath=path)
        else:
            raise RuntimeError("no importer for " + path)
    except Exception as e:  # an importer's failure is a finding, not a crash
        print("BBC_IMPORT " + json.dumps({"file": path, "error": str(e)}))
        continue
    meshes = [o for o in bpy.data.objects if o.type == "MESH"]
    tris = 0
    for o in meshes:
        o.data.calc_loop_triangles()
        tris += len(o.data.loop_triangles)
    mats = []
    for m in bpy.data.materials:
        if not m.use_nodes:
            continue
        imgs = [n.image for n in m.node_tree.nodes if n.type == "TEX_IMAGE" and n.image]
        bsdf = [n for n in m.node_tree.nodes if n.type == "BSDF_PRINCIPLED"]
        alpha_linked = bool(bsdf) and bsdf[0].inputs["Alpha"].is_linked
        mats.append({"name": m.name, "images": len(imgs),
                     "image_pixels": all(i.size[0] > 0 for i in imgs) and len(imgs) > 0,
                     "alpha_linked": alpha_linked, "blend": m.blend_method})
    print("BBC_IMPORT " + json.dumps({
        "file": path, "objects": len(meshes), "names": sorted(o.name for o in meshes),
        "roots": sorted(o.name for o in bpy.data.objects if o.parent is None),
        "triangles": tris, "materials": mats}))
