/* kinds.h - per-kind extents for the core's layers (the table itself is public:
 * limen_kind_get in limen.h). */
#ifndef LIMEN_CORE_KINDS_H
#define LIMEN_CORE_KINDS_H

#include "core/internal.h"

/* The kind's name for messages ("plane" for a QUAD), "node" out of range. */
const char *limen__kind_name(limen_node_kind k);
/* The local box of what node n shows: a unit shape's (limen_kind_bounds), a mesh's
 * triangles' (the origin before it has any), the origin for what shows nothing. */
void limen__node_extent(const limen__node *n, double lo[3], double hi[3]);
/* The bounding sphere of local box [lo, hi] of a shape of kind k, about the box's centre:
 * through its corners, or tighter where the kind is round (limen_kind_info.round). */
void limen__kind_sphere(limen_node_kind k, const double lo[3], const double hi[3],
                        double centre[3], double *radius);

#endif
