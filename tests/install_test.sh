#!/bin/sh
# install_test.sh BUILD_DIR CC — `make install` into a temporary prefix, then
# build and run programs against it through pkg-config, as a user would: the
# README's library example (taken from README.md itself) on a generated
# tree, and a forest-runtime program on a small map.
set -eu
build=$1
cc=$2
here=$(cd "$(dirname "$0")/.." && pwd)
prefix=$(mktemp -d)
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix" > /dev/null
test -x "$prefix/bin/bbcgen"
test -x "$prefix/bin/forest"
test -f "$prefix/include/bbc.h"
test -f "$prefix/include/bbc_forest.h"
export PKG_CONFIG_PATH="$prefix/lib/pkgconfig"

# The README's example, as printed there.
awk '/^```c$/ { on = 1; next } /^```$/ { on = 0 } on' "$here/README.md" > "$prefix/example.c"
[ -s "$prefix/example.c" ] || { echo "no C example in README.md"; exit 1; }
# shellcheck disable=SC2046
"$cc" -std=c11 -Wall -Wextra -Werror "$prefix/example.c" -o "$prefix/example" \
  $(pkg-config --cflags --libs bbc)
(cd "$prefix" && ./bin/bbcgen tree --species birch --leaves 400 -o tree.obj -q && ./example)
head -c 4 "$prefix/tree.glb" | grep -q glTF || { echo "the example wrote no tree.glb"; exit 1; }

# The forest runtime through its own pkg-config file.
cat > "$prefix/forest.c" <<'C'
#include <bbc_forest.h>
#include <stdio.h>
#include <string.h>
int main(void) {
  const char *text = "hmap h.png\nheightscale 2\nobject2d tree.txt 1 0 5 5 0 0 0 0\n";
  bbc_forest_map map;
  bbc_error e;
  if (bbc_forest_map_parse(text, strlen(text), "m.txt", &map, &e) != BBC_OK) {
    puts(e.message);
    return 1;
  }
  printf("%zu %g\n", map.placement_count, map.heightscale);
  bbc_forest_map_free(&map);
  return 0;
}
C
# shellcheck disable=SC2046
"$cc" -std=c11 "$prefix/forest.c" -o "$prefix/forest_use" $(pkg-config --cflags --libs bbc_forest)
[ "$("$prefix/forest_use")" = "1 2" ] || { echo "the forest program failed"; exit 1; }
"$prefix/bin/bbcgen" --version
"$prefix/bin/forest" --version
echo "install + pkg-config: ok (the README's example wrote tree.glb; the forest runtime parsed a map)"
