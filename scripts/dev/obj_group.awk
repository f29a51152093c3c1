# obj_group.awk — one OBJ (faces as v/vt/vn, as `bbcgen tree` writes) made
# into a group of 8 copies standing a few metres apart, each turned about
# the up axis (y) by the golden angle and scaled: the thesis's tree groups
# (3.3, Finland), simplified by bbcgen as one model.
#   awk -f obj_group.awk tree.obj > group.obj
BEGIN {
  n = split("0 0 1.00|6.5 1.0 0.90|-3.0 5.8 1.10|-4.2 -5.1 0.95|3.4 -6.3 1.05|" \
            "11.8 -2.2 0.85|-10.1 1.3 1.00|5.9 8.9 0.92", place, "|")
}
{ line[++lines] = $0 }
END {
  for (i = 1; i <= lines; i++) {
    split(line[i], f, " ")
    if (f[1] == "v") nv++
    else if (f[1] == "vt") nvt++
    else if (f[1] == "vn") nvn++
  }
  print "# " n " copies of one tree as a group (scripts/dev/obj_group.awk)"
  for (i = 1; i <= lines; i++)
    if (line[i] ~ /^mtllib /) { print line[i]; break }
  for (c = 1; c <= n; c++) {
    split(place[c], p, " ")
    a = (c - 1) * 2.39996323; cs = cos(a); sn = sin(a); s = p[3]; o = c - 1
    print "g tree" c
    for (i = 1; i <= lines; i++) {
      k = split(line[i], f, " ")
      if (f[1] == "v")
        printf "v %.5f %.5f %.5f\n", s * (cs * f[2] + sn * f[4]) + p[1], s * f[3],
               s * (-sn * f[2] + cs * f[4]) + p[2]
      else if (f[1] == "vn")
        printf "vn %.5f %.5f %.5f\n", cs * f[2] + sn * f[4], f[3], -sn * f[2] + cs * f[4]
      else if (f[1] == "vt" || f[1] == "usemtl")
        print line[i]
      else if (f[1] == "f") {
        out = "f"
        for (j = 2; j <= k; j++) {
          split(f[j], ix, "/")
          out = out " " (ix[1] + o * nv) "/" (ix[2] + o * nvt) "/" (ix[3] + o * nvn)
        }
        print out
      }
    }
  }
}
