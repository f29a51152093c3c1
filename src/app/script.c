/* script.c — the command language of BBCgen's batch files and prompt
 * (thesis Appendix A): a line split into its command and arguments and
 * checked, without running anything. The caller runs the commands on a
 * session (bbcgen's cmd_exec.c); the fuzzer (fuzz/fuzz_batch.c) feeds it
 * arbitrary text. */
#include "app.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const bbc_command_info k_commands[] = {
    {BBC_COMMAND_LOAD, "load", "FILE [nocg] [nomip]",
     "the model (it stays where it is); nomip: its textures without mipmaps"},
    {BBC_COMMAND_SET, "set", "NAME VALUE", "a parameter (PART.NAME for one part: trunk, foliage)"},
    {BBC_COMMAND_SPLIT, "split", "MODE",
     "trunk and foliage: auto, none, names, geometry, trunk=PATTERNS, foliage=..."},
    {BBC_COMMAND_BBC1, "bbc1", "", "step 1: the dual grid and its density (kept for bbc2)"},
    {BBC_COMMAND_BBC2, "bbc2", "", "step 2 on the kept grid: the planes (kept for bbc3)"},
    {BBC_COMMAND_BBC3, "bbc3", "", "step 3 on the kept planes (after texturing changes only)"},
    {BBC_COMMAND_BBC, "bbc", "", "steps 1 to 3"},
    {BBC_COMMAND_PLANES, "planes", "[OUT.json]", "steps 1 and 2, the planes as JSON"},
    {BBC_COMMAND_SHADE, "shade", "N [AMBIENT]", "voxel shadowing for the next step 3 (0 = off)"},
    {BBC_COMMAND_SAVE, "save", "[DIR]",
     "the cloud as VRML into vrml97models/[DIR/]MODEL/MODEL_eX.XX_texN.../"},
    {BBC_COMMAND_SETUP, "setup", "", "print every parameter"},
    {BBC_COMMAND_EXEC, "exec", "FILE", "run a batch file"},
    {BBC_COMMAND_BBCLOAD, "bbcload", "FILE",
     "a saved cloud, shown by show model to compare with the model"},
    {BBC_COMMAND_SHOW, "show", "model|bbc [KEYS]",
     "a window: the model, rectangles, cloud; or the grid's domains, density, faces (Esc "
     "returns)"},
    {BBC_COMMAND_HELP, "help", "[COMMAND]", "the commands, or one"},
    {BBC_COMMAND_CLS, "cls", "", "clear the screen"},
    {BBC_COMMAND_QUIT, "quit", "", "stop (also q)"},
};
#define COMMAND_COUNT (sizeof k_commands / sizeof k_commands[0])

size_t bbc_command_count(void) {
  return COMMAND_COUNT;
}

const bbc_command_info *bbc_command_at(size_t i) {
  return i < COMMAND_COUNT ? &k_commands[i] : NULL;
}

const bbc_command_info *bbc_command_find(const char *name) {
  if (!name) return NULL;
  if (!strcmp(name, "q")) name = "quit";
  for (size_t i = 0; i < COMMAND_COUNT; i++)
    if (!strcmp(name, k_commands[i].name)) return &k_commands[i];
  return NULL;
}

static int blank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

/* The word at s[*i] (blanks before it skipped) into out; 0 when none. A
 * word in double or single quotes ("my trees/oak.obj") runs to the closing
 * quote, blanks included, the quotes left out (to the line's end when it
 * has none). */
static int next_word(const char *s, size_t n, size_t *i, char *out, size_t cap) {
  while (*i < n && blank(s[*i])) (*i)++;
  if (*i < n && (s[*i] == '"' || s[*i] == '\'')) {
    char q = s[(*i)++];
    size_t b = *i;
    while (*i < n && s[*i] != q) (*i)++;
    size_t len = *i - b;
    if (*i < n) (*i)++; /* the closing quote */
    if (len >= cap) len = cap - 1;
    memcpy(out, s + b, len);
    out[len] = 0;
    return 1;
  }
  size_t b = *i;
  while (*i < n && !blank(s[*i])) (*i)++;
  size_t len = *i - b;
  if (!len) return 0;
  if (len >= cap) len = cap - 1;
  memcpy(out, s + b, len);
  out[len] = 0;
  return 1;
}

/* An integer or number that is all of `s`. */
static int whole_long(const char *s, long *v) {
  char *e;
  if (!*s) return 0;
  *v = strtol(s, &e, 10);
  return !*e;
}
static int whole_double(const char *s, double *v) {
  char *e;
  if (!*s) return 0;
  *v = strtod(s, &e);
  return !*e;
}

#define bad(err, ...) bbc_error_set(err, BBC_ERROR_INVALID_ARGUMENT, __VA_ARGS__)

/* The arguments of each command that takes some; `c` is its name. */
static bbc_result parse_load(bbc_command *cmd, const char *c, bbc_error *err) {
  if (!cmd->arg[0]) return bad(err, "%s needs an argument", c);
  size_t j = 0, rn = strlen(cmd->rest);
  char flag[BBC_COMMAND_LINE_MAX];
  while (next_word(cmd->rest, rn, &j, flag, sizeof flag)) {
    if (!strcmp(flag, "nomip"))
      cmd->nomip = 1;
    else if (strcmp(flag, "nocg"))
      return bad(err, "load: '%s' is not a flag (load FILE [nocg] [nomip])", flag);
  }
  return BBC_OK;
}

static bbc_result parse_set(bbc_command *cmd, const char *c, bbc_error *err) {
  if (!cmd->arg[0] || !cmd->rest[0]) return bad(err, "%s needs NAME VALUE", c);
  const char *dot = strchr(cmd->arg, '.');
  const char *name = dot ? dot + 1 : cmd->arg;
  if (dot) {
    if (dot == cmd->arg || (size_t)(dot - cmd->arg) >= sizeof cmd->part)
      return bad(err, "set: '%s' is not PART.NAME", cmd->arg);
    memcpy(cmd->part, cmd->arg, (size_t)(dot - cmd->arg));
  }
  if (!*name || strlen(name) >= sizeof cmd->name)
    return bad(err, "set: '%s' is not a parameter's name", cmd->arg);
  memcpy(cmd->name, name, strlen(name) + 1);
  return BBC_OK;
}

static bbc_result parse_split(bbc_command *cmd, const char *c, bbc_error *err) {
  if (!cmd->arg[0]) return bad(err, "%s needs an argument", c);
  if (cmd->rest[0]) return bad(err, "split takes one word, not '%s' after it", cmd->rest);
  const char *eq = strchr(cmd->arg, '=');
  if (eq) {
    size_t k = (size_t)(eq - cmd->arg);
    int trunk = k == 5 && !strncmp(cmd->arg, "trunk", 5);
    if (!trunk && !(k == 7 && !strncmp(cmd->arg, "foliage", 7)))
      return bad(err, "split: '%s' is not trunk=PATTERNS or foliage=PATTERNS", cmd->arg);
    if (!eq[1]) return bad(err, "split %s needs patterns", trunk ? "trunk=" : "foliage=");
    cmd->split = BBC_SPLIT_PATTERNS;
    cmd->trunk_side = trunk;
    memmove(cmd->rest, eq + 1, strlen(eq + 1) + 1);
    return BBC_OK;
  }
  static const char *const modes[] = {"auto", "none", "names", "geometry"};
  for (int m = 0; m < 4; m++)
    if (!strcmp(cmd->arg, modes[m])) {
      cmd->split = (bbc_split_mode)m;
      return BBC_OK;
    }
  return bad(err, "split must be auto, none, names, geometry, trunk=... or foliage=..., not '%s'",
             cmd->arg);
}

static bbc_result parse_shade(bbc_command *cmd, const char *c, bbc_error *err) {
  if (!cmd->arg[0]) return bad(err, "%s needs an argument", c);
  long v;
  double a = 0;
  if (!whole_long(cmd->arg, &v) || v < 0 || v > 512 ||
      (cmd->rest[0] && (!whole_double(cmd->rest, &a) || !(a >= 0 && a <= 1))))
    return bad(err, "%s NUMVOXELS [AMBIENT]: voxels 0..512, ambient 0..1", c);
  cmd->shade_voxels = (int)v;
  cmd->shade_ambient = a;
  return BBC_OK;
}

bbc_result bbc_command_parse(const char *line, size_t n, bbc_command *cmd, bbc_error *err) {
  int lineno = cmd->line;
  memset(cmd, 0, sizeof *cmd);
  cmd->line = lineno;
  if (memchr(line, 0, n))
    return bbc_error_set(err, BBC_ERROR_INVALID_ARGUMENT, "not text: a NUL byte in the line");
  if (n > BBC_COMMAND_LINE_MAX)
    return bbc_error_set(err, BBC_ERROR_INVALID_ARGUMENT, "a line longer than %d characters",
                         BBC_COMMAND_LINE_MAX);
  size_t i = 0;
  char word[BBC_COMMAND_LINE_MAX + 1];
  if (!next_word(line, n, &i, word, sizeof word) || word[0] == '#') return BBC_OK;
  const bbc_command_info *info = bbc_command_find(word);
  if (!info) return bad(err, "'%s' is not a command (help lists them)", word);
  const char *c = info->name;
  next_word(line, n, &i, cmd->arg, sizeof cmd->arg);
  while (i < n && blank(line[i])) i++;
  size_t e = n;
  while (e > i && blank(line[e - 1])) e--;
  memcpy(cmd->rest, line + i, e - i);
  cmd->rest[e - i] = 0;
  cmd->kind = info->kind;

  switch (info->kind) {
  case BBC_COMMAND_LOAD:
    return parse_load(cmd, c, err);
  case BBC_COMMAND_SET:
    return parse_set(cmd, c, err);
  case BBC_COMMAND_SPLIT:
    return parse_split(cmd, c, err);
  case BBC_COMMAND_SHADE:
    return parse_shade(cmd, c, err);
  case BBC_COMMAND_SHOW:
    if (strcmp(cmd->arg, "model") && strcmp(cmd->arg, "bbc"))
      return bad(err, "show %s: expected show model or show bbc",
                 cmd->arg[0] ? cmd->arg : "needs model or bbc:");
    cmd->show_bbc = cmd->arg[0] == 'b';
    return BBC_OK;
  case BBC_COMMAND_HELP:
    if (cmd->arg[0] && !bbc_command_find(cmd->arg))
      return bad(err, "help: no command '%s' (help lists them)", cmd->arg);
    return BBC_OK;
  case BBC_COMMAND_EXEC:
  case BBC_COMMAND_BBCLOAD:
    if (!cmd->arg[0]) return bad(err, "%s needs an argument", c);
    return BBC_OK;
  default:
    return BBC_OK;
  }
}

bbc_result bbc_script_next(const char *text, size_t size, const char *name, size_t *pos, int *line,
                           bbc_command *cmd, bbc_error *err) {
  while (*pos < size) {
    const char *s = text + *pos;
    const char *nl = memchr(s, '\n', size - *pos);
    size_t n = nl ? (size_t)(nl - s) : size - *pos;
    *pos += n + (nl != NULL);
    ++*line;
    cmd->line = *line;
    bbc_result r = bbc_command_parse(s, n, cmd, err);
    if (r != BBC_OK) {
      if (err) { /* "NAME:LINE: " first */
        char msg[sizeof err->message];
        memcpy(msg, err->message, sizeof msg);
        msg[sizeof msg - 1] = 0;
        int k = snprintf(err->message, sizeof err->message, "%.300s:%d: ", name ? name : "(text)",
                         *line);
        size_t at = k > 0 ? (size_t)k : 0, len = strlen(msg);
        if (at + len >= sizeof err->message) len = sizeof err->message - 1 - at;
        memcpy(err->message + at, msg, len);
        err->message[at + len] = 0;
      }
      return r;
    }
    if (cmd->kind != BBC_COMMAND_NONE) return BBC_OK;
  }
  memset(cmd, 0, sizeof *cmd);
  cmd->line = *line;
  return BBC_OK;
}
