/* shapes.h - the unit shapes' triangles (core/shapes.c, limen_unit_geometry). */
#ifndef LIMEN_CORE_SHAPES_H
#define LIMEN_CORE_SHAPES_H

#include "limen.h"

#define LIMEN__UNIT_LEVELS 11   /* a curved unit shape's levels: tessellations */

/* Level k of a ball's or cylinder's geometry has limen__unit_segments[k] segments around:
 * 256, 192, 128, 96, 64, 48, 32, 24, 16, 12, 8 (finest first, as a mesh's levels). */
extern const int limen__unit_segments[LIMEN__UNIT_LEVELS];

/* How many levels shape's geometry has: 1, LIMEN__UNIT_LEVELS for a curved shape, 0 for
 * none. */
int limen__unit_levels(limen_unit_shape shape);

/* The level with `segments` segments, or the next finer (the finest for more than 256). */
int limen__unit_level(int segments);

#endif
