/* mapfile.c — the forest engine's description files, exactly as the
 * thesis's Appendix B ("Perfect Motion manual") defines them: the map file
 * (terrain, sky, water, fog and the objects placed on it) and the model
 * description file (fade, shadow and LOD blocks). Parsed from memory, so
 * that tools, tests and fuzzers call the same function; the library never
 * prints: every problem is an error naming file:line and what was expected.
 *
 * Syntax: whitespace-separated words; a line whose first non-blank
 * character is ' (high comma) is a comment. A command's arguments are the
 * words that follow it, wherever the line breaks fall (the thesis writes an
 * LOD block over several lines). A word may be written in double quotes to
 * hold spaces (an extension: file names). */
#include "bbc_forest.h"
#include "io.h"

#include <assert.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#define MAX_WORD  4096
#define MAX_COUNT 100000000L /* objects of one rndtree line */

typedef struct lexer {
  const char *s, *end;
  const char *name; /* for messages */
  int line;
  char word[MAX_WORD];
  int word_line;
  int cmd_line;   /* where the command being read began */
  char hint[128]; /* said after a message about a value on a later line */
} lexer;

/* " (the command begins on line N: too few values there?)" when the word
 * that did not fit is on a later line than its command, else "". */
/* A word for a message: its first 64 bytes, control characters (a terminal's
 * escape sequences in a binary file) written as \xNN. */
static const char *shown(const char *w, char *out, size_t size) {
  size_t n = 0;
  for (size_t i = 0; w[i] && i < 64 && n + 5 < size; i++) {
    unsigned char c = (unsigned char)w[i];
    if (c < 0x20 || c == 0x7f)
      n += (size_t)snprintf(out + n, size - n, "\\x%02x", c);
    else
      out[n++] = (char)c;
  }
  out[n] = 0;
  return out;
}

static const char *later_line(lexer *lx) {
  lx->hint[0] = '\0';
  if (lx->cmd_line > 0 && lx->word_line > lx->cmd_line)
    snprintf(lx->hint, sizeof lx->hint, " (the command begins on line %d: too few values there?)",
             lx->cmd_line);
  return lx->hint;
}

/* The next word into lx->word; 0 at the end of the text, -1 on an error. */
static int next_word(lexer *lx, bbc_error *err) {
  for (;;) {
    while (lx->s < lx->end && (*lx->s == ' ' || *lx->s == '\t' || *lx->s == '\r' ||
                               *lx->s == '\n' || *lx->s == '\f' || *lx->s == '\v')) {
      if (*lx->s == '\n') lx->line++;
      lx->s++;
    }
    if (lx->s >= lx->end) return 0;
    if (*lx->s == '\'') { /* a comment: to the end of the line */
      while (lx->s < lx->end && *lx->s != '\n') lx->s++;
      continue;
    }
    break;
  }
  lx->word_line = lx->line;
  size_t n = 0;
  if (*lx->s == '"') {
    lx->s++;
    while (lx->s < lx->end && *lx->s != '"' && *lx->s != '\n') {
      if (n + 1 >= MAX_WORD) break;
      lx->word[n++] = *lx->s++;
    }
    if (lx->s >= lx->end || *lx->s != '"') {
      bbc__fail(err, BBC_ERROR_CORRUPT, "%s:%d: a quoted word is not closed on its line", lx->name,
                lx->word_line);
      return -1;
    }
    lx->s++;
  } else {
    while (lx->s < lx->end && !(*lx->s == ' ' || *lx->s == '\t' || *lx->s == '\r' ||
                                *lx->s == '\n' || *lx->s == '\f' || *lx->s == '\v')) {
      if (n + 1 >= MAX_WORD) break;
      if (*lx->s == '\0') {
        bbc__fail(err, BBC_ERROR_CORRUPT, "%s:%d: a NUL byte: not a text file", lx->name, lx->line);
        return -1;
      }
      lx->word[n++] = *lx->s++;
    }
  }
  if (n + 1 >= MAX_WORD) {
    bbc__fail(err, BBC_ERROR_CORRUPT, "%s:%d: a word longer than %d characters", lx->name,
              lx->word_line, MAX_WORD - 1);
    return -1;
  }
  lx->word[n] = '\0';
  return 1;
}

/* The next word, which must exist: `what` says what was expected. */
static int need_word(lexer *lx, const char *cmd, const char *what, bbc_error *err) {
  int r = next_word(lx, err);
  if (r < 0) return 0;
  if (r == 0) {
    /* named at the line the command begins on: the file ended within it */
    bbc__fail(err, BBC_ERROR_CORRUPT, "%s:%d: %s: expected %s, found the end of the file", lx->name,
              lx->cmd_line > 0 ? lx->cmd_line : lx->line, cmd, what);
    return 0;
  }
  return 1;
}

static int need_real(lexer *lx, const char *cmd, const char *what, double *v, bbc_error *err) {
  if (!need_word(lx, cmd, what, err)) return 0;
  char *e;
  errno = 0;
  double x = strtod(lx->word, &e);
  if (e == lx->word || *e || errno == ERANGE || !isfinite(x)) {
    bbc__fail(err, BBC_ERROR_CORRUPT, "%s:%d: %s: expected %s (a number), found '%.64s'%s",
              lx->name, lx->word_line, cmd, what, lx->word, later_line(lx));
    return 0;
  }
  *v = x;
  return 1;
}

static int need_long(lexer *lx, const char *cmd, const char *what, long lo, long hi, long *v,
                     bbc_error *err) {
  if (!need_word(lx, cmd, what, err)) return 0;
  char *e;
  errno = 0;
  long x = strtol(lx->word, &e, 10);
  if (e == lx->word || *e || errno == ERANGE || x < lo || x > hi) {
    bbc__fail(err, BBC_ERROR_CORRUPT,
              "%s:%d: %s: expected %s (a whole number %ld..%ld), found '%.64s'%s", lx->name,
              lx->word_line, cmd, what, lo, hi, lx->word, later_line(lx));
    return 0;
  }
  *v = x;
  return 1;
}

static int need_flag(lexer *lx, const char *cmd, const char *what, int *v, bbc_error *err) {
  long x;
  if (!need_long(lx, cmd, what, 0, 1, &x, err)) return 0;
  *v = (int)x;
  return 1;
}

static int need_string(lexer *lx, const char *cmd, const char *what, char **v, bbc_error *err) {
  if (!need_word(lx, cmd, what, err)) return 0;
  free(*v);
  *v = bbc__strdup(lx->word);
  if (!*v) {
    bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", lx->name);
    return 0;
  }
  return 1;
}

static int check(lexer *lx, int ok, const char *fmt, const char *cmd, bbc_error *err) {
  if (!ok) bbc__fail(err, BBC_ERROR_CORRUPT, "%s:%d: %s: %s", lx->name, lx->word_line, cmd, fmt);
  return ok;
}

/* ---- map files ------------------------------------------------------------ */

void bbc_forest_map_free(bbc_forest_map *map) {
  if (!map) return;
  free(map->hmap);
  free(map->colmap);
  free(map->skymap);
  free(map->name);
  for (size_t i = 0; i < map->placement_count; i++) {
    free(map->placements[i].file);
    free(map->placements[i].file2);
  }
  free(map->placements);
  memset(map, 0, sizeof *map);
}

static bbc_forest_placement *new_placement(bbc_forest_map *map, size_t *cap) {
  if (map->placement_count == *cap) {
    size_t nc = *cap ? 2 * *cap : 16;
    bbc_forest_placement *p = realloc(map->placements, nc * sizeof *p);
    if (!p) return NULL;
    map->placements = p;
    *cap = nc;
  }
  bbc_forest_placement *p = &map->placements[map->placement_count++];
  memset(p, 0, sizeof *p);
  return p;
}

static int parse_placement(lexer *lx, bbc_forest_map *map, size_t *cap, bbc_forest_place_kind kind,
                           bbc_error *err) {
  const char *cmd = kind == BBC_FOREST_OBJECT2D  ? "object2d"
                    : kind == BBC_FOREST_RNDTREE ? "rndtree"
                                                 : "rndtree2";
  int line = lx->word_line;
  bbc_forest_placement *p = new_placement(map, cap);
  if (!p) {
    bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", lx->name);
    return 0;
  }
  p->kind = kind;
  p->line = line;
  p->count = 1;
  if (!need_string(lx, cmd, "a model description file or 3D model", &p->file, err)) return 0;
  if (kind == BBC_FOREST_RNDTREE2 && !need_string(lx, cmd, "the second model file", &p->file2, err))
    return 0;
  if (!need_real(lx, cmd, "the scale", &p->scale, err)) return 0;
  if (!check(lx, p->scale > 0, "the scale must be > 0", cmd, err)) return 0;
  if (kind != BBC_FOREST_OBJECT2D) {
    long n;
    if (!need_long(lx, cmd, "the number of objects", 0, MAX_COUNT, &n, err)) return 0;
    p->count = (size_t)n;
  }
  if (!need_flag(lx, cmd, "mipmap (0 or 1)", &p->mipmap, err)) return 0;
  if (kind == BBC_FOREST_OBJECT2D) {
    if (!need_real(lx, cmd, "the map position x", &p->x, err) ||
        !need_real(lx, cmd, "the map position y", &p->y, err))
      return 0;
  } else if (!need_flag(lx, cmd, "random orientation (0 or 1)", &p->random, err)) {
    return 0;
  }
  static const char *const rot[3] = {"the rotation xr (degrees)", "the rotation yr (degrees)",
                                     "the rotation zr (degrees)"};
  for (int k = 0; k < 3; k++)
    if (!need_real(lx, cmd, rot[k], &p->rotation_deg[k], err)) return 0;
  return need_real(lx, cmd, "the additional altitude", &p->altitude, err);
}

void bbc_forest_map_default(bbc_forest_map *map) {
  assert(map);
  memset(map, 0, sizeof *map);
  map->heightscale = 1.0;
  map->stretch = 1.0;
  map->light[0] = 1.0; /* the terrain lit from above and the side */
  map->light[1] = 1.0;
  map->light[2] = 0.5;
  map->roetger = 10.0;
  map->wind.dir[0] = 1.0; /* still, and towards +x once it blows */
}

/* The next word when it is a number on the command's line (an optional
 * value): 1 and *v; else 0 with the lexer where it was. */
static int optional_real(lexer *lx, double *v) {
  lexer save = *lx;
  bbc_error ignored;
  if (next_word(lx, &ignored) > 0 && lx->word_line == lx->cmd_line) {
    char *e;
    errno = 0;
    double x = strtod(lx->word, &e);
    if (e != lx->word && !*e && errno != ERANGE && isfinite(x)) {
      *v = x;
      return 1;
    }
  }
  *lx = save;
  return 0;
}

/* wind STRENGTH [DIRX DIRZ] */
static int parse_wind(lexer *lx, bbc_forest_map *map, bbc_error *err) {
  bbc_forest_wind *w = &map->wind;
  if (!need_real(lx, "wind", "the wind's strength", &w->strength, err) ||
      !check(lx, w->strength >= 0 && w->strength <= 100,
             "the wind's strength must be within 0..100 (1 = a breeze)", "wind", err))
    return 0;
  double d[2];
  if (!optional_real(lx, &d[0])) return 1;
  if (!need_real(lx, "wind", "the direction's z (after its x)", &d[1], err)) return 0;
  double n = sqrt(d[0] * d[0] + d[1] * d[1]);
  if (!check(lx, n > 0, "the wind's direction must not be zero", "wind", err)) return 0;
  w->dir[0] = d[0] / n;
  w->dir[1] = d[1] / n;
  return 1;
}

bbc_result bbc_forest_map_parse(const char *text, size_t size, const char *name,
                                bbc_forest_map *map, bbc_error *err) {
  assert((text || size == 0) && map);
  bbc_forest_map_default(map);
  lexer lx = {text, text + size, name ? name : "map", 1, {0}, 1, 0, {0}};
  size_t cap = 0;
  int r;
  while ((r = next_word(&lx, err)) > 0) {
    const char *w = lx.word;
    char word[5 * 64 + 1];
    lx.cmd_line = lx.word_line;
    int ok = 1;
    if (!strcasecmp(w, "hmap")) {
      ok = need_string(&lx, "hmap", "the heightmap image file", &map->hmap, err);
      map->hmap_line = lx.cmd_line;
    } else if (!strcasecmp(w, "hmapfilter")) {
      long a = 0, b = 0;
      ok = need_long(&lx, "hmapfilter", "the filter radius", 0, 64, &a, err) &&
           need_long(&lx, "hmapfilter", "the filter passes", 0, 64, &b, err);
      map->hmap_filter_radius = (int)a;
      map->hmap_filter_passes = (int)b;
    } else if (!strcasecmp(w, "colmap")) {
      ok = need_string(&lx, "colmap", "the colour map image file", &map->colmap, err);
      map->colmap_line = lx.cmd_line;
    } else if (!strcasecmp(w, "heightscale")) {
      ok = need_real(&lx, "heightscale", "the vertical scale", &map->heightscale, err) &&
           check(&lx, map->heightscale > 0, "the vertical scale must be > 0", "heightscale", err);
    } else if (!strcasecmp(w, "stretch")) {
      ok = need_real(&lx, "stretch", "the horizontal stretch", &map->stretch, err) &&
           check(&lx, map->stretch > 0, "the horizontal stretch must be > 0", "stretch", err);
    } else if (!strcasecmp(w, "light")) {
      ok = need_real(&lx, "light", "the light vector x", &map->light[0], err) &&
           need_real(&lx, "light", "the light vector y", &map->light[1], err) &&
           need_real(&lx, "light", "the light vector z", &map->light[2], err) &&
           check(&lx, map->light[0] != 0 || map->light[1] != 0 || map->light[2] != 0,
                 "the light vector must not be zero", "light", err);
    } else if (!strcasecmp(w, "wind")) {
      ok = parse_wind(&lx, map, err);
    } else if (!strcasecmp(w, "farclip")) {
      ok = need_real(&lx, "farclip", "the far clipping distance (map vertices)", &map->farclip,
                     err) &&
           check(&lx, map->farclip > 0, "the far clipping distance must be > 0", "farclip", err);
    } else if (!strcasecmp(w, "roetger")) {
      ok = need_real(&lx, "roetger", "the terrain detail factor", &map->roetger, err) &&
           check(&lx, map->roetger > 0, "the terrain detail factor must be > 0", "roetger", err);
    } else if (!strcasecmp(w, "skymap")) {
      ok = need_string(&lx, "skymap", "the sky box's file stem", &map->skymap, err);
      map->skymap_line = lx.cmd_line;
    } else if (!strcasecmp(w, "waterheight")) {
      ok = need_real(&lx, "waterheight", "the water level", &map->water_height, err);
      map->has_water = 1;
    } else if (!strcasecmp(w, "fog")) {
      ok = need_real(&lx, "fog", "the fog's start", &map->fog_start, err) &&
           need_real(&lx, "fog", "the fog's end", &map->fog_end, err) &&
           check(&lx, map->fog_end > map->fog_start && map->fog_start >= 0,
                 "the fog must end beyond where it starts (0 <= start < end)", "fog", err);
      map->has_fog = 1;
    } else if (!strcasecmp(w, "numobjs")) {
      long n = 0;
      ok = need_long(&lx, "numobjs", "the number of objects", 0, MAX_COUNT, &n, err);
      map->numobjs = (size_t)n;
      map->has_numobjs = 1;
    } else if (!strcasecmp(w, "object2d")) {
      ok = parse_placement(&lx, map, &cap, BBC_FOREST_OBJECT2D, err);
    } else if (!strcasecmp(w, "rndtree")) {
      ok = parse_placement(&lx, map, &cap, BBC_FOREST_RNDTREE, err);
    } else if (!strcasecmp(w, "rndtree2")) {
      ok = parse_placement(&lx, map, &cap, BBC_FOREST_RNDTREE2, err);
    } else {
      bbc__fail(
          err, BBC_ERROR_CORRUPT,
          "%s:%d: unknown command '%s' (expected hmap, hmapfilter, colmap, heightscale, "
          "stretch, light, wind, farclip, roetger, skymap, waterheight, fog, numobjs, object2d, "
          "rndtree or rndtree2)%s",
          lx.name, lx.word_line, shown(w, word, sizeof word),
          strtod(w, NULL) != 0 || w[0] == '0' ? ": a number, one value too many for the "
                                                "command before it?"
                                              : "");
      ok = 0;
    }
    if (!ok) {
      bbc_forest_map_free(map);
      return err ? err->code : BBC_ERROR_CORRUPT;
    }
  }
  if (r < 0) {
    bbc_forest_map_free(map);
    return err ? err->code : BBC_ERROR_CORRUPT;
  }
  if (!map->hmap) {
    bbc_forest_map_free(map);
    return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: no heightmap: a map needs 'hmap <file>'",
                     lx.name);
  }
  map->name = bbc__strdup(lx.name);
  if (!map->name) {
    bbc_forest_map_free(map);
    return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", lx.name);
  }
  return BBC_OK;
}

/* ---- model description files --------------------------------------------- */

void bbc_forest_model_free(bbc_forest_model *model) {
  if (!model) return;
  for (size_t i = 0; i < model->lod_count; i++)
    for (int k = 0; k < 2; k++) free(model->lods[i].part[k].file);
  free(model->lods);
  memset(model, 0, sizeof *model);
}

/* One LOD block after the word LOD: ( file1 F [opts] [file2 F [opts]] min D max D ). */
static int parse_lod(lexer *lx, bbc_forest_model *m, size_t *cap, bbc_error *err) {
  const char *cmd = "LOD";
  if (m->lod_count == *cap) {
    size_t nc = *cap ? 2 * *cap : 4;
    bbc_forest_lod *l = realloc(m->lods, nc * sizeof *l);
    if (!l) {
      bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "%s: out of memory", lx->name);
      return 0;
    }
    m->lods = l;
    *cap = nc;
  }
  bbc_forest_lod *lod = &m->lods[m->lod_count++];
  memset(lod, 0, sizeof *lod);
  lod->line = lx->word_line;
  lx->cmd_line = 0; /* a block spans lines: no "too few values" hint inside */
  if (!need_word(lx, cmd, "'('", err)) return 0;
  if (!check(lx, !strcmp(lx->word, "("), "expected '(' after LOD", cmd, err)) return 0;
  int has_min = 0, has_max = 0, part = -1;
  for (;;) {
    if (!need_word(lx, cmd, "file1, file2, min, max or ')'", err)) return 0;
    const char *w = lx->word;
    if (!strcmp(w, ")")) break;
    if (!strcasecmp(w, "file1") || !strcasecmp(w, "file2")) {
      int k = w[4] - '1';
      if (!check(lx, k == part + 1,
                 k == 0 ? "file1 is given twice" : "file2 must follow file1, once", cmd, err))
        return 0;
      part = k;
      if (!need_string(lx, cmd, "a model file name", &lod->part[k].file, err)) return 0;
      lod->part_count = k + 1;
    } else if (!strcasecmp(w, "displaylist") || !strcasecmp(w, "mipmap") ||
               !strcasecmp(w, "lighting")) {
      if (!check(lx, part >= 0, "an option must follow a file (file1 F displaylist ...)", cmd, err))
        return 0;
      bbc_forest_lod_file *f = &lod->part[part];
      if (!strcasecmp(w, "displaylist")) f->displaylist = 1;
      if (!strcasecmp(w, "mipmap")) f->mipmap = 1;
      if (!strcasecmp(w, "lighting")) f->lighting = 1;
    } else if (!strcasecmp(w, "min")) {
      if (!need_real(lx, cmd, "the least distance", &lod->min_dist, err)) return 0;
      has_min = 1;
    } else if (!strcasecmp(w, "max")) {
      if (!need_real(lx, cmd, "the greatest distance", &lod->max_dist, err)) return 0;
      has_max = 1;
    } else {
      bbc__fail(err, BBC_ERROR_CORRUPT,
                "%s:%d: LOD: unknown word '%.64s' (expected file1, file2, displaylist, mipmap, "
                "lighting, min, max or ')')",
                lx->name, lx->word_line, w);
      return 0;
    }
  }
  if (!check(lx, part >= 0, "the block names no file (file1 <file>)", cmd, err)) return 0;
  if (!check(lx, has_min && has_max, "the block needs 'min <distance>' and 'max <distance>'", cmd,
             err))
    return 0;
  return check(lx, lod->min_dist >= 0 && lod->max_dist > lod->min_dist,
               "the distances must satisfy 0 <= min < max", cmd, err);
}

bbc_result bbc_forest_model_parse(const char *text, size_t size, const char *name,
                                  bbc_forest_model *model, bbc_error *err) {
  assert((text || size == 0) && model);
  memset(model, 0, sizeof *model);
  lexer lx = {text, text + size, name ? name : "model", 1, {0}, 1, 0, {0}};
  size_t cap = 0;
  int r;
  while ((r = next_word(&lx, err)) > 0) {
    const char *w = lx.word;
    char word[5 * 64 + 1];
    lx.cmd_line = lx.word_line;
    int ok = 1;
    if (!strcasecmp(w, "fade")) {
      ok = need_real(&lx, "fade", "the fade length (units per half transition)", &model->fade,
                     err) &&
           check(&lx, model->fade >= 0, "the fade length must be >= 0", "fade", err);
    } else if (!strcasecmp(w, "shadowrad")) {
      ok =
          need_real(&lx, "shadowrad", "the shadow's radius", &model->shadow_radius, err) &&
          check(&lx, model->shadow_radius > 0, "the shadow's radius must be > 0", "shadowrad", err);
    } else if (!strcasecmp(w, "shadowcutoff")) {
      ok = need_real(&lx, "shadowcutoff", "the shadow's cutoff radius", &model->shadow_cutoff,
                     err) &&
           check(&lx, model->shadow_cutoff >= 0, "the cutoff radius must be >= 0", "shadowcutoff",
                 err);
    } else if (!strcasecmp(w, "LOD")) {
      ok = parse_lod(&lx, model, &cap, err);
    } else if (!strcmp(w, "LOD(")) {
      bbc__fail(err, BBC_ERROR_CORRUPT, "%s:%d: write 'LOD (' with a space", lx.name, lx.word_line);
      ok = 0;
    } else {
      bbc__fail(err, BBC_ERROR_CORRUPT,
                "%s:%d: unknown command '%s' (expected fade, shadowrad, shadowcutoff or LOD)",
                lx.name, lx.word_line, shown(w, word, sizeof word));
      ok = 0;
    }
    if (!ok) {
      bbc_forest_model_free(model);
      return err ? err->code : BBC_ERROR_CORRUPT;
    }
  }
  if (r < 0) {
    bbc_forest_model_free(model);
    return err ? err->code : BBC_ERROR_CORRUPT;
  }
  if (model->lod_count == 0) {
    bbc_forest_model_free(model);
    return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: no LOD block: a model needs 'LOD ( file1 ... )'",
                     lx.name);
  }
  if (model->shadow_cutoff > 0 && model->shadow_cutoff > model->shadow_radius) {
    bbc_forest_model_free(model);
    return bbc__fail(err, BBC_ERROR_CORRUPT, "%s: shadowcutoff (%g) must not exceed shadowrad (%g)",
                     lx.name, model->shadow_cutoff, model->shadow_radius);
  }
  return BBC_OK;
}

/* ---- from files ----------------------------------------------------------- */

bbc_result bbc_forest_map_load(const char *path, bbc_forest_map *map, bbc_error *err) {
  assert(path && map);
  char *text = NULL;
  size_t n = 0;
  bbc_forest_map_default(map);
  bbc_result r = bbc__check_input_file(path, err);
  if (r == BBC_OK) r = bbc__read_whole_file(path, &text, &n, err);
  if (r != BBC_OK) return r;
  r = bbc_forest_map_parse(text, n, path, map, err);
  free(text);
  return r;
}

bbc_result bbc_forest_model_load(const char *path, bbc_forest_model *model, bbc_error *err) {
  assert(path && model);
  char *text = NULL;
  size_t n = 0;
  memset(model, 0, sizeof *model);
  bbc_result r = bbc__check_input_file(path, err);
  if (r == BBC_OK) r = bbc__read_whole_file(path, &text, &n, err);
  if (r != BBC_OK) return r;
  r = bbc_forest_model_parse(text, n, path, model, err);
  free(text);
  return r;
}
