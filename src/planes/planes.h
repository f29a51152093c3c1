/*
 * planes.h — what steps 1 and 2 give the layers above them besides the
 * public API (src/planes): the options a grid was built with, copied.
 * Not installed.
 */
#ifndef BBC_PLANES_H
#define BBC_PLANES_H

#include "base.h"

/* A copy of planes options whose split pattern texts live in `text` (the
 * caller's may change); callbacks cleared. */
void bbc__planes_options_copy(bbc_planes_options *dst, char text[3][4096],
                              const bbc_planes_options *src);
/* The options a grid's step 1 ran with. */
const bbc_planes_options *bbc__grid_options(const bbc_grid *grid);

#endif /* BBC_PLANES_H */
