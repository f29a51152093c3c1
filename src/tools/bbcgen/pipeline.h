/* pipeline.h — what the tool says and checks around the application layer's session
 * (which runs the steps and writes the outputs: bbc_session_*). Shared by
 * `bbcgen MODEL -o OUT`, the batch commands, the prompt and the viewer. */
#ifndef BBCGEN_PIPELINE_H
#define BBCGEN_PIPELINE_H

#include "cli.h"

/* Loads the model into the session and runs steps 1 to 3 for each epsilon
 * (percent; NULL / 0 = the parameters' epsilon), printing a line per level.
 * Returns an exit code. */
int session_run(const cli *c, bbc_session *s, const char *model, const bbc_lod_level *levels,
                size_t count);
/* The info line of the session's planes (no cloud yet: `kept` 1 = step 1
 * was kept) or of level k's cloud (`kept` 1 = steps 1+2 were kept). */
void session_info(const cli *c, const bbc_session *s, size_t k, int kept);
/* Writes the session's levels to OUT (bbc_session_write) and says what. */
int session_write(const cli *c, bbc_session *s, const char *out);
/* Thesis Appendix A `save [dir]` (bbc_session_save) and what it wrote. */
int session_save(const cli *c, bbc_session *s, const char *user_dir);

/* `show model` and `show bbc` (cmd_view.c): a window with the viewer over
 * the session's model, grid, planes and `cloud` (may be NULL; bbcload's or
 * the session's); `keys` (may be NULL) script it: key names and
 * shot:FILE.png, the window closing after them. */
int show_window(const cli *c, const bbc_session *session, const bbc_cloud *cloud, int bbc,
                const char *keys);
/* The debug levels (parameter debug >= 1): from begin to end, step 2 shows
 * its picks (1), greedy steps (2) and clusters (3) in a window over `model`
 * (sets o->callbacks.debug). */
void debug_views_begin(const cli *c, const bbc_mesh *model, bbc_planes_options *o);
void debug_views_end(void);

#endif
