/* run.h — the forest's frame loop (window or headless). */
#ifndef FOREST_RUN_H
#define FOREST_RUN_H

#include "scene.h"

typedef struct run_options {
  int headless;      /* EGL without a display */
  int width, height; /* framebuffer or window size */
  int has_camera;    /* --camera given */
  bbc_forest_camera camera;
  const char *path;       /* --path: camera positions, interpolated over the frames */
  int frames;             /* --frames (0 = 1, or 30 per path position) */
  const char *screenshot; /* --screenshot PNG: the last frame */
  int bench;              /* --bench: timing line at the end */
  const char *keys;       /* --keys: a scripted key sequence */
  int stats;              /* --stats: the F10 overlay from the start */
  int progress;           /* messages while loading and drawing (a terminal) */
  int print_camera;       /* --print-camera: the final camera on stdout */
  int coverage;           /* --coverage: per frame, the pixels the objects cover */
  int naive;              /* --naive: draw the thesis's way (to measure against) */
  int uncompressed;       /* --uncompressed: RGBA8 textures where BC1 would do */
  int gpu_cull;           /* --gpu-cull: culling and levels of detail in a compute shader */
  int reference;          /* --reference: no occlusion (every tree at its own level) */
  int has_sun;            /* --sun given (else the map's light) */
  double sun_azimuth, sun_elevation; /* --sun AZ,EL (degrees) */
  double time;                       /* --time: the wind's clock at the first frame (s) */
  double load_s;                     /* how long loading took (for --bench) */
  double start_s; /* CLOCK_MONOTONIC when loading began (for --bench's ready_s) */
} run_options;

/* Draws `s` as `o` says; the exit status. */
int run(scene *s, const run_options *o, FILE *log);

#endif
