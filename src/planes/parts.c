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
 *   - geometry (BBC_SPLIT_GEOMETRY, and AUTO when the names tell nothing;
 *     parts_geometry.c): a tree's trunk is a few large connected pieces,
 *     its foliage many small ones (leaves, cards, twig clusters);
 *   - the user's glob patterns (BBC_SPLIT_PATTERNS).
 * Then, within the trunk, the rules of trunk_rules: with `limbs` its thin
 * pieces join the foliage (parts_geometry.c), without branches_with_trunk the faces off
 * the stem's path (stem.c).
 * Names and patterns are evaluated once per material and group, then looked
 * up per face: linear in the triangles. The geometry adds a radix sort of
 * the vertices and a union-find: linear in practice. No global state; the
 * result depends only on the mesh and the options. */
#include "parts.h"
#include "planes.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

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
 * "tree" is no keyword: files use it for the trunk alone (a group "tree"
 * beside the twigs) as well as for everything ("twig.534_tree"). */
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
void bbc__split_format_count(size_t v, char *out, size_t size) {
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

static void set_why(const split_out *o, const char *text) {
  if (o->why && o->why_size) snprintf(o->why, o->why_size, "%s", text);
}

bbc_result bbc__split_one_part(const split_out *o, const char *why) {
  if (o->triangle_count) memset(o->face_part, 0, o->triangle_count * sizeof *o->face_part);
  *o->part_count = 1;
  memset(o->names, 0, 2 * sizeof o->names[0]);
  snprintf(o->names[0], sizeof o->names[0], "all");
  set_why(o, why);
  return BBC_OK;
}

/* face_part already holds 0 = trunk, 1 = foliage for every face. */
bbc_result bbc__split_two_parts(const split_out *o, const char *why) {
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
 * say so or one says so and the other nothing (one group and materials
 * "Bark" / "Tree_Leaves"; or materials "Trunk" / "Leaves" and groups
 * "tree" / "twigs_Cube.001"). When they contradict each other the face is
 * foliage: the thesis puts the branches with the foliage and keeps the
 * stem apart (2.2.4), and bark-textured twigs inside a foliage object
 * belong to the foliage (a material "Branch" in a group "twig.534_tree"
 * repeated over the crown: clusters of twigs and leaves).
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
    return bbc__split_one_part(o, why);
  }
  uint32_t rest = count[PART_TRUNK] == 0 ? PART_TRUNK : PART_FOLIAGE;
  for (size_t t = 0; t < nt; t++)
    if (o->face_part[t] == 2) o->face_part[t] = rest;
  size_t total[2] = {count[0], count[1]};
  total[rest] += unknown;
  bbc__split_format_count(total[PART_TRUNK], num[0], sizeof num[0]);
  bbc__split_format_count(total[PART_FOLIAGE], num[1], sizeof num[1]);
  bbc__split_format_count(unknown, num[2], sizeof num[2]);
  bbc__split_format_count(conflict, num[3], sizeof num[3]);
  snprintf(why, sizeof why, "names: trunk %s triangles", num[0]);
  if (count[PART_TRUNK]) append(why, sizeof why, " (%s)", names[PART_TRUNK]);
  append(why, sizeof why, ", foliage %s", num[1]);
  if (count[PART_FOLIAGE]) append(why, sizeof why, " (%s)", names[PART_FOLIAGE]);
  if (conflict)
    append(why, sizeof why, "; %s triangles named trunk and foliage count as foliage", num[3]);
  if (unknown)
    append(why, sizeof why, "; %s triangles with other names joined the %s", num[2],
           rest == PART_TRUNK ? "trunk" : "foliage");
  return bbc__split_two_parts(o, why);
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
  bbc__split_format_count(total[PART_TRUNK], num[0], sizeof num[0]);
  bbc__split_format_count(total[PART_FOLIAGE], num[1], sizeof num[1]);
  bbc__split_format_count(count[0], num[2], sizeof num[2]);
  bbc__split_format_count(count[1], num[3], sizeof num[3]);
  bbc__split_format_count(count[2], num[4], sizeof num[4]);
  const char *rest_name = rest == PART_TRUNK ? "trunk" : "foliage";
  if (total[PART_TRUNK] == 0 || total[PART_FOLIAGE] == 0) {
    snprintf(why, sizeof why,
             "no split: the patterns put every face in the %s (%s by trunk patterns, %s by "
             "foliage patterns, %s the rest)",
             total[PART_TRUNK] ? "trunk" : "foliage", num[2], num[3], num[4]);
    return bbc__split_one_part(o, why);
  }
  snprintf(why, sizeof why,
           "patterns: trunk %s triangles, foliage %s (%s by trunk patterns, %s by foliage "
           "patterns, %s the rest, given to the %s)",
           num[0], num[1], num[2], num[3], num[4], rest_name);
  return bbc__split_two_parts(o, why);
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

/* Within the trunk of a split in two: with `limbs`, its thin pieces join
 * the foliage (parts_geometry.c); without branches_with_trunk, unless the limbs found
 * the trunk in several pieces, the faces off its stem's path do (stem.c,
 * thesis 2.2.4). Each says what it moved in `why`. */
static bbc_result trunk_rules(const bbc_mesh *mesh, const bbc_split_options *options,
                              uint32_t *face_part, size_t part_count, char *why, size_t why_size) {
  bbc_result r = BBC_OK;
  size_t trunk_pieces = 0;
  if (options->limbs > 0 && part_count == 2 && mesh->kind != BBC_MESH_POINTS) {
    size_t moved =
        bbc__split_keep_thick_pieces(mesh, face_part, 2 * (size_t)options->limbs, &trunk_pieces);
    if (moved == SIZE_MAX)
      r = BBC_ERROR_OUT_OF_MEMORY;
    else if (moved && why && why_size) {
      size_t l = strlen(why);
      snprintf(why + l, why_size - l, "; limbs: %zu triangles of thin branches join the foliage",
               moved);
    }
  }
  if (r == BBC_OK && !options->branches_with_trunk && part_count == 2 && trunk_pieces <= 1) {
    size_t moved =
        bbc__stem_keep(mesh, face_part, PART_TRUNK, PART_FOLIAGE, bbc_up_axis(options->up));
    if (moved == SIZE_MAX)
      r = BBC_ERROR_OUT_OF_MEMORY;
    else if (moved && why && why_size) {
      size_t l = strlen(why);
      snprintf(why + l, why_size - l, "; stem only: %zu branch triangles join the foliage", moved);
    }
  }
  return r;
}

/* `options` may be NULL: BBC_SPLIT_AUTO. */
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
    r = bbc__split_one_part(&o, mesh->kind == BBC_MESH_POINTS
                                    ? "no split: a point cloud is one part"
                                    : "no split: no triangles");
  } else if (options->mode == BBC_SPLIT_NONE) {
    r = bbc__split_one_part(&o, "no split: split mode none");
  } else if (options->mode == BBC_SPLIT_PATTERNS) {
    r = split_by_patterns(mesh, &trunk_pl, &foliage_pl, rest, &o);
  } else if (options->mode == BBC_SPLIT_GEOMETRY) {
    r = bbc__split_by_geometry(mesh, &o);
  } else {
    int decided = 0;
    r = split_by_names(mesh, &o, &decided);
    if (r == BBC_OK && !decided) {
      if (options->mode == BBC_SPLIT_NAMES)
        r = bbc__split_one_part(&o, "no split: no material or group name says trunk or foliage");
      else
        r = bbc__split_by_geometry(mesh, &o);
    }
  }
  pattern_list_free(&trunk_pl);
  pattern_list_free(&foliage_pl);
  if (r == BBC_OK) r = trunk_rules(mesh, options, face_part, *part_count, why, why_size);
  if (r == BBC_ERROR_OUT_OF_MEMORY)
    return bbc__fail(err, r, "out of memory splitting %zu triangles into parts (split mode %s)",
                     mesh->triangle_count, mode_name(options->mode));
  return r;
}
