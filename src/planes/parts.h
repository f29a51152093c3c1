/*
 * parts.h — what the split's files share (parts.c, parts_geometry.c);
 * internal. parts.c holds the entry point (bbc_split_parts), the names and
 * the user's patterns; parts_geometry.c the split by geometry and the
 * thickness of the trunk's pieces; the stem is stem.c's (planes.h).
 */
#ifndef BBC_PARTS_H
#define BBC_PARTS_H

#include "base.h"

enum { PART_TRUNK = 0, PART_FOLIAGE = 1 };

/* Where a split writes its result: bbc_split_parts' arguments. */
typedef struct split_out {
  uint32_t *face_part;
  size_t triangle_count;
  size_t *part_count;
  char (*names)[32];
  char *why;
  size_t why_size;
  int all_trunk_by_geometry; /* bbc_split_options' (auto mode) */
} split_out;

/* "108,810"; `out` holds at least 27 bytes (20 digits, 6 commas). */
void bbc__split_format_count(size_t v, char *out, size_t size);
/* One part, "all", for every face; `why` the explanation. */
bbc_result bbc__split_one_part(const split_out *o, const char *why);
/* face_part already holds 0 = trunk, 1 = foliage for every face. */
bbc_result bbc__split_two_parts(const split_out *o, const char *why);

/* The split by geometry (parts_geometry.c): a tree's trunk is a few large
 * connected pieces, its foliage many small ones. */
bbc_result bbc__split_by_geometry(const bbc_mesh *m, const split_out *o);
/* With `limbs`: the trunk keeps its thickest pieces that fit `keep`
 * triangles, the others join the foliage (parts_geometry.c). Returns the
 * triangles moved, or SIZE_MAX when out of memory; *pieces the trunk's
 * pieces. */
size_t bbc__split_keep_thick_pieces(const bbc_mesh *m, uint32_t *face_part, size_t keep,
                                    size_t *pieces);

#endif
