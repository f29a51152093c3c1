/* parts_geometry.c — the split by geometry (thesis 2.2.4: the stem apart
 * from the foliage and branches): a tree's trunk is a few large connected
 * pieces, its foliage many small ones (leaves, cards, twig clusters); and,
 * with `limbs`, the trunk's thin pieces moved to the foliage. Connected
 * pieces come from welding vertices at equal positions (a radix sort of
 * position hashes) and a union-find: linear in practice. */
#include "parts.h"

#include <stdlib.h>
#include <string.h>

/* ------------------------------------------------------------------------ */
/* By geometry                                                               */
/* ------------------------------------------------------------------------ */

/* The geometry rule, tuned on real tree models against what their names
 * say, and on the built-in trees.
 *
 * A tree's foliage is many pieces of nearly the same size, one leaf card (2
 * triangles), needle twig (20-28) or leaf cluster (16) instanced over and
 * over, so the median piece size L is the size of a foliage piece. A piece
 * is trunk when it has at least
 *     max(GEOM_MIN_TRUNK_TRIS, GEOM_TRUNK_TIMES_MEDIAN * L, triangles / 1000)
 * triangles, foliage otherwise. The floor keeps twig cones of 3 triangles
 * next to 2-triangle cards in the foliage; 2 L separates branch tubes from
 * leaves (branches of 24 or more triangles beside cards of 2-4, or of 68
 * or more beside leaf blobs of 24); the per-mille term keeps the repeated
 * parts of big foliage clusters out of the trunk (twigs of 48 triangles in
 * a crown of nearly 200,000).
 *
 * The split is made only when it looks like a tree: at least one trunk
 * piece, at least GEOM_MIN_FOLIAGE_PIECES foliage pieces, and at least half
 * of the foliage pieces within a factor 1.5 of their median size. The last
 * test tells foliage from the small parts of a made object, pieces of all
 * sizes (a vehicle's body would otherwise be called its trunk).
 *
 * What it costs: trunk pieces below the threshold join the foliage. On
 * real trees whose names tell the parts, 94-100 % of the triangles land on
 * the side their names give (large leaf pieces, such as old palm fronds,
 * may be called trunk); 58-90 % on the built-in trees, whose smaller
 * branches and twigs are separate tubes of 3-15 triangles: they go to the
 * foliage, where the thesis puts branches anyway (2.2.4). A tree of a few
 * leaf blobs, or one without leaves, is not split. */
#define GEOM_MIN_TRUNK_TRIS     8
#define GEOM_TRUNK_TIMES_MEDIAN 2
#define GEOM_MIN_FOLIAGE_PIECES 20

typedef struct vkey {
  double p[3];
  uint32_t v;
} vkey;

static int vkey_compare(const void *pa, const void *pb) {
  const vkey *a = pa, *b = pb;
  for (int k = 0; k < 3; k++) {
    if (a->p[k] < b->p[k]) return -1;
    if (a->p[k] > b->p[k]) return 1;
  }
  return (a->v > b->v) - (a->v < b->v);
}

/* The splitmix64 finaliser: a 64-bit mix. */
static uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

static uint64_t position_hash(const double *p) {
  uint64_t h = 0x9E3779B97F4A7C15ull;
  for (int k = 0; k < 3; k++) {
    double c = p[k] + 0.0; /* -0 and +0 are the same position */
    uint64_t bits;
    memcpy(&bits, &c, sizeof bits);
    h = mix64(h ^ bits);
  }
  return h;
}

typedef struct hkey {
  uint64_t h;
  uint32_t v;
} hkey;

/* Sorts a run of vertices by position (then index): insertion sort for the
 * usual few copies of a seam vertex, qsort for long runs. */
static void vkey_sort(vkey *run, size_t k) {
  if (k > 16) {
    qsort(run, k, sizeof *run, vkey_compare);
    return;
  }
  for (size_t i = 1; i < k; i++) {
    vkey x = run[i];
    size_t j = i;
    while (j > 0 && vkey_compare(&run[j - 1], &x) > 0) {
      run[j] = run[j - 1];
      j--;
    }
    run[j] = x;
  }
}

/* Welds vertices at exactly equal positions: weld[v] gets the same number
 * for equal positions and different numbers otherwise; *unique the count of
 * distinct positions. The vertices are sorted by a hash of their position
 * (a radix sort: 8 passes of 8 bits, linear), and a run of equal hashes is
 * then sorted by position, which separates the rare different positions
 * with the same hash: linear in practice, O(n log n) at worst (every hash
 * equal), a comparison sort of all vertices being 3 times slower on 200k
 * triangles. The numbering depends on the hash, the components built on it
 * do not (they are numbered by their first triangle). */
static bbc_result weld_positions(const bbc_mesh *m, uint32_t *weld, size_t *unique) {
  size_t nv = m->vertex_count;
  *unique = 0;
  if (nv == 0) return BBC_OK;
  hkey *a = malloc(nv * sizeof *a), *b = malloc(nv * sizeof *b);
  size_t(*count)[256] = calloc(8, sizeof *count);
  if (!a || !b || !count) {
    free(a);
    free(b);
    free(count);
    return BBC_ERROR_OUT_OF_MEMORY;
  }
  for (size_t v = 0; v < nv; v++) {
    a[v].h = position_hash(m->positions + 3 * v);
    a[v].v = (uint32_t)v;
    for (int d = 0; d < 8; d++) count[d][(a[v].h >> (8 * d)) & 255u]++;
  }
  for (int d = 0; d < 8; d++) {
    if (count[d][(a[0].h >> (8 * d)) & 255u] == nv) continue; /* one digit: in order */
    size_t sum = 0;
    for (int i = 0; i < 256; i++) {
      size_t c = count[d][i];
      count[d][i] = sum;
      sum += c;
    }
    for (size_t i = 0; i < nv; i++) b[count[d][(a[i].h >> (8 * d)) & 255u]++] = a[i];
    hkey *t = a;
    a = b;
    b = t;
  }
  free(b);
  free(count);
  vkey *run = NULL;
  size_t run_cap = 0, id = 0;
  for (size_t i = 0; i < nv;) {
    size_t j = i + 1;
    while (j < nv && a[j].h == a[i].h) j++;
    if (j - i == 1) {
      weld[a[i].v] = (uint32_t)id++;
    } else {
      size_t k = j - i;
      if (k > run_cap) {
        vkey *grown = realloc(run, k * sizeof *run);
        if (!grown) {
          free(run);
          free(a);
          return BBC_ERROR_OUT_OF_MEMORY;
        }
        run = grown;
        run_cap = k;
      }
      for (size_t r = 0; r < k; r++) {
        memcpy(run[r].p, m->positions + 3 * (size_t)a[i + r].v, sizeof run[r].p);
        run[r].v = a[i + r].v;
      }
      vkey_sort(run, k);
      for (size_t r = 0; r < k; r++) {
        if (r > 0 && (run[r].p[0] != run[r - 1].p[0] || run[r].p[1] != run[r - 1].p[1] ||
                      run[r].p[2] != run[r - 1].p[2]))
          id++;
        weld[run[r].v] = (uint32_t)id;
      }
      id++;
    }
    i = j;
  }
  free(run);
  free(a);
  *unique = id;
  return BBC_OK;
}

static uint32_t uf_find(uint32_t *parent, uint32_t x) {
  while (parent[x] != x) {
    parent[x] = parent[parent[x]]; /* path halving */
    x = parent[x];
  }
  return x;
}

/* Links the larger root under the smaller: the result does not depend on
 * the order of the unions' arguments. */
static void uf_union(uint32_t *parent, uint32_t a, uint32_t b) {
  a = uf_find(parent, a);
  b = uf_find(parent, b);
  if (a < b)
    parent[b] = a;
  else if (b < a)
    parent[a] = b;
}

/* Connected components of the triangles, two triangles being connected
 * when they share a vertex position (files split vertices at UV and normal
 * seams, so indices alone would cut a trunk into strips), welded where
 * exactly equal (weld_positions). Union-find: almost linear.
 * face_comp[t] receives the component of each triangle, numbered in the
 * order of their first triangle; *comp_count their number; *comp_size (to
 * free) the triangles of each. */
static bbc_result triangle_components(const bbc_mesh *m, uint32_t *face_comp, size_t *comp_count,
                                      size_t **comp_size) {
  size_t nv = m->vertex_count, nt = m->triangle_count;
  *comp_count = 0;
  *comp_size = NULL;
  uint32_t *weld = malloc((nv ? nv : 1) * sizeof *weld);
  size_t nu = 0;
  if (!weld || weld_positions(m, weld, &nu) != BBC_OK) {
    free(weld);
    return BBC_ERROR_OUT_OF_MEMORY;
  }
  uint32_t *parent = malloc((nu ? nu : 1) * sizeof *parent);
  if (!parent) {
    free(weld);
    return BBC_ERROR_OUT_OF_MEMORY;
  }
  for (size_t i = 0; i < nu; i++) parent[i] = (uint32_t)i;
  for (size_t t = 0; t < nt; t++) {
    const uint32_t *ix = m->indices + 3 * t;
    uf_union(parent, weld[ix[0]], weld[ix[1]]);
    uf_union(parent, weld[ix[0]], weld[ix[2]]);
  }
  /* Number the components by their first triangle: comp_of maps a root to
   * its component (UINT32_MAX = not seen yet). */
  uint32_t *comp_of = malloc((nu ? nu : 1) * sizeof *comp_of);
  size_t *size = calloc(nt ? nt : 1, sizeof *size);
  if (!comp_of || !size) {
    free(weld);
    free(parent);
    free(comp_of);
    free(size);
    return BBC_ERROR_OUT_OF_MEMORY;
  }
  for (size_t i = 0; i < nu; i++) comp_of[i] = UINT32_MAX;
  size_t nc = 0;
  for (size_t t = 0; t < nt; t++) {
    uint32_t r = uf_find(parent, weld[m->indices[3 * t]]);
    if (comp_of[r] == UINT32_MAX) comp_of[r] = (uint32_t)nc++;
    face_comp[t] = comp_of[r];
    size[comp_of[r]]++;
  }
  free(weld);
  free(parent);
  free(comp_of);
  *comp_count = nc;
  *comp_size = size;
  return BBC_OK;
}

static int size_compare(const void *pa, const void *pb) {
  size_t a = *(const size_t *)pa, b = *(const size_t *)pb;
  return (a > b) - (a < b);
}

bbc_result bbc__split_by_geometry(const bbc_mesh *m, const split_out *o) {
  size_t nt = m->triangle_count, nc = 0, *size = NULL;
  bbc_result r = triangle_components(m, o->face_part, &nc, &size);
  if (r != BBC_OK) return r;
  size_t *sorted = malloc((nc ? nc : 1) * sizeof *sorted);
  if (!sorted) {
    free(size);
    return BBC_ERROR_OUT_OF_MEMORY;
  }
  memcpy(sorted, size, nc * sizeof *sorted);
  qsort(sorted, nc, sizeof *sorted, size_compare);
  size_t median = sorted[nc / 2];
  size_t threshold = GEOM_MIN_TRUNK_TRIS;
  if (GEOM_TRUNK_TIMES_MEDIAN * median > threshold) threshold = GEOM_TRUNK_TIMES_MEDIAN * median;
  if ((nt + 999) / 1000 > threshold) threshold = (nt + 999) / 1000;
  size_t pieces[2] = {0, 0}, tris[2] = {0, 0};
  for (size_t c = 0; c < nc; c++) {
    int k = size[c] >= threshold ? PART_TRUNK : PART_FOLIAGE;
    pieces[k]++;
    tris[k] += size[c];
  }
  /* The foliage pieces are sorted[0 .. pieces[FOLIAGE]). */
  size_t similar = 0, nf = pieces[PART_FOLIAGE];
  if (nf) {
    size_t fm = sorted[nf / 2];
    for (size_t i = 0; i < nf; i++) similar += 3 * sorted[i] >= 2 * fm && 2 * sorted[i] <= 3 * fm;
  }
  free(sorted);
  char num[5][32], why[512];
  bbc__split_format_count(pieces[PART_TRUNK], num[0], sizeof num[0]);
  bbc__split_format_count(tris[PART_TRUNK], num[1], sizeof num[1]);
  bbc__split_format_count(pieces[PART_FOLIAGE], num[2], sizeof num[2]);
  bbc__split_format_count(tris[PART_FOLIAGE], num[3], sizeof num[3]);
  bbc__split_format_count(threshold, num[4], sizeof num[4]);
  const char *reason = NULL;
  if (nc == 1)
    reason = "it is one connected piece";
  else if (pieces[PART_TRUNK] == 0)
    reason = "no piece is large enough for a trunk";
  else if (nf < GEOM_MIN_FOLIAGE_PIECES)
    reason = "too few small pieces for foliage";
  else if (2 * similar < nf)
    reason = "the small pieces differ too much in size for foliage";
  if (reason) {
    free(size);
    if (nc == 1)
      snprintf(why, sizeof why, "no split: geometry: %s", reason);
    else
      snprintf(why, sizeof why,
               "no split: geometry: %s; %s piece%s of at least %s triangles (%s triangles), %s "
               "smaller (%s triangles)",
               reason, num[0], pieces[PART_TRUNK] == 1 ? "" : "s", num[4], num[1], num[2], num[3]);
    return bbc__split_one_part(o, why);
  }
  for (size_t t = 0; t < nt; t++)
    o->face_part[t] = size[o->face_part[t]] >= threshold ? PART_TRUNK : PART_FOLIAGE;
  free(size);
  snprintf(why, sizeof why,
           "geometry: %s large piece%s (%s triangles, each at least %s) %s the trunk, %s small "
           "pieces (%s triangles) the foliage",
           num[0], pieces[PART_TRUNK] == 1 ? "" : "s", num[1], num[4],
           pieces[PART_TRUNK] == 1 ? "is" : "are", num[2], num[3]);
  return bbc__split_two_parts(o, why);
}

/* ---- the limbs within the trunk (limbs) ---------------------------------- */

typedef struct piece {
  double radius; /* mean tube radius: area / (2 pi length) */
  uint32_t comp;
  size_t tris;
} piece;

static int piece_compare(const void *pa, const void *pb) {
  const piece *a = pa, *b = pb;
  if (a->radius != b->radius) return a->radius > b->radius ? -1 : 1;
  return (a->comp > b->comp) - (a->comp < b->comp);
}

/* A trunk component's sums: triangles, area, its vertices' count, sums and
 * products (x, y, z, xx, yy, zz, xy, xz, yz); then the principal axis and
 * the vertices' extent along it. */
typedef struct comp_sums {
  size_t tris;
  double area, nv, s[9];
  double axis[3], lo, hi;
} comp_sums;

/* The unit principal axis of the vertices: the covariance's dominant
 * eigenvector. */
static void principal_axis(const comp_sums *c, double axis[3]) {
  double m[3] = {c->s[0] / c->nv, c->s[1] / c->nv, c->s[2] / c->nv};
  double C[3][3];
  C[0][0] = c->s[3] / c->nv - m[0] * m[0];
  C[1][1] = c->s[4] / c->nv - m[1] * m[1];
  C[2][2] = c->s[5] / c->nv - m[2] * m[2];
  C[0][1] = C[1][0] = c->s[6] / c->nv - m[0] * m[1];
  C[0][2] = C[2][0] = c->s[7] / c->nv - m[0] * m[2];
  C[1][2] = C[2][1] = c->s[8] / c->nv - m[1] * m[2];
  static const double start[3] = {0.577, 0.578, 0.579};
  bbc__largest_eigenvector(C, start, axis);
}

/* With `limbs` (the trunk part kept as a simplified mesh): of the trunk's
 * connected pieces (branch tubes, welded at equal positions), the thickest
 * that fit `keep` triangles stay in the trunk, the thickest always; the
 * thinner join the foliage, whose billboards keep their coverage in
 * proportion where simplification collapses thin tubes to lines (a
 * sparse tree's bark simplified to a seventh of its triangles may keep
 * little more than half its pixels in side views). A piece's thickness is
 * its mean radius,
 * area / (2 pi length), the length its vertices' extent along their
 * principal axis. Returns the triangles moved, or SIZE_MAX when out of
 * memory; *pieces the trunk's pieces (nothing moves when it is one). */
size_t bbc__split_keep_thick_pieces(const bbc_mesh *m, uint32_t *face_part, size_t keep,
                                    size_t *pieces) {
  size_t nt = m->triangle_count, nc = 0, *size = NULL;
  *pieces = 0;
  uint32_t *comp = malloc((nt ? nt : 1) * sizeof *comp);
  if (!comp || triangle_components(m, comp, &nc, &size) != BBC_OK) {
    free(comp);
    return SIZE_MAX;
  }
  free(size);
  comp_sums *cs = calloc(nc ? nc : 1, sizeof *cs);
  piece *pc = malloc((nc ? nc : 1) * sizeof *pc);
  uint8_t *thin = calloc(nc ? nc : 1, 1);
  if (!cs || !pc || !thin) {
    free(comp);
    free(cs);
    free(pc);
    free(thin);
    return SIZE_MAX;
  }
  for (size_t t = 0; t < nt; t++) {
    if (face_part[t] != PART_TRUNK) continue;
    comp_sums *c = &cs[comp[t]];
    c->tris++;
    c->area += bbc__triangle_area(m, t);
    for (int j = 0; j < 3; j++) {
      const double *x = m->positions + 3 * m->indices[3 * t + j];
      double q[9] = {x[0],        x[1],        x[2],        x[0] * x[0], x[1] * x[1],
                     x[2] * x[2], x[0] * x[1], x[0] * x[2], x[1] * x[2]};
      c->nv += 1;
      for (int k = 0; k < 9; k++) c->s[k] += q[k];
    }
  }
  for (size_t i = 0; i < nc; i++)
    if (cs[i].tris > 0) {
      principal_axis(&cs[i], cs[i].axis);
      cs[i].lo = INFINITY;
      cs[i].hi = -INFINITY;
    }
  for (size_t t = 0; t < nt; t++) {
    if (face_part[t] != PART_TRUNK) continue;
    comp_sums *c = &cs[comp[t]];
    for (int j = 0; j < 3; j++) {
      const double *x = m->positions + 3 * m->indices[3 * t + j];
      double d = x[0] * c->axis[0] + x[1] * c->axis[1] + x[2] * c->axis[2];
      c->lo = fmin(c->lo, d);
      c->hi = fmax(c->hi, d);
    }
  }
  size_t np = 0;
  for (size_t i = 0; i < nc; i++) {
    if (cs[i].tris == 0) continue;
    double length = cs[i].hi - cs[i].lo;
    pc[np].radius = length > 0 ? cs[i].area / (2 * 3.14159265358979323846 * length) : 0;
    pc[np].comp = (uint32_t)i;
    pc[np].tris = cs[i].tris;
    np++;
  }
  *pieces = np;
  size_t moved = 0;
  if (np > 1) {
    qsort(pc, np, sizeof *pc, piece_compare);
    size_t sum = 0;
    for (size_t i = 0; i < np; i++) {
      if (i > 0 && sum + pc[i].tris > keep)
        thin[pc[i].comp] = 1;
      else
        sum += pc[i].tris;
    }
    for (size_t t = 0; t < nt; t++)
      if (face_part[t] == PART_TRUNK && thin[comp[t]]) {
        face_part[t] = PART_FOLIAGE;
        moved++;
      }
  }
  free(comp);
  free(cs);
  free(pc);
  free(thin);
  return moved;
}
