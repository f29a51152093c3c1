#!/usr/bin/env bash
# fuzz_seeds.sh DIR — seed corpora for the fuzzers in DIR/HARNESS/seeds:
# small files (under 64 KiB) of ../shared/data, head excerpts of the bigger
# point files, and a few generated inputs of each format. Nothing is copied
# into the repository.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
data="$root/../shared/data"
dir=${1:?usage: fuzz_seeds.sh DIR}
for h in fuzz_ply fuzz_xyz fuzz_wrl fuzz_forest_map fuzz_forest_model fuzz_batch fuzz_scene fuzz_objr fuzz_obj fuzz_3ds fuzz_glb; do
  mkdir -p "$dir/$h/seeds"
done
seed() { # HARNESS NAME < content
  cat > "$dir/$1/seeds/$2"
}
if [ -d "$data" ]; then
  find "$data" -type f -size -64k \( -name '*.ply' \) -exec cp {} "$dir/fuzz_ply/seeds/" \; 2>/dev/null || true
  find "$data" -type f -size -64k \( -name '*.wrl' \) -exec cp {} "$dir/fuzz_wrl/seeds/" \; 2>/dev/null || true
  for f in "$data"/points/*.xyz "$data"/points/adtree/*.xyz; do
    [ -f "$f" ] && head -c 16384 "$f" > "$dir/fuzz_xyz/seeds/$(basename "$f")"
  done
  find "$data" -type f -size -64k -name '*.obj' -exec cp {} "$dir/fuzz_obj/seeds/" \; 2>/dev/null || true
  find "$data" -type f -size -64k -name '*.obj' -exec cp {} "$dir/fuzz_objr/seeds/" \; 2>/dev/null || true
  for f in "$data"/models/*.3ds; do # small 3DS files whole, the others' first chunks
    [ -f "$f" ] && head -c 65536 "$f" > "$dir/fuzz_3ds/seeds/$(basename "$f")"
  done
  for f in "$data"/points/*.ply; do # the header and the first records
    [ -f "$f" ] && head -c 8192 "$f" > "$dir/fuzz_ply/seeds/head_$(basename "$f")"
  done
fi
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 255 0 0\n1 0 0 0 255 0\n0 1 0 0 0 255\n3 0 1 2\n' | seed fuzz_ply tri_ascii.ply
printf 'ply\nformat binary_little_endian 1.0\nelement vertex 2\nproperty double x\nproperty double y\nproperty double z\nend_header\n' > "$dir/fuzz_ply/seeds/bin.ply"
head -c 48 /dev/zero >> "$dir/fuzz_ply/seeds/bin.ply"
printf '# x y z\n1 2 3\n4,5,6\n7\t8\t9 extra\n519054.680 5357592.050 4.760\n' | seed fuzz_xyz mixed.xyz
printf '3\n1 2 3\n4 5 6\n7 8 9\n' | seed fuzz_xyz counted.pts
printf '#VRML V2.0 utf8\nDEF T Transform { translation 1 2 3 rotation 0 1 0 1.57 scale 2 2 2 children [\n Shape { appearance Appearance { material Material { diffuseColor 1 0 0 } texture ImageTexture { url "t.png" } }\n geometry IndexedFaceSet { coord Coordinate { point [ 0 0 0, 1 0 0, 0 1 0 ] } coordIndex [ 0 1 2 -1 ] texCoord TextureCoordinate { point [ 0 0, 1 0, 0 1 ] } texCoordIndex [ 0 1 2 -1 ] solid FALSE } }\n Shape { geometry PointSet { coord Coordinate { point [ 0 0 0, 1 1 1 ] } color Color { color [ 1 0 0, 0 1 0 ] } } }\n] }\nUSE T\nLOD { level [ Group { children [] } ] }\n' | seed fuzz_wrl scene.wrl
printf "' a map with every command of Appendix B\nhmap terrain.png\nhmapfilter 2 3\ncolmap colour.png\nheightscale 10.0\nstretch 2.0\nlight 1 -2 0.5\nfarclip 400\nroetger 12.5\nskymap sky/clouds\nwaterheight 15.5\nfog 100 900\nnumobjs 38001\nobject2d house.txt 1.5 1 100 200 0 90 0 -0.5\nrndtree tupelo.txt 1.0 20000 1 1 0 0 0 0\nrndtree2 foliage.wrl \"stem file.wrl\" 0.8 18000 0 1 -90 0 0 0.25\n" | seed fuzz_forest_map every.txt
printf "fade 250\n' a shadow\nshadowrad 5.2\nshadowcutoff 2.0\nLOD\n(\n    file1 tree.3ds displaylist lighting\n    min 0\n    max 1000\n)\nLOD\n(\n    file1 treefoliage.wrl displaylist\n    file2 treetrunk.wrl displaylist\n    min 1000\n    max 5000\n)\n" | seed fuzz_forest_model thesis.txt
printf '# every command of Appendix A once\nload tree.obj nocg nomip\nset epsilon 5.5\nset trunk.texres 64\nset foliage.prelight off\nsplit auto\nsplit trunk=bark*,stem\nsplit foliage=leaf?\nbbc1\nbbc2\nbbc3\nbbc\nplanes out.json\nshade 64 0.3\nshade 0\nsave trees\nsetup\nexec other.bbc\nbbcload cloud.wrl\nshow model F1 Tab\nshow bbc\nhelp load\nhelp\ncls\nq\nquit\n' | seed fuzz_batch every.bbc
printf 'load a.wrl\r\n\tset   maxplanes  32 \r\n#set x\n\n  bbc\n' | seed fuzz_batch crlf.bbc
# the demo's maps and models when `make demo` has made them
for f in "$root"/build/demo/forest/*.txt; do
  [ -f "$f" ] || continue
  case "$(head -c 400 "$f")" in
    *hmap*) cp "$f" "$dir/fuzz_forest_map/seeds/" ;;
    *LOD*) cp "$f" "$dir/fuzz_forest_model/seeds/" ;;
  esac
done
printf 'o tri\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\ng leaves\nusemtl leaf\nf 1/1/1 2/2/1 3/3/1\nf 1 2 3 4\nl 1 2\np 3\n' | seed fuzz_obj tri.obj
printf 'mtllib m.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.3 0.3 1e-3\nvt 0 0\nvt 1 0\nvt 0 1\nvn 0 0 1\no a\nusemtl leaf\nf 1/1/1 2/2/1 5/3/1 4/1/1\ng twigs\nf -3//1 -2//1 -1//1\nusemtl bark\nf 1 2 3\ns 1\no a\nf 3 4 5\n' | seed fuzz_objr made.obj
# a small .glb: our own cloud of the built-in tree when the build has made one
for f in "$root"/build/demo/*.glb "$root"/build/demo/forest/*_6.glb; do
  [ -f "$f" ] && [ "$(stat -c %s "$f")" -lt 262144 ] && cp "$f" "$dir/fuzz_glb/seeds/"
done
exit 0
