/* parts.c — splitting a model into the parts that are simplified on their
 * own: trunk and foliage. Thesis 2.2.4: planes that also take leaves and
 * branches "slice" the stem, and "a simple and highly effective manual
 * solution for tree models is to separate the stem and the foliage plus
 * branches and simplify these two models on their own"; 3.1.1 does so for
 * the Tupelo (a stem of 1,200 polygons, with its own parameters). This file
 * makes that separation automatic.
 *
 * Three sources of evidence, by mode:
 *   - names (BBC_SPLIT_NAMES, and first in BBC_SPLIT_AUTO): keywords in
 *     material and group names ("Bark", "Tree_Leaves", "twigs_Cube.001");
 *   - geometry (BBC_SPLIT_GEOMETRY, and AUTO when the names tell nothing):
 *     a tree's trunk is a few large connected pieces, its foliage many small
 *     ones (leaves, cards, twig clusters);
 *   - the user's glob patterns (BBC_SPLIT_PATTERNS).
 * Names and patterns are evaluated once per material and group, then looked
 * up per face: linear in the triangles. The geometry adds a radix sort of
 * the vertices and a union-find: about 13 ms for the 187k triangles of the
 * Scopia copper beech. No global state; the result depends only on the mesh
 * and the options. */
#include "base.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { PART_TRUNK = 0, PART_FOLIAGE = 1 };

/* What a name says. */
enum { CLASS_UNKNOWN = 0, CLASS_TRUNK = 1, CLASS_FOLIAGE = 2, CLASS_BOTH = 3 };

/* ------------------------------------------------------------------------ */
/* Small text helpers (ASCII only: no locale dependence)                     */
/* ------------------------------------------------------------------------ */

static int lower(int c) {
  return c >= 'A' && c <= 'Z' ? c - 'A' + 'a' : c;
}

static int is_alpha(int c) {
  return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || c >= 0x80;
}

static int is_upper(int c) {
  return c >= 'A' && c <= 'Z';
}

static int is_lower(int c) {
  return c >= 'a' && c <= 'z';
}

/* 1 when s[0..n) equals the lower-case `word` ignoring ASCII case. */
static int equal_nocase(const char *s, const char *word, size_t n) {
  for (size_t i = 0; i < n; i++)
    if (lower((unsigned char)s[i]) != (unsigned char)word[i]) return 0;
  return 1;
}

/* A word starts at i: the name's start, after a non-letter ("Tree_Leaves",
 * "leaves.001") or at a lower-to-upper case change ("OldLeaves"). */
static int word_starts(const char *s, size_t i) {
  if (i == 0) return 1;
  int a = (unsigned char)s[i - 1], b = (unsigned char)s[i];
  return !is_alpha(a) || (is_lower(a) && is_upper(b));
}

static int word_ends(const char *s, size_t j) {
  int a = (unsigned char)s[j - 1], b = (unsigned char)s[j];
  return b == 0 || !is_alpha(b) || (is_lower(a) && is_upper(b));
}

/* ------------------------------------------------------------------------ */
/* Keywords                                                                  */
/* ------------------------------------------------------------------------ */

/* `whole`: the keyword must be a whole word, optionally with a plural "s" or
 * "es" ("Stems", "Logs"), because as a bare substring it would also match
 * unrelated names: "stem" in "System", "log" in "Logo" or "Catalog", "wood"
 * in "Hollywood", "crown" in "Crowne". The others are matched anywhere in a
 * name, so that run-together names ("treeleaves", "pinebark") are found too;
 * they cover their plurals ("twigs", "needles", "branches") by themselves.
 * "tree" is no keyword: files use it for the trunk ("tree" in the Scopia
 * pine) as well as for everything ("twig.534_tree" in the copper beech). */
typedef struct keyword {
  const char *word; /* lower case */
  int whole;
} keyword;

/* German too ("Blatt", "Laub", "Blaetter" / UTF-8 "Bl\u00e4tter"; "Stamm",
 * "Rinde"). */
static const keyword k_foliage_words[] = {
    {"leaf", 0},  {"leaves", 0}, {"twig", 0}, {"foliage", 0},  {"needle", 0},         {"frond", 0},
    {"crown", 1}, {"blatt", 0},  {"laub", 0}, {"blaetter", 0}, {"bl\xc3\xa4tter", 0},
};

static const keyword k_trunk_words[] = {
    {"trunk", 0}, {"bark", 0},  {"branch", 0}, {"stem", 1},  {"wood", 1},
    {"log", 1},   {"stump", 1}, {"stamm", 1},  {"rinde", 1},
};

static int keyword_in(const char *name, const keyword *kw) {
  size_t n = strlen(kw->word), len = strlen(name);
  for (size_t i = 0; i + n <= len; i++) {
    if (!equal_nocase(name + i, kw->word, n)) continue;
    if (!kw->whole) return 1;
    if (!word_starts(name, i)) continue;
    size_t j = i + n;
    if (word_ends(name, j)) return 1;
    if (lower((unsigned char)name[j]) == 's' && word_ends(name, j + 1)) return 1;
    if (lower((unsigned char)name[j]) == 'e' && lower((unsigned char)name[j + 1]) == 's' &&
        word_ends(name, j + 2))
      return 1;
  }
  return 0;
}

static int classify_name(const char *name) {
  int c = CLASS_UNKNOWN;
  if (!name) return c;
  for (size_t i = 0; i < sizeof k_trunk_words / sizeof k_trunk_words[0]; i++)
    if (keyword_in(name, &k_trunk_words[i])) {
      c |= CLASS_TRUNK;
      break;
    }
  for (size_t i = 0; i < sizeof k_foliage_words / sizeof k_foliage_words[0]; i++)
    if (keyword_in(name, &k_foliage_words[i])) {
      c |= CLASS_FOLIAGE;
      break;
    }
  return c;
}

/* ------------------------------------------------------------------------ */
/* Glob patterns: '*' any run, '?' one character, case-insensitive, whole   */
/* name. Iterative with one backtrack point: linear-ish, no recursion.      */
/* ------------------------------------------------------------------------ */

static int glob_match(const char *p, size_t plen, const char *s) {
  size_t pi = 0, si = 0, star_p = (size_t)-1, star_s = 0;
  size_t slen = strlen(s);
  while (si < slen) {
    if (pi < plen && p[pi] == '*') {
      star_p = pi++;
      star_s = si;
    } else if (pi < plen &&
               (p[pi] == '?' || lower((unsigned char)p[pi]) == lower((unsigned char)s[si]))) {
      pi++;
      si++;
    } else if (star_p != (size_t)-1) {
      pi = star_p + 1;
      si = ++star_s;
    } else {
      return 0;
    }
  }
  while (pi < plen && p[pi] == '*') pi++;
  return pi == plen;
}

/* One comma-separated list of patterns: items as (offset, length) into the
 * caller's string, blanks around items trimmed. */
typedef struct pattern_list {
  const char *text;
  size_t count;
  size_t *start;
  size_t *len;
} pattern_list;

static int is_blank(int c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r';
}

/* Parses `text` (NULL or blank = no patterns). An empty item ("a,,b", a
 * trailing comma) is refused: it is a typo, and as a pattern it would match
 * only the empty name. */
static bbc_result pattern_list_parse(pattern_list *pl, const char *text, const char *what,
                                     bbc_error *err) {
  memset(pl, 0, sizeof *pl);
  pl->text = text;
  if (!text) return BBC_OK;
  size_t n = strlen(text), blank = 1;
  for (size_t i = 0; i < n; i++)
    if (!is_blank((unsigned char)text[i])) blank = 0;
  if (blank) return BBC_OK;
  size_t items = 1;
  for (size_t i = 0; i < n; i++) items += text[i] == ',';
  pl->start = malloc(items * sizeof *pl->start);
  pl->len = malloc(items * sizeof *pl->len);
  if (!pl->start || !pl->len) {
    free(pl->start);
    free(pl->len);
    memset(pl, 0, sizeof *pl);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "out of memory parsing %s", what);
  }
  size_t i = 0;
  while (pl->count < items) {
    size_t a = i;
    while (a < n && text[a] != ',' && is_blank((unsigned char)text[a])) a++;
    size_t e = a;
    while (e < n && text[e] != ',') e++;
    size_t b = e;
    while (b > a && is_blank((unsigned char)text[b - 1])) b--;
    if (b == a) {
      free(pl->start);
      free(pl->len);
      memset(pl, 0, sizeof *pl);
      return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                       "split %s \"%s\": empty pattern (two commas in a row or a comma at an "
                       "end)",
                       what, text);
    }
    pl->start[pl->count] = a;
    pl->len[pl->count] = b - a;
    pl->count++;
    i = e + 1;
  }
  return BBC_OK;
}

static void pattern_list_free(pattern_list *pl) {
  free(pl->start);
  free(pl->len);
  memset(pl, 0, sizeof *pl);
}

static int pattern_list_match(const pattern_list *pl, const char *name) {
  if (!name) return 0;
  for (size_t i = 0; i < pl->count; i++)
    if (glob_match(pl->text + pl->start[i], pl->len[i], name)) return 1;
  return 0;
}

/* ------------------------------------------------------------------------ */
/* Explanations                                                              */
/* ------------------------------------------------------------------------ */

/* "108,810"; `out` holds at least 27 bytes (20 digits, 6 commas). */
static void format_count(size_t v, char *out, size_t size) {
  char digits[24];
  int n = snprintf(digits, sizeof digits, "%zu", v);
  size_t o = 0;
  for (int i = 0; i < n && o + 2 < size; i++) {
    if (i > 0 && (n - i) % 3 == 0) out[o++] = ',';
    out[o++] = digits[i];
  }
  out[o] = 0;
}

/* Appends to a bounded string; truncates silently. */
static void append(char *buf, size_t size, const char *fmt, ...) BBC__PRINTF(3, 4);
static void append(char *buf, size_t size, const char *fmt, ...) {
  if (!buf || size == 0) return;
  size_t n = strlen(buf);
  if (n + 1 >= size) return;
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf + n, size - n, fmt, ap);
  va_end(ap);
}

/* ------------------------------------------------------------------------ */
/* Results                                                                   */
/* ------------------------------------------------------------------------ */

typedef struct split_out {
  uint32_t *face_part;
  size_t triangle_count;
  size_t *part_count;
  char (*names)[32];
  char *why;
  size_t why_size;
  int all_trunk_by_geometry; /* bbc_split_options' (auto mode) */
} split_out;

static void set_why(const split_out *o, const char *text) {
  if (o->why && o->why_size) snprintf(o->why, o->why_size, "%s", text);
}

static bbc_result one_part(const split_out *o, const char *why) {
  if (o->triangle_count) memset(o->face_part, 0, o->triangle_count * sizeof *o->face_part);
  *o->part_count = 1;
  memset(o->names, 0, 2 * sizeof o->names[0]);
  snprintf(o->names[0], sizeof o->names[0], "all");
  set_why(o, why);
  return BBC_OK;
}

/* face_part already holds 0 = trunk, 1 = foliage for every face. */
static bbc_result two_parts(const split_out *o, const char *why) {
  *o->part_count = 2;
  memset(o->names, 0, 2 * sizeof o->names[0]);
  snprintf(o->names[PART_TRUNK], sizeof o->names[0], "trunk");
  snprintf(o->names[PART_FOLIAGE], sizeof o->names[0], "foliage");
  set_why(o, why);
  return BBC_OK;
}

/* ------------------------------------------------------------------------ */
/* By names                                                                  */
/* ------------------------------------------------------------------------ */

/* Names that decided faces, for the explanation: "material Trunk",
 * "materials Branch, Trunk", "material Bark, group trunk". */
static void describe_names(const bbc_mesh *m, const size_t *mat_count, const size_t *grp_count,
                           char *buf, size_t size) {
  buf[0] = 0;
  size_t nm = 0, ng = 0;
  for (size_t i = 0; i < m->material_count; i++) nm += mat_count[i] > 0;
  for (size_t i = 0; i < m->group_count; i++) ng += grp_count[i] > 0;
  const size_t shown_max = 3;
  if (nm) {
    append(buf, size, "material%s ", nm > 1 ? "s" : "");
    size_t shown = 0;
    for (size_t i = 0; i < m->material_count && shown < shown_max; i++)
      if (mat_count[i]) append(buf, size, "%s%s", shown++ ? ", " : "", m->materials[i].name);
    if (nm > shown_max) append(buf, size, ", ...");
  }
  if (ng) {
    append(buf, size, "%sgroup%s ", nm ? ", " : "", ng > 1 ? "s" : "");
    size_t shown = 0;
    for (size_t i = 0; i < m->group_count && shown < shown_max; i++)
      if (grp_count[i]) append(buf, size, "%s%s", shown++ ? ", " : "", m->group_names[i]);
    if (ng > shown_max) append(buf, size, ", ...");
  }
}

/* Returns BBC_OK with *decided = 1 when the names settle the question (a
 * split, or "all" because every face was recognised as one kind), *decided
 * = 0 when they recognise no face at all.
 *
 * Each material and group name says trunk, foliage or nothing; a name with
 * keywords of both kinds ("BarkLeavesAtlas", a texture atlas shared by the
 * whole tree) says nothing. Group names are ignored when the model has a
 * single group: it names the model, not a part ("Tree_1_Cylinder.037",
 * "OakWithLeaves"). A face is trunk or foliage when its material and group
 * say so or one says so and the other nothing (quaternius: one group,
 * materials "Bark" / "Tree_Leaves"; Scopia pine: materials "Trunk" /
 * "Leaves", groups "tree" / "twigs_Cube.001"). When they contradict each
 * other the face is foliage: the thesis puts the branches with the foliage
 * and keeps the stem apart (2.2.4), and bark-textured twigs inside a
 * foliage object belong to the foliage (Scopia copper beech: material
 * "Branch" in group "twig.534_tree", 9,940 clusters of twigs and leaves).
 *
 * Faces about which the names say nothing join the other kind when only one
 * kind was recognised (a model that names only its "Leaves": the rest is the
 * trunk), and the foliage when both were: next to a named trunk, what the
 * names leave unexplained is in practice small detail (fruit, flowers) that
 * is simplified like foliage, and the trunk's treatment should go only to
 * what is known to be trunk. */
static bbc_result split_by_names(const bbc_mesh *m, const split_out *o, int *decided) {
  *decided = 0;
  size_t nmat = m->material_count, ngrp = m->group_count, nt = m->triangle_count;
  unsigned char *mat_class = calloc(nmat ? nmat : 1, 1);
  unsigned char *grp_class = calloc(ngrp ? ngrp : 1, 1);
  /* faces each name helped to decide, per part: [part * count + index] */
  size_t *mat_n = calloc(2 * (nmat ? nmat : 1), sizeof *mat_n);
  size_t *grp_n = calloc(2 * (ngrp ? ngrp : 1), sizeof *grp_n);
  if (!mat_class || !grp_class || !mat_n || !grp_n) {
    free(mat_class);
    free(grp_class);
    free(mat_n);
    free(grp_n);
    return BBC_ERROR_OUT_OF_MEMORY;
  }
  for (size_t i = 0; i < nmat; i++) {
    int c = classify_name(m->materials[i].name);
    mat_class[i] = (unsigned char)(c == CLASS_BOTH ? CLASS_UNKNOWN : c);
  }
  for (size_t i = 0; i < ngrp && ngrp > 1; i++) {
    int c = classify_name(m->group_names[i]);
    grp_class[i] = (unsigned char)(c == CLASS_BOTH ? CLASS_UNKNOWN : c);
  }

  size_t count[2] = {0, 0}, unknown = 0, conflict = 0;
  for (size_t t = 0; t < nt; t++) {
    uint32_t mi = m->face_material ? m->face_material[t] : 0;
    uint32_t gi = m->face_group ? m->face_group[t] : 0;
    int mc = mi < nmat ? mat_class[mi] : CLASS_UNKNOWN;
    int gc = gi < ngrp ? grp_class[gi] : CLASS_UNKNOWN;
    int c = mc | gc;
    uint32_t part = 2; /* unknown */
    if (c == CLASS_TRUNK) {
      part = PART_TRUNK;
    } else if (c != CLASS_UNKNOWN) {
      part = PART_FOLIAGE;
      conflict += c == CLASS_BOTH;
    }
    if (part < 2) {
      int want = part == PART_TRUNK ? CLASS_TRUNK : CLASS_FOLIAGE;
      if (mc == want) mat_n[part * nmat + mi]++;
      if (gc == want) grp_n[part * ngrp + gi]++;
      count[part]++;
    } else {
      unknown++;
    }
    o->face_part[t] = part;
  }

  char names[2][256], num[4][32], why[1024];
  describe_names(m, mat_n, grp_n, names[PART_TRUNK], sizeof names[0]);
  describe_names(m, mat_n + nmat, grp_n + ngrp, names[PART_FOLIAGE], sizeof names[0]);
  free(mat_class);
  free(grp_class);
  free(mat_n);
  free(grp_n);

  if (count[PART_TRUNK] + count[PART_FOLIAGE] == 0) return BBC_OK; /* names tell nothing */
  *decided = 1;
  if (unknown == 0 && count[PART_FOLIAGE] == 0 && o->all_trunk_by_geometry) {
    *decided = 0; /* every face trunk: geometry finds the limbs and the twigs */
    return BBC_OK;
  }
  if (unknown == 0 && (count[PART_TRUNK] == 0 || count[PART_FOLIAGE] == 0)) {
    int k = count[PART_TRUNK] ? PART_TRUNK : PART_FOLIAGE;
    snprintf(why, sizeof why, "no split: the names make every face %s (%s)",
             k == PART_TRUNK ? "trunk" : "foliage", names[k]);
    return one_part(o, why);
  }
  uint32_t rest = count[PART_TRUNK] == 0 ? PART_TRUNK : PART_FOLIAGE;
  for (size_t t = 0; t < nt; t++)
    if (o->face_part[t] == 2) o->face_part[t] = rest;
  size_t total[2] = {count[0], count[1]};
  total[rest] += unknown;
  format_count(total[PART_TRUNK], num[0], sizeof num[0]);
  format_count(total[PART_FOLIAGE], num[1], sizeof num[1]);
  format_count(unknown, num[2], sizeof num[2]);
  format_count(conflict, num[3], sizeof num[3]);
  snprintf(why, sizeof why, "names: trunk %s triangles", num[0]);
  if (count[PART_TRUNK]) append(why, sizeof why, " (%s)", names[PART_TRUNK]);
  append(why, sizeof why, ", foliage %s", num[1]);
  if (count[PART_FOLIAGE]) append(why, sizeof why, " (%s)", names[PART_FOLIAGE]);
  if (conflict)
    append(why, sizeof why, "; %s triangles named trunk and foliage count as foliage", num[3]);
  if (unknown)
    append(why, sizeof why, "; %s triangles with other names joined the %s", num[2],
           rest == PART_TRUNK ? "trunk" : "foliage");
  return two_parts(o, why);
}

/* ------------------------------------------------------------------------ */
/* By geometry                                                               */
/* ------------------------------------------------------------------------ */

/* The geometry rule, tuned on the real trees of ../shared/data (Scopia,
 * ez-tree, quaternius) against what their names say, and on the built-in
 * trees.
 *
 * A tree's foliage is many pieces of nearly the same size, one leaf card (2
 * triangles), needle twig (20-28) or leaf cluster (16) instanced over and
 * over, so the median piece size L is the size of a foliage piece. A piece
 * is trunk when it has at least
 *     max(GEOM_MIN_TRUNK_TRIS, GEOM_TRUNK_TIMES_MEDIAN * L, triangles / 1000)
 * triangles, foliage otherwise. The floor keeps twig cones of 3 triangles
 * next to 2-triangle cards in the foliage; 2 L separates branch tubes from
 * leaves (ez-tree: branches of 24+ triangles, cards of 2-4; quaternius:
 * branches of 68+, leaf blobs of 24); the per-mille term keeps the repeated
 * parts of big foliage clusters out of the trunk (copper beech: twigs of 48
 * triangles among 187k).
 *
 * The split is made only when it looks like a tree: at least one trunk
 * piece, at least GEOM_MIN_FOLIAGE_PIECES foliage pieces, and at least half
 * of the foliage pieces within a factor 1.5 of their median size. The last
 * test tells foliage from the small parts of a made object: the H-60
 * helicopter has 83 pieces of 2 to 744 triangles, of all sizes (without it,
 * AUTO would call its fuselage the trunk).
 *
 * What it costs: trunk pieces below the threshold join the foliage.
 * Triangles on the side their names give: 100% for the Scopia pine and
 * copper beech, ez-tree pine_medium, bush_1 and aspen_small, quaternius
 * Birch_1, Pine_1 and Tree_3; 97% palm (15 old fronds of 85 triangles are
 * called trunk), 96% Scopia bush, 95% ez-tree oak_medium, 94% ash_large_hi;
 * 58-90% for the built-in trees, whose smaller branches and twigs are
 * separate tubes of 3-15 triangles: they go to the foliage, where the
 * thesis puts branches anyway (2.2.4). Quaternius Tree_1 (19 leaf
 * blobs) and DeadTree_1 (no leaves) are not split. */
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

static bbc_result split_by_geometry(const bbc_mesh *m, const split_out *o) {
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
  format_count(pieces[PART_TRUNK], num[0], sizeof num[0]);
  format_count(tris[PART_TRUNK], num[1], sizeof num[1]);
  format_count(pieces[PART_FOLIAGE], num[2], sizeof num[2]);
  format_count(tris[PART_FOLIAGE], num[3], sizeof num[3]);
  format_count(threshold, num[4], sizeof num[4]);
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
    return one_part(o, why);
  }
  for (size_t t = 0; t < nt; t++)
    o->face_part[t] = size[o->face_part[t]] >= threshold ? PART_TRUNK : PART_FOLIAGE;
  free(size);
  snprintf(why, sizeof why,
           "geometry: %s large piece%s (%s triangles, each at least %s) %s the trunk, %s small "
           "pieces (%s triangles) the foliage",
           num[0], pieces[PART_TRUNK] == 1 ? "" : "s", num[1], num[4],
           pieces[PART_TRUNK] == 1 ? "is" : "are", num[2], num[3]);
  return two_parts(o, why);
}

/* ------------------------------------------------------------------------ */
/* By the user's patterns                                                    */
/* ------------------------------------------------------------------------ */

static bbc_result split_by_patterns(const bbc_mesh *m, const pattern_list *trunk,
                                    const pattern_list *foliage, uint32_t rest,
                                    const split_out *o) {
  size_t nmat = m->material_count, ngrp = m->group_count, nt = m->triangle_count;
  /* per name: bit 0 matches trunk, bit 1 matches foliage */
  unsigned char *mat = calloc(nmat ? nmat : 1, 1);
  unsigned char *grp = calloc(ngrp ? ngrp : 1, 1);
  if (!mat || !grp) {
    free(mat);
    free(grp);
    return BBC_ERROR_OUT_OF_MEMORY;
  }
  for (size_t i = 0; i < nmat; i++)
    mat[i] = (unsigned char)(pattern_list_match(trunk, m->materials[i].name) |
                             pattern_list_match(foliage, m->materials[i].name) << 1);
  for (size_t i = 0; i < ngrp; i++)
    grp[i] = (unsigned char)(pattern_list_match(trunk, m->group_names[i]) |
                             pattern_list_match(foliage, m->group_names[i]) << 1);
  size_t count[3] = {0, 0, 0}; /* by trunk pattern, by foliage pattern, rest */
  for (size_t t = 0; t < nt; t++) {
    uint32_t mi = m->face_material ? m->face_material[t] : 0;
    uint32_t gi = m->face_group ? m->face_group[t] : 0;
    unsigned f = (mi < nmat ? mat[mi] : 0u) | (gi < ngrp ? grp[gi] : 0u);
    uint32_t part;
    if (f & 1u) {
      part = PART_TRUNK;
      count[0]++;
    } else if (f & 2u) {
      part = PART_FOLIAGE;
      count[1]++;
    } else {
      part = rest;
      count[2]++;
    }
    o->face_part[t] = part;
  }
  free(mat);
  free(grp);
  size_t total[2] = {count[0], count[1]};
  total[rest] += count[2];
  char num[5][32], why[512];
  format_count(total[PART_TRUNK], num[0], sizeof num[0]);
  format_count(total[PART_FOLIAGE], num[1], sizeof num[1]);
  format_count(count[0], num[2], sizeof num[2]);
  format_count(count[1], num[3], sizeof num[3]);
  format_count(count[2], num[4], sizeof num[4]);
  const char *rest_name = rest == PART_TRUNK ? "trunk" : "foliage";
  if (total[PART_TRUNK] == 0 || total[PART_FOLIAGE] == 0) {
    snprintf(why, sizeof why,
             "no split: the patterns put every face in the %s (%s by trunk patterns, %s by "
             "foliage patterns, %s the rest)",
             total[PART_TRUNK] ? "trunk" : "foliage", num[2], num[3], num[4]);
    return one_part(o, why);
  }
  snprintf(why, sizeof why,
           "patterns: trunk %s triangles, foliage %s (%s by trunk patterns, %s by foliage "
           "patterns, %s the rest, given to the %s)",
           num[0], num[1], num[2], num[3], num[4], rest_name);
  return two_parts(o, why);
}

/* ------------------------------------------------------------------------ */
/* Entry point                                                               */
/* ------------------------------------------------------------------------ */

static const char *mode_name(bbc_split_mode mode) {
  switch (mode) {
  case BBC_SPLIT_AUTO:
    return "auto";
  case BBC_SPLIT_NONE:
    return "none";
  case BBC_SPLIT_NAMES:
    return "names";
  case BBC_SPLIT_GEOMETRY:
    return "geometry";
  case BBC_SPLIT_PATTERNS:
    return "patterns";
  }
  return "?";
}

/* `options` may be NULL: BBC_SPLIT_AUTO. */

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
 * proportion where simplification collapses thin tubes to lines (the
 * generated larch, seed 2: its 1,857 bark triangles simplified to 256 kept
 * 0.60 of their pixels in side views). A piece's thickness is its mean radius,
 * area / (2 pi length), the length its vertices' extent along their
 * principal axis. Returns the triangles moved, or SIZE_MAX when out of
 * memory; *pieces the trunk's pieces (nothing moves when it is one). */
static size_t keep_thick_pieces(const bbc_mesh *m, uint32_t *face_part, size_t keep,
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
    double cr[3];
    bbc__triangle_cross(m, t, cr);
    c->tris++;
    c->area += 0.5 * sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
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

/* ---- the stem within the trunk (stem_only) -------------------------------- */

/* Keeps in the trunk part only the faces near the stem's axis; the others
 * (branches) join the foliage. The axis is followed in 32 slices up the up
 * axis: each slice's centre is the mean of the trunk face centroids in it
 * that lie within 1.5 base radii of the slice below's centre, so a leaning
 * trunk keeps its stem. Returns the number of faces moved, or SIZE_MAX when
 * out of memory. */
static size_t keep_stem_only(const bbc_mesh *m, uint32_t *face_part, int up) {
  enum { SLICES = 32 };
  size_t nf = m->triangle_count;
  int a = (up + 1) % 3, b = (up + 2) % 3;
  size_t nt = 0;
  for (size_t t = 0; t < nf; t++) nt += face_part[t] == PART_TRUNK;
  if (nt == 0) return 0;
  double *q = malloc(nt * 3 * sizeof *q); /* trunk face centroids */
  uint32_t *which = malloc(nt * sizeof *which);
  if (!q || !which) {
    free(q);
    free(which);
    return SIZE_MAX;
  }
  double hmin = INFINITY, hmax = -INFINITY;
  size_t k = 0;
  for (size_t t = 0; t < nf; t++) {
    if (face_part[t] != PART_TRUNK) continue;
    for (int i = 0; i < 3; i++) {
      q[3 * k + i] = 0;
      for (int j = 0; j < 3; j++) q[3 * k + i] += m->positions[3 * m->indices[3 * t + j] + i] / 3;
    }
    hmin = fmin(hmin, q[3 * k + up]);
    hmax = fmax(hmax, q[3 * k + up]);
    which[k++] = (uint32_t)t;
  }
  size_t moved = 0;
  if (hmax > hmin) {
    double dh = (hmax - hmin) / SLICES;
    int *slice = malloc(nt * sizeof *slice);
    if (!slice) {
      free(q);
      free(which);
      return SIZE_MAX;
    }
    for (size_t i = 0; i < nt; i++) {
      int s = (int)((q[3 * i + up] - hmin) / dh);
      slice[i] = s < 0 ? 0 : (s >= SLICES ? SLICES - 1 : s);
    }
    /* Base: centre and radius of the lowest slice. */
    double ca = 0, cb = 0, n = 0, r0 = 0;
    for (size_t i = 0; i < nt; i++)
      if (slice[i] == 0) {
        ca += q[3 * i + a];
        cb += q[3 * i + b];
        n++;
      }
    ca /= n;
    cb /= n;
    for (size_t i = 0; i < nt; i++)
      if (slice[i] == 0) r0 = fmax(r0, hypot(q[3 * i + a] - ca, q[3 * i + b] - cb));
    double reach = 1.5 * r0;
    double cx[SLICES], cy[SLICES];
    int found[SLICES];
    for (int s = 0; s < SLICES; s++) {
      double sa = 0, sb = 0, cnt = 0;
      for (size_t i = 0; i < nt; i++)
        if (slice[i] == s && hypot(q[3 * i + a] - ca, q[3 * i + b] - cb) <= reach) {
          sa += q[3 * i + a];
          sb += q[3 * i + b];
          cnt++;
        }
      found[s] = cnt > 0;
      if (cnt > 0) {
        ca = sa / cnt;
        cb = sb / cnt;
      }
      cx[s] = ca;
      cy[s] = cb;
    }
    for (size_t i = 0; i < nt; i++) {
      int s = slice[i];
      if (found[s] && hypot(q[3 * i + a] - cx[s], q[3 * i + b] - cy[s]) <= reach) continue;
      face_part[which[i]] = PART_FOLIAGE;
      moved++;
    }
    free(slice);
  }
  free(q);
  free(which);
  return moved;
}

bbc_result bbc_split_parts(const bbc_mesh *mesh, const bbc_split_options *options,
                           uint32_t *face_part, size_t *part_count, char names[2][32], char *why,
                           size_t why_size, bbc_error *err) {
  assert(mesh && part_count && names);
  assert(face_part || mesh->triangle_count == 0 || mesh->kind == BBC_MESH_POINTS);
  bbc_split_options defaults;
  memset(&defaults, 0, sizeof defaults);
  defaults.mode = BBC_SPLIT_AUTO;
  if (!options) options = &defaults;
  split_out o;
  o.face_part = face_part;
  o.triangle_count = mesh->kind == BBC_MESH_POINTS ? 0 : mesh->triangle_count;
  o.part_count = part_count;
  o.names = names;
  o.why = why;
  o.why_size = why_size;
  o.all_trunk_by_geometry = options->mode == BBC_SPLIT_AUTO && options->all_trunk_by_geometry;
  if (why && why_size) why[0] = 0;

  /* Options first: a wrong option is an error whatever the mesh. */
  int mode = (int)options->mode;
  if (mode < (int)BBC_SPLIT_AUTO || mode > (int)BBC_SPLIT_PATTERNS)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "split mode %d is not one of auto, none, names, geometry, patterns", mode);
  uint32_t rest = PART_FOLIAGE;
  if (options->rest) {
    if (strlen(options->rest) == 5 && equal_nocase(options->rest, "trunk", 5))
      rest = PART_TRUNK;
    else if (strlen(options->rest) == 7 && equal_nocase(options->rest, "foliage", 7))
      rest = PART_FOLIAGE;
    else
      return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                       "split rest \"%s\" is neither \"trunk\" nor \"foliage\"", options->rest);
  }
  pattern_list trunk_pl, foliage_pl;
  memset(&trunk_pl, 0, sizeof trunk_pl);
  memset(&foliage_pl, 0, sizeof foliage_pl);
  if (options->mode == BBC_SPLIT_PATTERNS) {
    bbc_result r = pattern_list_parse(&trunk_pl, options->trunk_patterns, "trunk patterns", err);
    if (r != BBC_OK) return r;
    r = pattern_list_parse(&foliage_pl, options->foliage_patterns, "foliage patterns", err);
    if (r != BBC_OK) {
      pattern_list_free(&trunk_pl);
      return r;
    }
    if (trunk_pl.count + foliage_pl.count == 0)
      return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                       "split mode patterns needs trunk or foliage patterns (comma-separated "
                       "globs such as \"*bark*,trunk\"); both are empty");
  }

  bbc_result r = BBC_OK;
  if (mesh->kind == BBC_MESH_POINTS || o.triangle_count == 0) {
    r = one_part(&o, mesh->kind == BBC_MESH_POINTS ? "no split: a point cloud is one part"
                                                   : "no split: no triangles");
  } else if (options->mode == BBC_SPLIT_NONE) {
    r = one_part(&o, "no split: split mode none");
  } else if (options->mode == BBC_SPLIT_PATTERNS) {
    r = split_by_patterns(mesh, &trunk_pl, &foliage_pl, rest, &o);
  } else if (options->mode == BBC_SPLIT_GEOMETRY) {
    r = split_by_geometry(mesh, &o);
  } else {
    int decided = 0;
    r = split_by_names(mesh, &o, &decided);
    if (r == BBC_OK && !decided) {
      if (options->mode == BBC_SPLIT_NAMES)
        r = one_part(&o, "no split: no material or group name says trunk or foliage");
      else
        r = split_by_geometry(mesh, &o);
    }
  }
  pattern_list_free(&trunk_pl);
  pattern_list_free(&foliage_pl);
  size_t trunk_pieces = 0;
  if (r == BBC_OK && options->limbs > 0 && *part_count == 2 && mesh->kind != BBC_MESH_POINTS) {
    size_t moved = keep_thick_pieces(mesh, face_part, 2 * (size_t)options->limbs, &trunk_pieces);
    if (moved == SIZE_MAX)
      r = BBC_ERROR_OUT_OF_MEMORY;
    else if (moved && why && why_size) {
      size_t l = strlen(why);
      snprintf(why + l, why_size - l, "; limbs: %zu triangles of thin branches join the foliage",
               moved);
    }
  }
  if (r == BBC_OK && options->stem_only && *part_count == 2 && trunk_pieces <= 1) {
    int up = options->up_axis >= 0 && options->up_axis <= 2 ? options->up_axis : 1;
    size_t moved = keep_stem_only(mesh, face_part, up);
    if (moved == SIZE_MAX)
      r = BBC_ERROR_OUT_OF_MEMORY;
    else if (moved && why && why_size) {
      size_t l = strlen(why);
      snprintf(why + l, why_size - l, "; stem only: %zu branch triangles join the foliage", moved);
    }
  }
  if (r == BBC_ERROR_OUT_OF_MEMORY)
    return bbc__fail(err, r, "out of memory splitting %zu triangles into parts (split mode %s)",
                     mesh->triangle_count, mode_name(options->mode));
  return r;
}
