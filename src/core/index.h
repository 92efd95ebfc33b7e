/* index.h - the scene's spatial index (core/index.c): bounding volume hierarchies over the
 * world bounds of its shapes and surfaces, kept current as nodes move, come and go. */
#ifndef LIMEN_INDEX_H
#define LIMEN_INDEX_H

#include "core/bvh.h"
#include "core/internal.h"
#include "core/rtc.h"

/* Refreshes the world matrices and brings the index up to date: refits the leaves of the
 * nodes that moved, inserts and removes those of the nodes created and destroyed (rebuilds
 * when they are many against what it holds). NULL when out of memory.
 * Items are node slots of live nodes, visible or not: callers test visibility. */
limen__spatial *limen__scene_index(limen_scene *s);
/* Boxes, quads (shapes) and mirrors, portals (surfaces). */
const limen__bvh *limen__index_shapes(const limen__spatial *x);
const limen__bvh *limen__index_surfaces(const limen__spatial *x);
/* The trees as Embree holds them, current with the index (call limen__scene_index first),
 * for tracing rays; NULL where Embree does not work (walk the trees instead). */
const limen__rtc *limen__index_rtc(limen__spatial *x);
/* The live portals' slots, ascending; the live mirrors' and portals' slots, ascending. */
int limen__index_portals(const limen__spatial *x, const int **out);
int limen__index_surface_slots(const limen__spatial *x, const int **out);
/* Full builds of the trees so far (for the tests: changes go in as leaves, not builds). */
long limen__index_builds(const limen__spatial *x);
/* World box of a node as the index holds it (a little wider than its bounds). */
void limen__node_box(const limen__node *n, limen__box *b);

#endif
