#!/bin/sh
# install_test.sh BUILD_DIR CC — `make install` into a temporary prefix, then
# build and run a small program against it through pkg-config, as a user would.
set -eu
build=$1
cc=$2
prefix=$(mktemp -d)
trap 'rm -rf "$prefix"' EXIT
cmake --install "$build" --prefix "$prefix" > /dev/null
test -x "$prefix/bin/bbcgen"
test -x "$prefix/bin/forest"
test -f "$prefix/include/bbc.h"
cat > "$prefix/use.c" <<'C'
#include <bbc.h>
#include <stdio.h>
int main(void) {
  bbc_tree_options o;
  bbc_tree_options_default(&o);
  o.leaves = 100;
  bbc_mesh m;
  bbc_error e;
  if (bbc_tree_generate(&o, &m, &e) != BBC_OK) {
    puts(e.message);
    return 1;
  }
  printf("%zu\n", m.triangle_count);
  bbc_mesh_free(&m);
  return 0;
}
C
export PKG_CONFIG_PATH="$prefix/lib/pkgconfig"
# shellcheck disable=SC2046
"$cc" -std=c11 "$prefix/use.c" -o "$prefix/use" $(pkg-config --cflags --libs bbc)
n=$("$prefix/use")
[ "$n" -gt 200 ] || { echo "unexpected triangle count: $n"; exit 1; }
"$prefix/bin/bbcgen" --version
"$prefix/bin/forest" --version
echo "install + pkg-config: ok ($n triangles)"
