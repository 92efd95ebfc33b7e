/* testing.h - knobs for tests and benchmarks only: deliberate faults that show the accuracy
 * metric has teeth, and the seed's mirror construction kept as a compared method. Not part
 * of the public API and never set in real use. */
#ifndef LIMEN_TESTING_H
#define LIMEN_TESTING_H

#include <cglm/cglm.h>

#include "limen.h"

/* Deliberately wrong virtual cameras, for tests that show the accuracy metric catches them. */
enum {
    LIMEN_FAULT_PORTAL_NO_TURN = 1   /* portal matrix without its 180-degree turn */
};

/* Sets the LIMEN_FAULT_* bits every later plan of the scene (and so every frame rendered
 * from it) applies; 0 turns them off. The ray tracer ignores them: it stays the truth. */
void limen__scene_set_faults(limen_scene *s, unsigned faults);

/* Seed 000's construction, kept only as a compared method: M = A^-1 F A, A = R T, T moves
 * the plane's closest point to the origin, R rotates n onto +Y about axis n x Y by
 * acos(n.Y), F = diag(1,-1,1). Done in float with the seed's steps, weaknesses included:
 * the axis n x Y vanishes at n = (0,-1,0) (and at (0,1,0)), where it is normalised as the
 * seed does (v / |v|, as glm::normalize) and the result is NaN; near those normals acos
 * loses precision. Never use it as the default. */
void limen__mirror_mat4_axis_angle(const vec4 plane, mat4 out);

/* The renderer's faults (src/gl): 1 makes every upload of a mesh or a texture fail as if
 * memory ran out; 0 turns it off. */
void limen__renderer_set_faults(limen_renderer *r, unsigned faults);

#endif
