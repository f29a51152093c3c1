/*
 * search.c — bbc_planes_select: step 2 at the asked epsilon, or the search
 * over epsilon scales that `maxplanes` and `minplanes` ask for (whole runs
 * of steps 1 and 2, or probes on a sample of the faces and one whole run
 * where they land).
 */
#include "grid.h"
#include "planes.h"
#include "select.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The planes the budget (maxplanes, minplanes) counts: step 2's, not those
 * the leftovers of a sampled part got (a few small billboards, on top). */
static size_t budget_count(const bbc_planeset *set) {
  return set->plane_count - set->leftover_planes;
}

/* Narrowing the growth of epsilon: the scale between lo (more than maxp
 * planes, lo_n of them) and hi (hi_n <= maxp) where the count, interpolated
 * as a power of epsilon through both ends, reaches maxp; 0 when the two are
 * already within 2 % or hi already uses 7/8 of the budget (each run builds
 * a grid: seconds a run on a model of a million triangles). */
enum { NARROW_TRIES = 3 };
static double narrow_scale(double lo, size_t lo_n, double hi, size_t hi_n, int maxp) {
  if (8 * hi_n >= 7 * (size_t)maxp || hi < lo * 1.02 || lo_n <= hi_n) return 0;
  double k = log(hi / lo) / log((double)lo_n / (double)hi_n); /* d log eps / -d log n */
  double s = lo * pow((double)lo_n / maxp, k);
  /* at least 1 % inside both ends */
  if (s < lo * 1.01) s = lo * 1.01;
  if (s > hi / 1.01) s = hi / 1.01;
  return s;
}

/* ---- the search's probe ------------------------------------------------------ */

/* The search over epsilon scales (maxplanes, minplanes) asks how many planes
 * a scale gives. A probe answers on one face in `stride` of each part (every
 * stride-th from stride / 2: the same faces at every scale), steps 1 and 2
 * at a fraction of a whole run's cost, so that the search's tries cost
 * probes and only its answer a whole run. Smaller models (a point cloud of
 * fewer than PROBE_MIN_POINTS points, a mesh of fewer than PROBE_MIN_FACES
 * faces in its largest part) are searched whole. The plane count of a
 * sample follows the whole's within about 0.7-1.3 of it (a probe's slab
 * gathers fewer, sparser faces); a whole run that lands on another side of
 * the budget than predicted calibrates the probe by the ratio of the two
 * counts and searches again. Since the search steps along the count's
 * slope (below), probes pay from a few thousand points or faces; below the
 * two bounds they mispredict more often than they save (the figures behind
 * both: docs/design.md, "The epsilon search's probes"). */
enum {
  PROBE_MIN_POINTS = 4096,
  PROBE_MIN_FACES = 16384,
  PROBE_FACES = 8192,
  PROBE_MAX_STRIDE = 16,
  PROBE_CACHE = 48
};

typedef struct probe {
  int stride;
  dual_face *faces[2];
  size_t nf[2];
  double total[2];
  double ratio; /* calibration: a whole run's count over the probe's */
  int cached;
  double scales[PROBE_CACHE];
  size_t counts[PROBE_CACHE]; /* the probe's own counts, before the ratio */
  int runs;
  double seconds;
} probe;

static void probe_free(probe *pr) {
  for (int k = 0; k < 2; k++) free(pr->faces[k]);
  memset(pr, 0, sizeof *pr);
}

/* 1 when the grid's parts are large enough to be probed (and the probe's
 * faces could be had). */
static int probe_init(const bbc_grid *g, probe *pr) {
  memset(pr, 0, sizeof *pr);
  size_t most = 0;
  int points = 0, sampled = 0;
  for (size_t pi = 0; pi < g->part_count; pi++) {
    if (g->part[pi].nf > most) most = g->part[pi].nf;
    points |= g->part[pi].nf && g->part[pi].faces[0].point;
    sampled |= g->part[pi].stride > 1;
  }
  /* a sampled model's sample (8k-16k points or faces at the defaults), a
   * whole cloud from PROBE_MIN_POINTS, a whole mesh from PROBE_MIN_FACES */
  if (most < (points || sampled ? PROBE_MIN_POINTS : PROBE_MIN_FACES)) return 0;
  size_t stride = most / PROBE_FACES;
  if (stride < 4) stride = 4; /* a probe of 1/4 a run at most */
  pr->stride = stride > PROBE_MAX_STRIDE ? PROBE_MAX_STRIDE : (int)stride;
  /* A probe of a mesh finds fewer planes than a whole run (1 face in 4
   * of 5 meshes' samples, 250k-1.1M triangles: 0.71-1.0 of the count,
   * median 0.81); of a cloud about as many (6 scans: 0.76-1.13, median
   * 0.97). The first whole run that disagrees calibrates it. */
  pr->ratio = points ? 1.0 : 1.2;
  for (size_t pi = 0; pi < g->part_count; pi++) {
    const grid_part *gp = &g->part[pi];
    size_t st = (size_t)pr->stride, first = st / 2;
    if (gp->nf <= first) continue;
    size_t n = (gp->nf - first + st - 1) / st;
    pr->faces[pi] = malloc(n * sizeof *pr->faces[pi]);
    if (!pr->faces[pi]) {
      probe_free(pr);
      return 0;
    }
    double total = 0;
    for (size_t i = 0; i < n; i++) {
      pr->faces[pi][i] = gp->faces[first + i * st];
      total += pr->faces[pi][i].area;
    }
    pr->nf[pi] = n;
    pr->total[pi] = total;
  }
  return 1;
}

/* A probe's count `raw` as a whole run's, by the calibration ratio. */
static size_t probe_calibrated(const probe *pr, size_t raw) {
  return (size_t)floor((double)raw * pr->ratio + 0.5);
}

/* The probe's plane count at `scale` (its own, before the ratio). */
static bbc_result probe_count(const bbc_grid *g, const bbc_planes_options *o, probe *pr,
                              double scale, size_t *count, bbc_error *err) {
  for (int k = 0; k < pr->cached; k++)
    if (pr->scales[k] == scale) {
      *count = pr->counts[k];
      return BBC_OK;
    }
  double t0 = bbc__now_s();
  size_t n = 0;
  for (size_t pi = 0; pi < g->part_count; pi++) {
    const grid_part *gp = &g->part[pi];
    if (!pr->nf[pi]) continue;
    const bbc_params *p = gp->params;
    /* step 2's parameters as they are now; `breaknum` counts faces */
    bbc_params sp = *bbc__part_params(o, gp->name);
    sp.break_num = bbc__sampled_break_num(gp, sp.break_num, pr->stride);
    double eps = scale * p->epsilon_pct / 100.0 * g->mesh_radius;
    bbc_label lab;
    bbc_callbacks cb;
    bbc_callbacks_label(&o->callbacks, &lab, &cb, "probe (1 face in %d) at epsilon %.3g %%",
                        pr->stride, scale * p->epsilon_pct);
    dual_grid dg;
    if (bbc__dual_grid_init(&dg, p->res_deg, eps, gp->radius, p->up_axis, pr->total[pi],
                            p->threads) != BBC_OK)
      return bbc__fail(err, BBC_ERROR_OUT_OF_MEMORY, "step 1: out of memory for the grid");
    select_result sr;
    bbc_result r = bbc__dual_grid_accumulate(&dg, pr->faces[pi], NULL, pr->nf[pi], +1, NULL);
    if (r == BBC_OK)
      r = bbc__select_planes(pr->faces[pi], pr->nf[pi], &dg, &sp, eps, gp->radius, &cb, &sr);
    bbc__dual_grid_free(&dg);
    if (r == BBC_ERROR_CANCELLED) return bbc__fail(err, r, "plane selection: cancelled");
    if (r != BBC_OK) return bbc__fail(err, r, "plane selection failed: %s", bbc_result_string(r));
    n += sr.plane_count;
    bbc__select_result_free(&sr);
  }
  pr->runs++;
  pr->seconds += bbc__now_s() - t0;
  if (pr->cached < PROBE_CACHE) {
    pr->scales[pr->cached] = scale;
    pr->counts[pr->cached++] = n;
  }
  *count = n;
  return BBC_OK;
}

/* ---- the search over epsilon scales ---------------------------------------- */

/* bbc_planes_select's search over epsilon scales for maxplanes and
 * minplanes: whole runs, or (pr) the probe's predictions. */
typedef struct scale_search {
  const bbc_planes_options *o;
  probe *pr; /* predicting: no log lines, sets hold a count only */
  int maxp, minp;
  double scale, retry;
  int grown;         /* epsilon grew: too many planes at the asked one */
  bbc_planeset best; /* shrinking: the last result within maxplanes */
  int have_best, narrow;
  /* Growing: the largest scale known to give more than maxplanes and its
   * count, to narrow the step between it and the first scale within. */
  double over_scale;
  size_t over_n;
  /* The try before this one and this one: the slope of the plane count
   * over epsilon between them aims shrinking. */
  double prev_scale, cur_scale;
  size_t prev_n, cur_n;
  /* Probing down: the largest scale known to give more than maxplanes. */
  double past_scale;
  size_t past_n;
} scale_search;

/* What narrowing aims at: maxplanes for whole runs, 7/8 of it for a probe
 * (whose count strays: a whole run at a probe's 31 of 32 planes gave 33). */
static int narrow_aim(const scale_search *s) {
  return s->pr ? s->maxp * 7 / 8 : s->maxp;
}

/* A narrowing step to `next` after n planes at this scale (`side`: more
 * than or within maxplanes), logged for whole runs. */
static void narrow_step(scale_search *s, size_t n, const char *side, double next, double t0) {
  s->narrow++;
  if (!s->pr)
    bbc__log(&s->o->callbacks, BBC_LOG_INFO, "%zu planes at epsilon %.3g %%, %s %d: trying %.3g %%",
             n, s->o->params.epsilon_pct * s->scale, side, s->maxp,
             s->o->params.epsilon_pct * next);
  s->retry += bbc__now_s() - t0;
  s->scale = next;
}

/* Narrowing overshot: the result (n planes) at this scale is the new lower
 * end; returns 1 when a scale between it and the best is to be tried. */
static int narrow_overshot(scale_search *s, bbc_planeset *set, size_t n, double t0) {
  int maxp = s->maxp;
  if (!(s->grown && maxp > 0 && n > (size_t)maxp && s->have_best && s->narrow < NARROW_TRIES))
    return 0;
  s->over_scale = s->scale;
  s->over_n = n;
  double next = narrow_scale(s->over_scale, s->over_n, s->best.epsilon_scale,
                             budget_count(&s->best), narrow_aim(s));
  if (!(next > 0)) return 0;
  bbc_planeset_free(set);
  memset(set, 0, sizeof *set);
  narrow_step(s, n, "more than maxplanes", next, t0);
  return 1;
}

/* Growing by at least 1.25 may land well below maxplanes: a scale between
 * the last one over it and this one, while within, keeps more fidelity
 * (more planes, still within maxplanes). Returns 1 when such a scale is to
 * be tried (this result kept as the best). */
static int narrow_within(scale_search *s, bbc_planeset *set, size_t n, double t0) {
  int maxp = s->maxp;
  if (!(s->grown && maxp > 0 && n <= (size_t)maxp && s->over_n && s->narrow < NARROW_TRIES))
    return 0;
  double next = narrow_scale(s->over_scale, s->over_n, s->scale, n, narrow_aim(s));
  if (!(next > 0)) return 0;
  s->best = *set;
  s->have_best = 1;
  memset(set, 0, sizeof *set);
  narrow_step(s, n, "within maxplanes", next, t0);
  return 1;
}
/* Shrinking's aim: minplanes for whole runs, a tenth above it for a
 * probe (whose count strays more), within the budget's middle. */
static double shrink_target(const scale_search *s) {
  if (!s->pr) return s->minp;
  double t = 1.1 * s->minp;
  return s->maxp > 0 && t > 0.5 * (s->minp + s->maxp) ? 0.5 * (s->minp + s->maxp) : t;
}

/* The exponent b of count ~ epsilon^-b for shrinking. A probe's: between
 * its last two tries (the count rising as epsilon fell), within [0.25, 3];
 * 1.0 before there are two and 0.25 where the count did not rise (a flat
 * count: on to a much smaller epsilon). Whole runs assume 1.5 (planes fall
 * roughly with epsilon^1.5) and step by at most 2: a measured slope's
 * longer steps pass maxplanes where the count jumps, and a whole run past
 * it costs the fidelity of the step back. */
static double shrink_slope(const scale_search *s) {
  if (!s->pr) return 1.5;
  if (!(s->prev_scale > s->cur_scale * 1.001) || !s->prev_n) return 1.0;
  if (s->cur_n <= s->prev_n) return 0.25;
  double b = log((double)s->cur_n / (double)s->prev_n) / log(s->prev_scale / s->cur_scale);
  return b < 0.25 ? 0.25 : b > 3 ? 3 : b;
}

/* A probe's scale between `below` (nb planes, fewer than minplanes) and a
 * smaller `over` (no planes, more than maxplanes) where the count's slope
 * between the two reaches minplanes, at least 1 % inside both. */
static double probe_between(double below, size_t nb, double over, size_t no, int minp) {
  double lo_n = (double)(nb ? nb : 1);
  double b = log((double)no / lo_n) / log(below / over);
  double next = below * pow(lo_n / minp, 1.0 / b);
  return fmin(below / 1.01, fmax(over * 1.01, next));
}

/* The factor for the next scale after n planes at attempt `attempt`, 0
 * when the result stands. */
static double next_factor(scale_search *s, bbc_planeset *set, size_t n, int attempt) {
  const bbc_planes_options *o = s->o;
  int maxp = s->maxp, minp = s->minp;
  double f = 0, scale = s->scale;
  if (maxp > 0 && n > (size_t)maxp && attempt < 12 &&
      o->params.epsilon_pct * scale < 99) { /* epsilon's own range ends at 99 % */
    /* Too many planes: grow epsilon by a factor that follows the excess
     * (planes fall roughly with epsilon^1.5), between 1.25 and 2. */
    f = pow((double)n / maxp, 1.0 / 1.5);
    f = f < 1.25 ? 1.25 : f > 2 ? 2 : f;
    s->grown = 1;
    s->over_scale = scale;
    s->over_n = n;
  } else if (minp > 0 && n < (size_t)minp && !s->grown && scale > 0.2 + 1e-9 &&
             (maxp <= 0 || minp <= maxp)) {
    /* Few planes: a smaller epsilon buys fidelity within the budget, down
     * to 1/5 of the asked epsilon, aimed at minplanes (a probe a tenth
     * above) along the count's slope over epsilon (count ~ epsilon^-b), by
     * 1.25 to 2 (a probe 1.1 to 3). */
    double step = pow(shrink_target(s) / (double)(n ? n : 1), 1.0 / shrink_slope(s));
    f = s->pr ? 1.0 / fmin(3.0, fmax(1.1, step)) : 1.0 / fmin(2.0, fmax(1.25, step));
    if (s->pr && s->past_scale > 0 && s->past_scale < scale) {
      /* between this scale and one known past maxplanes, where the slope
       * between the two reaches minplanes */
      if (s->narrow >= NARROW_TRIES) return 0;
      s->narrow++;
      f = probe_between(scale, n, s->past_scale, s->past_n, minp) / scale;
    }
    if (scale * f < 0.2) f = 0.2 / scale;
    s->best = *set;
    s->have_best = 1;
  }
  return f;
}

/* Shrinking's probe search landed within the budget (n planes) on a flat
 * count: the slope between its last two tries under 0.5, where the count
 * rises with epsilon^-1 to ^-1.5 on most models. There the first scale
 * reaching minplanes is where the count's noise puts it (a ball scan's
 * count: 23, 20, 21, 23, 23, 24 planes at 6, 4, 3, 2, 1.5, 1.2 %; the
 * search stopped at 5.23 % for 25, billboards across the ball's faces,
 * IoU 0.949 against 0.981 at 1.26 %). A probe at the floor (1/5 of the
 * asked epsilon) whose count stays within maxplanes and within a quarter
 * above n says the count is flat all the way: the floor buys the fidelity
 * for at most a quarter more planes. Returns 1 when set now holds the
 * floor's prediction (or *r an error). */
static int flat_to_floor(scale_search *s, bbc_grid *grid, bbc_planeset *set, size_t n,
                         bbc_result *r, bbc_error *err) {
  if (s->grown || !(s->scale < 1) || !(s->scale > 0.2 + 1e-9) || s->minp <= 0 ||
      n < (size_t)s->minp || (s->maxp > 0 && n > (size_t)s->maxp) || shrink_slope(s) >= 0.5)
    return 0;
  size_t raw;
  *r = probe_count(grid, s->o, s->pr, 0.2, &raw, err);
  if (*r != BBC_OK) return 1;
  size_t at_floor = probe_calibrated(s->pr, raw);
  if ((s->maxp > 0 && at_floor > (size_t)s->maxp) || 4 * at_floor > 5 * n) return 0;
  memset(set, 0, sizeof *set);
  set->epsilon_scale = 0.2;
  set->plane_count = at_floor;
  return 1;
}

/* One try of the search: a whole run at `scale` into set, or the probe's
 * prediction (set->plane_count only). */
static bbc_result search_try(bbc_grid *grid, const bbc_planes_options *o, probe *pr, double scale,
                             int attempt, bbc_planeset *set, bbc_error *err) {
  if (!pr) return bbc__select_once(grid, o, scale, attempt, set, err);
  memset(set, 0, sizeof *set);
  size_t raw;
  bbc_result r = probe_count(grid, o, pr, scale, &raw, err);
  set->plane_count = probe_calibrated(pr, raw);
  return r;
}

/* The search from `scale`: tries until the plane count stands (the thesis's
 * maxplanes and the minplanes extension); `first`, when given, is the
 * result of the first try already made (whole runs only; taken over).
 * set->attempts counts the tries, from attempt0 + 1. */
static bbc_result search(bbc_grid *grid, const bbc_planes_options *o, probe *pr, double scale,
                         bbc_planeset *first, int attempt0, bbc_planeset *set, bbc_error *err) {
  scale_search s;
  memset(&s, 0, sizeof s);
  s.o = o;
  s.pr = pr;
  s.scale = scale;
  s.maxp = o->params.max_planes;
  s.minp = o->params.min_planes;
  for (int attempt = attempt0 + 1;; attempt++) {
    double t0 = bbc__now_s();
    bbc_result r = BBC_OK;
    if (first) {
      *set = *first;
      memset(first, 0, sizeof *first);
      first = NULL;
    } else {
      r = search_try(grid, o, pr, s.scale, attempt, set, err);
    }
    if (r != BBC_OK) {
      if (s.have_best) bbc_planeset_free(&s.best);
      return r;
    }
    set->epsilon_scale = s.scale;
    set->attempts = attempt;
    set->retry_s = s.retry;
    size_t n = budget_count(set);
    s.prev_scale = s.cur_scale;
    s.prev_n = s.cur_n;
    s.cur_scale = s.scale;
    s.cur_n = n;
    if (narrow_overshot(&s, set, n, t0)) continue;
    if (pr && !s.grown && s.have_best && s.maxp > 0 && n > (size_t)s.maxp &&
        s.narrow < NARROW_TRIES && budget_count(&s.best) < n) {
      /* A probe shrinking past maxplanes: a scale between it and the last
       * one below minplanes where the count's slope between the two reaches
       * minplanes (the count curves up as epsilon falls: the slope's aim
       * lands above it). */
      double sb = s.best.epsilon_scale;
      double next = probe_between(sb, budget_count(&s.best), s.scale, n, s.minp);
      if (next > s.scale && next < sb) {
        s.narrow++;
        s.past_scale = s.scale;
        s.past_n = n;
        memset(set, 0, sizeof *set);
        s.retry += bbc__now_s() - t0;
        s.scale = next;
        continue;
      }
    }
    if (s.have_best && s.maxp > 0 && n > (size_t)s.maxp) {
      /* Shrinking (or narrowing) went one step too far: the previous result
       * it is. */
      s.retry += bbc__now_s() - t0;
      bbc_planeset_free(set);
      *set = s.best;
      set->attempts = attempt;
      set->retry_s = s.retry;
      if (!pr) bbc__show_level(grid, set->epsilon_scale);
      return BBC_OK;
    }
    if (s.have_best) bbc_planeset_free(&s.best);
    s.have_best = 0;
    if (narrow_within(&s, set, n, t0)) continue;
    double f = next_factor(&s, set, n, attempt);
    if (pr && f > 0 && f < 1 && s.scale * f <= 0.2 + 1e-9) {
      /* Probing on down to the floor (1/5 of the asked epsilon), where the
       * count stands whatever it is within maxplanes: a count the slope
       * (at least 0.75) predicts well within maxplanes needs no probe
       * there; the whole run checks it. */
      double at_floor = (double)n * pow(s.scale / 0.2, fmax(shrink_slope(&s), 0.75));
      if (s.maxp <= 0 || 1.3 * at_floor <= s.maxp) {
        if (s.have_best) bbc_planeset_free(&s.best);
        memset(set, 0, sizeof *set);
        set->epsilon_scale = s.scale * f;
        set->plane_count = (size_t)ceil(at_floor);
        set->attempts = attempt;
        set->retry_s = s.retry + bbc__now_s() - t0;
        return BBC_OK;
      }
    }
    if (f == 0 && pr && flat_to_floor(&s, grid, set, n, &r, err)) {
      if (r != BBC_OK) return r;
      set->attempts = ++attempt;
      set->retry_s = s.retry + bbc__now_s() - t0;
      return BBC_OK;
    }
    if (f == 0) {
      if (s.maxp > 0 && n > (size_t)s.maxp && !pr)
        bbc__log(&o->callbacks, BBC_LOG_WARNING,
                 "%zu planes after %d tries (maxplanes %d): keeping them", n, attempt, s.maxp);
      if (!pr) bbc__show_level(grid, set->epsilon_scale);
      return BBC_OK;
    }
    if (!pr)
      bbc__log(&o->callbacks, BBC_LOG_INFO, "%zu planes at epsilon %.3g %%, %s %d: trying %.3g %%",
               n, o->params.epsilon_pct * s.scale,
               f > 1 ? "more than maxplanes" : "fewer than minplanes", f > 1 ? s.maxp : s.minp,
               o->params.epsilon_pct * s.scale * f);
    s.scale *= f;
    if (!s.have_best) bbc_planeset_free(set);
    memset(set, 0, sizeof *set);
    s.retry += bbc__now_s() - t0;
  }
}

/* Where n planes stand against the budget: -1 fewer than minplanes (while
 * epsilon may still fall), 1 more than maxplanes, 0 within. */
static int budget_side(const bbc_planes_options *o, double scale, size_t n) {
  int maxp = o->params.max_planes, minp = o->params.min_planes;
  if (maxp > 0 && n > (size_t)maxp) return 1;
  if (minp > 0 && n < (size_t)minp && (maxp <= 0 || minp <= maxp) && scale > 0.2 + 1e-9) return -1;
  return 0;
}

/* After a calibration: the smallest epsilon scale the probe has tried
 * (but `not`) whose count, calibrated, is within the budget, as the next
 * guess; 0 when there is none (the search starts again). */
static int cached_guess(const bbc_planes_options *o, const probe *pr, double not,
                        bbc_planeset *guess) {
  int found = 0;
  for (int k = 0; k < pr->cached; k++) {
    size_t n = probe_calibrated(pr, pr->counts[k]);
    double sc = pr->scales[k];
    if (sc == not || budget_side(o, sc, n) != 0 || (found && sc >= guess->epsilon_scale)) continue;
    memset(guess, 0, sizeof *guess);
    guess->epsilon_scale = sc;
    guess->plane_count = n;
    found = 1;
  }
  return found;
}

bbc_result bbc_planes_select(bbc_grid *grid, const bbc_planes_options *o, bbc_planeset *set,
                             bbc_error *err) {
  assert(grid && set);
  memset(set, 0, sizeof *set);
  const char *which = NULL;
  if (bbc_planes_options_stale_step(&grid->options, o, &which) == 1)
    return bbc__fail(err, BBC_ERROR_INVALID_ARGUMENT,
                     "%s changed since step 1: the grid must be built again (step 1)", which);
  int maxp = o->params.max_planes, minp = o->params.min_planes;
  if (minp > 0 && maxp > 0 && minp > maxp)
    bbc__log(&o->callbacks, BBC_LOG_WARNING, "minplanes %d is above maxplanes %d: ignored", minp,
             maxp);
  probe pr;
  if ((maxp <= 0 && minp <= 0) || !probe_init(grid, &pr))
    return search(grid, o, NULL, 1, NULL, 0, set, err);
  /* The search on the probe: where it lands, one whole run. */
  bbc_planeset guess, got;
  double retry = 0;
  int attempts = 0;
  bbc_result r = search(grid, o, &pr, 1, NULL, 0, &guess, err);
  /* The asked epsilon as any other: a whole run there outside the budget
   * where the probe found it within calibrates the probe (a ball scan whose
   * count stays at 20-23 down to 1.5 % searched on by whole runs took 8). */
  for (int round = 0; r == BBC_OK; round++) {
    double scale = guess.epsilon_scale;
    size_t predicted = guess.plane_count;
    double t0 = bbc__now_s();
    r = bbc__select_once(grid, o, scale, ++attempts, &got, err);
    if (r != BBC_OK) break;
    got.epsilon_scale = scale;
    size_t n = budget_count(&got);
    int side = budget_side(o, scale, n);
    if (side == 0 || side == budget_side(o, scale, predicted)) {
      bbc__log(&o->callbacks, BBC_LOG_INFO,
               "epsilon %.3g %%: %zu planes (%zu predicted by %d probes of 1 face in %d)",
               o->params.epsilon_pct * scale, n, predicted, pr.runs, pr.stride);
      *set = got;
      set->attempts = attempts;
      bbc__show_level(grid, scale);
      break;
    }
    size_t raw = 0;
    probe_count(grid, o, &pr, scale, &raw, NULL); /* cached, but at a floor it skipped */
    bbc__log(&o->callbacks, BBC_LOG_INFO, "epsilon %.3g %%: %zu planes where %zu were predicted",
             o->params.epsilon_pct * scale, n, predicted);
    double run_s = bbc__now_s() - t0;
    if (round == 0 && raw > 0) {
      pr.ratio = (double)n / (double)raw;
      if (!cached_guess(o, &pr, scale, &guess)) r = search(grid, o, &pr, 1, NULL, 0, &guess, err);
    }
    if (r == BBC_OK && (round > 0 || raw == 0 || guess.epsilon_scale == scale)) {
      /* The search goes on with whole runs from this result. */
      r = search(grid, o, NULL, scale, &got, attempts - 1, set, err);
      if (r == BBC_OK && set->epsilon_scale != scale) retry += run_s;
      break;
    }
    retry += run_s;
    bbc_planeset_free(&got);
  }
  if (r == BBC_OK) {
    set->retry_s += retry + pr.seconds;
    set->probe_runs = pr.runs;
    set->probe_stride = pr.stride;
    set->probe_s = pr.seconds;
  }
  probe_free(&pr);
  return r;
}
