/*
 * app.h — the application layer (src/app): BBCgen's workflow as the tools
 * run it — the session that keeps a model, its planes and its cloud between
 * steps, what is written of it (cloud files, the report, the preview, the
 * save folders), the command language of batch files and the prompt, the
 * by-hand parameter rules. Built on the public library (bbc.h); linked into bbcgen and the tests,
 * not installed.
 */
#ifndef BBC_APP_H
#define BBC_APP_H

#include "bbc.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- parameters set by hand ---------------------------------------------- */
/* Parameters as a person sets them (bbcgen's command line, its prompt, the
 * session): which were set by hand, a bit per bbc_param_at index. A value
 * set by hand is meant: a texres set by hand turns atlasmax off unless
 * atlasmax is set by hand too, and an epsilon (the model's or a part's) turns
 * maxplanes and minplanes off unless they are set by hand too, in any order. */
typedef uint64_t bbc_hand;
/* bbc_params_set, then the value counts as set by hand. */
bbc_result bbc_params_set_by_hand(bbc_params *params, bbc_hand *hand, const char *name,
                                  const char *text, bbc_error *err);
/* Counts `name` as set by hand (a value set elsewhere, e.g. a part's own
 * epsilon) and applies the rules. */
void bbc_params_note_hand(bbc_params *params, bbc_hand *hand, const char *name);
int bbc_params_by_hand(bbc_hand hand, const char *name);
/* Appendix A's defaults (bbc_params_thesis) for every parameter not set by
 * hand (bbcgen --thesis). */
void bbc_params_thesis_merge(bbc_params *params, bbc_hand hand);
/* A chain of levels of detail asks for its epsilons: maxplanes and
 * minplanes off unless set by hand. */
void bbc_params_lod_chain(bbc_params *params, bbc_hand hand);

/* How a cloud is lit (bbcgen --lighting): MATERIAL bakes the albedo, a
 * normal map and an occlusion map for engines to light (prelight 0, nm 1,
 * occlusion 64, lit materials); BAKED bakes a fixed light into the colours
 * and marks the materials unlit (prelight 1, nm 0, occlusion 0), as the
 * thesis does. Parameters set by hand are kept. */
typedef enum bbc_lighting { BBC_LIGHTING_MATERIAL = 0, BBC_LIGHTING_BAKED = 1 } bbc_lighting;
void bbc_params_lighting(bbc_params *params, bbc_hand hand, bbc_lighting mode);
/* The lighting an output gets unless asked: MATERIAL for glTF (.glb,
 * .gltf), BAKED for VRML and OBJ (viewers that light with a headlight or
 * not at all). */
bbc_lighting bbc_lighting_for_output(const char *path);
/* What a cloud baked with `params` carries, for people: "material",
 * "baked", ... */
const char *bbc_params_lighting_name(const bbc_params *params);

/* ---- session: BBCgen's workflow (thesis Appendix A), GL-free ----------- */
/* A model, its planes (steps 1 and 2) and its cloud (step 3) kept between
 * steps, as BBCgen's prompt keeps them: after a change of texturing
 * parameters only ('*' in Appendix A) step 3 runs again on the kept planes;
 * any other change needs the planes again (bbc_session_stale_step says which
 * parameter and step). Every step builds into new state and replaces the
 * old only when it is whole: a failed or cancelled step (bbc_callbacks
 * cancel) leaves the session as it was. Options are the caller's and are
 * read by each call; the session copies what it must remember. */
typedef struct bbc_session bbc_session;

/* A new, empty session (NULL: out of memory), and its release with all it
 * keeps (NULL: nothing). */
bbc_session *bbc_session_new(void);
void bbc_session_free(bbc_session *session);
/* Loads a model in place of the current one (planes and cloud dropped). */
bbc_result bbc_session_load(bbc_session *session, const char *path, const bbc_load_options *options,
                            bbc_error *err);
/* Step 1 (bbc1): the grid; planes and cloud are dropped. */
bbc_result bbc_session_build_grid(bbc_session *session, const bbc_planes_options *options,
                                  bbc_error *err);
/* Step 2 (bbc2) on the kept grid (the cloud is dropped); refused
 * (BBC_ERROR_INVALID_ARGUMENT, naming the parameter) without a grid or when
 * `options` changed something step 1 uses. */
bbc_result bbc_session_select_planes(bbc_session *session, const bbc_planes_options *options,
                                     bbc_error *err);
/* Step 3 on the kept planes; refused (BBC_ERROR_INVALID_ARGUMENT, naming
 * the parameter) when `options` changed something steps 1 or 2 use. */
bbc_result bbc_session_build_cloud(bbc_session *session, const bbc_planes_options *options,
                                   bbc_error *err);
/* Steps 1 to 3, all of them again. */
bbc_result bbc_session_run(bbc_session *session, const bbc_planes_options *options, bbc_error *err);
/* The first step `options` would need again (bbc_planes_options_stale_step
 * against the planes' options; 0: none), -1 without planes. */
int bbc_session_stale_step(const bbc_session *session, const bbc_planes_options *options,
                           const char **which);
/* The same against the grid's options: 1 when step 1 is needed again, 0
 * when the grid serves `options`, -1 without a grid. */
int bbc_session_grid_stale_step(const bbc_session *session, const bbc_planes_options *options,
                                const char **which);
/* Levels of detail (bbcgen --lod): steps 1 to 3 for each epsilon (percent,
 * increasing), maxplanes/minplanes as in `options` (bbc_params_lod_chain
 * turns them off); level 0 becomes the session's grid, planes and cloud,
 * the others are kept beside it until level 0's cloud changes. */
#define BBC_SESSION_MAX_LEVELS 8
bbc_result bbc_session_run_levels(bbc_session *session, const bbc_planes_options *options,
                                  const double *epsilons, size_t count, bbc_error *err);
/* One level of a chain: its epsilon (percent); the tree's height on screen,
 * in pixels, where the level starts to be shown (0: not known); its texres
 * (0: the parameters' texres and atlasmax). */
typedef struct bbc_lod_level {
  double epsilon_pct;
  double screen_px;
  int texres;
} bbc_lod_level;
/* bbc_session_run_levels with screen sizes and texres per level. Along the
 * chain texels and triangles strictly fall: a level with as many texels as
 * the one before it is baked again at half its texres, one with as many
 * triangles gets a 1.5x epsilon (up to 99 %), until they fall. */
bbc_result bbc_session_run_chain(bbc_session *session, const bbc_planes_options *options,
                                 const bbc_lod_level *levels, size_t count, bbc_error *err);
/* The tree's height on screen, in pixels, where level k starts to be shown
 * (0 when the chain was made from epsilons only). */
double bbc_session_get_level_screen_px(const bbc_session *session, size_t k);
/* On: bbc_session_write also writes each level of a glTF chain as a file
 * of its own, OUT_LOD<k>.glb|.gltf, a node named <model>_LOD<k> (for
 * engines that do not read MSFT_lod). */
void bbc_session_set_level_files(bbc_session *session, int on);
/* OUT_LOD<k>.EXT: level k's own file (bbc_session_set_level_files). */
void bbc_session_get_level_file_path(const char *path, size_t k, char *buf, size_t size);
/* Levels held: 0 without a cloud, 1 after a run or step 3, more after
 * bbc_session_run_levels. */
size_t bbc_session_get_level_count(const bbc_session *session);
/* Level k's cloud (NULL past the last), its planes, the parameters it was
 * made with and the epsilon asked (each may be NULL). */
const bbc_cloud *bbc_session_get_level(const bbc_session *session, size_t k,
                                       const bbc_planeset **planes, const bbc_params **params,
                                       double *epsilon_pct);
/* " (raised from 6 % by maxplanes 32)" when maxplanes/minplanes moved level
 * k's epsilon, else "". */
void bbc_session_get_epsilon_note(const bbc_session *session, size_t k, char *buf, size_t size);
const char *bbc_session_get_model_path(const bbc_session *session);
/* Seconds the last load and the last write took. */
void bbc_session_get_times(const bbc_session *session, double *load_s, double *write_s);

/* What bbcgen writes, from the session's levels (byte for byte the same):
 * by the extension .glb/.gltf (one file; a chain as MSFT_lod with nodes
 * <model>_LOD<k> and MSFT_screencoverage, one shared atlas when it fits),
 * .obj or .wrl (level k > 0 in OUT_lod<k>.EXT), each stating the parameters
 * and the epsilon used. Atomic: nothing half-written. */
bbc_result bbc_session_write(bbc_session *session, const char *path, const bbc_callbacks *callbacks,
                             bbc_error *err);
/* Takes the output-only parameters of `params` (`format`, `dds`: how a
 * cloud is written, not what it is) into every level, so that a `set` of
 * them after the steps acts on the next bbc_session_write/_save. */
void bbc_session_set_output(bbc_session *session, const bbc_params *params);
/* The file of level k that bbc_session_write makes for `path`. */
void bbc_session_get_output_path(const char *path, size_t k, char *buf, size_t size);
/* Appendix A's save: the cloud as VRML in
 * vrml97models/[DIR/]<model>/<model>_eX.XX_texN[_nm][_pl]/<model>.wrl under
 * the current folder (DIR may be NULL; no leading '/', no '..'); `written`
 * (may be NULL) gets the file's path. */
bbc_result bbc_session_save(bbc_session *session, const char *dir, const bbc_callbacks *callbacks,
                            char *written, size_t written_size, bbc_error *err);
/* The JSON report of bbcgen --report: the model, the parameters, times,
 * every level's planes, billboards and atlas. `output` (may be NULL): the
 * cloud file it describes. */
bbc_result bbc_session_write_report(const bbc_session *session, const char *path,
                                    const char *output, bbc_error *err);
/* The preview sheet of bbcgen --preview: four views (front, side, above,
 * oblique) of the original, the cloud and the billboards' outlines coloured
 * by kind; `cell` pixels a view (16 to 4096). */
bbc_result bbc_session_write_preview(const bbc_session *session, const char *path, int cell,
                                     bbc_error *err);

/* What the session holds now, or NULL. */
const bbc_mesh *bbc_session_get_model(const bbc_session *session);
const bbc_grid *bbc_session_get_grid(const bbc_session *session);
const bbc_planeset *bbc_session_get_planes(const bbc_session *session);
const bbc_cloud *bbc_session_get_cloud(const bbc_session *session);

/* ---- the command language (Appendix A's batch files and prompt) -------- */
/* One command per line, words separated by blanks, '#' starting a comment
 * line. The library parses; the caller (bbcgen's batch files and prompt)
 * runs the commands on a session. */
typedef enum bbc_command_kind {
  BBC_COMMAND_NONE = 0, /* no command: the end of the text */
  BBC_COMMAND_LOAD,     /* load FILE [nocg] [nomip] */
  BBC_COMMAND_SET,      /* set [PART.]NAME VALUE */
  BBC_COMMAND_SPLIT,    /* split auto|none|names|geometry, split trunk=P / foliage=P */
  BBC_COMMAND_BBC1,
  BBC_COMMAND_BBC2,
  BBC_COMMAND_BBC3,
  BBC_COMMAND_BBC,
  BBC_COMMAND_PLANES,  /* planes [OUT.json] */
  BBC_COMMAND_SHADE,   /* shade N [AMBIENT] */
  BBC_COMMAND_SAVE,    /* save [DIR] */
  BBC_COMMAND_SETUP,   /* print the parameters */
  BBC_COMMAND_EXEC,    /* exec FILE */
  BBC_COMMAND_BBCLOAD, /* bbcload FILE */
  BBC_COMMAND_SHOW,    /* show model|bbc [KEYS] */
  BBC_COMMAND_HELP,    /* help [COMMAND] */
  BBC_COMMAND_CLS,
  BBC_COMMAND_QUIT, /* q, quit */
  BBC_COMMAND_KIND_COUNT
} bbc_command_kind;

typedef struct bbc_command_info {
  bbc_command_kind kind;
  const char *name, *args, *what; /* "load", "FILE [nocg] [nomip]", a line of help */
} bbc_command_info;
/* The commands of the batch language and the prompt: their count, the
 * i-th, one by name. */
size_t bbc_command_count(void);
const bbc_command_info *bbc_command_at(size_t i); /* i < bbc_command_count(), help's order */
const bbc_command_info *bbc_command_find(const char *name); /* NULL: no such command */

#define BBC_COMMAND_LINE_MAX 4096 /* characters of a line, its end excluded */
typedef struct bbc_command {
  bbc_command_kind kind;
  int line;                        /* 1-based line of the text (bbc_script_next) */
  char arg[BBC_COMMAND_LINE_MAX];  /* the first argument ("" when none) */
  char rest[BBC_COMMAND_LINE_MAX]; /* what follows it, trimmed ("" when nothing) */
  /* parsed where the command has them */
  int nomip;            /* load */
  char part[64];        /* set PART.NAME: the part ("" for every part) */
  char name[64];        /* set: the parameter as written (bbc_param_find checks it) */
  bbc_split_mode split; /* split: a mode, or BBC_SPLIT_PATTERNS with trunk_side */
  int trunk_side;       /* split trunk=P (1) or foliage=P (0): the patterns in `rest` */
  int shade_voxels;     /* shade: 0..512 */
  double shade_ambient; /* shade: 0..1, 0 when not given */
  int show_bbc;         /* show: 0 model, 1 bbc; keys in `rest` */
} bbc_command;

/* Parses one line (no line break in it). An empty or comment line gives
 * kind BBC_COMMAND_NONE. Errors (BBC_ERROR_INVALID_ARGUMENT): an unknown
 * command, a missing or malformed argument, a NUL byte, a line too long;
 * the message names the command. */
bbc_result bbc_command_parse(const char *line, size_t length, bbc_command *cmd, bbc_error *err);
/* The next command of a text (a batch file in memory, `size` bytes) from
 * `*pos` on, blank and comment lines skipped; `*pos` and `*line` (the last
 * line read, 1-based) move past it. kind BBC_COMMAND_NONE at the end. An
 * error is bbc_command_parse's, with "NAME:LINE: " first (`name`: the
 * file's name in messages). */
bbc_result bbc_script_next(const char *text, size_t size, const char *name, size_t *pos, int *line,
                           bbc_command *cmd, bbc_error *err);

#ifdef __cplusplus
}
#endif

#endif /* BBC_APP_H */
