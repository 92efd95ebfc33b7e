/* baseline.h - the two programs `make bench` measures limen against, each in an OpenGL
 * context of its own (OSMesa, llvmpipe) and owing nothing to limen's renderer:
 *   - the floor: one quad (a scene's single wall) shaded with the plain formula
 *     albedo * (ambient + (1 - ambient) * max(0, n . normalize(L - p))), nothing else;
 *   - the classic stencil recursion of tutorials and small engines: for every view the whole
 *     scene drawn with a stencil test, each portal or mirror marked with an increment, a
 *     full-screen depth clear; no culling, no scissor. It takes its views (matrices, clip
 *     planes, which surfaces recurse) from limen's public planner without culling.
 * Both draw into a framebuffer of their own; a frame ends with glFinish. */
#ifndef LIMEN_BENCH_BASELINE_H
#define LIMEN_BENCH_BASELINE_H

#include "limen.h"

typedef struct baseline baseline;

/* A context and a width x height framebuffer; NULL (with a message in err) on failure. */
baseline *baseline_create(int width, int height, char *err, size_t errsize);
void baseline_destroy(baseline *b);

/* One frame of the floor: the scene's one lit quad under its camera and first light.
 * Returns the frame's milliseconds, or a negative number with a message in err. */
double baseline_floor_frame(baseline *b, limen_scene *s, char *err, size_t errsize);

/* One frame of the classic recursion, views to depth max_depth (every surface's own limit
 * applies too). Returns milliseconds (planning included), or a negative number. */
double baseline_classic_frame(baseline *b, limen_scene *s, int max_depth, char *err,
                              size_t errsize);

/* The last frame as RGB, top row first (width * height * 3 bytes). */
void baseline_read_rgb(baseline *b, unsigned char *rgb);

/* Views the last classic frame drew. */
int baseline_views(const baseline *b);

#endif
