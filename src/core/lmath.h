/* lmath.h - the core's maths: planes, mirror and portal matrices, cameras, projections.
 * Not part of the public API (the public wrappers over float[16] live in limen.h). No GL,
 * no Lua.
 *
 * Conventions (docs/DESIGN.md): right-handed world, +Y up, cameras look down local -Z. cglm
 * matrices: column-major, column vectors, v' = M v, element (row i, column j) is m[j][i].
 * A plane is (n.x, n.y, n.z, d) with |n| = 1, n.p + d = 0 on it, n.p + d > 0 its front;
 * planes transform as covectors, C' = (M^-1)^T C. Angles are radians.
 *
 * Destination last, as in cglm; every function is safe when the destination aliases an
 * input. Functions that return a limen_status leave their output untouched on failure.
 * Internally the work is done in double and rounded to float once at the end. Nothing here
 * relies on the 16-byte alignment of vec4/mat4 (all scalar code), except the seed method
 * limen__mirror_mat4_axis_angle (core/testing.h), which calls cglm on its own aligned locals.
 */
#ifndef LIMEN_LMATH_H
#define LIMEN_LMATH_H

#include <math.h>
#include <stdbool.h>

#include <cglm/cglm.h>

#include "limen.h"

/* Relative threshold below which limen__oblique refuses the plane: the eye must be behind
 * the (normalised) clip plane by more than LIMEN__OBLIQUE_EPS times the projection's near
 * distance. See limen__oblique for why. */
#define LIMEN__OBLIQUE_EPS 1e-6

/* Sine of the angle under which two directions count as parallel: collinear points,
 * up parallel to the view direction. */
#define LIMEN__PARALLEL_EPS 1e-6

/* 1 if the n floats at v are all finite. (internal.h's limen__finite3 is the 3-vector
 * case; this one has another name so that both headers can be included together.) */
static inline bool limen__finitev(const float *v, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(v[i]))
            return false;
    return true;
}

/* ---------------------------------------------------------------- planes */

/* Plane through a, b, c; its front is where (b-a)x(c-a) points. DEGENERATE when the points
 * are repeated or collinear (sine of the angle at a below LIMEN__PARALLEL_EPS), ARG for
 * NaN/Inf. */
limen_status limen__plane_from_points(const vec3 a, const vec3 b, const vec3 c, vec4 out);
/* Plane through p with normal n (any length > 0, normalised). Zero n -> DEGENERATE. */
limen_status limen__plane_from_point_normal(const vec3 p, const vec3 n, vec4 out);
/* out = (M^-1)^T plane, renormalised so |n| = 1. Singular M or a plane that becomes
 * normal-less (M projective) -> DEGENERATE. */
limen_status limen__plane_transform(const mat4 m, const vec4 plane, vec4 out);
/* Normalises a plane so |n| = 1. Zero normal -> DEGENERATE, NaN/Inf -> ARG. */
limen_status limen__plane_normalize(const vec4 plane, vec4 out);
/* Signed distance n.p + d (plane assumed normalised). */
float limen__plane_distance(const vec4 plane, const vec3 p);

/* ---------------------------------------------------------------- mirrors and portals */

/* Reflection about plane, closed form: I - 2 n n^T, translation -2 d n (seeds 001, 004).
 * The plane is renormalised first; it must have a finite non-zero normal (a zero normal
 * gives the identity). det = -1. */
void limen__mirror_mat4(const vec4 plane, mat4 out);
/* (Seed 000's axis-angle construction, a compared method only: core/testing.h.) */
/* Reflection in the node-transform form: W * diag(1,1,-1,1) * W^-1, for a node whose local
 * z = 0 is the mirror and +Z its normal. Singular W -> DEGENERATE. */
limen_status limen__mirror_mat4_node(const mat4 world, mat4 out);
/* Portal A -> B: W_B * R_y(180 deg) * W_A^-1. Singular W_A -> DEGENERATE. */
limen_status limen__portal_mat4(const mat4 wa, const mat4 wb, mat4 out);

/* ---------------------------------------------------------------- cameras and projections */

/* Right-handed view matrix, eye looking at center. eye == center, zero up or up parallel to
 * the view direction -> DEGENERATE. */
limen_status limen__look_at(const vec3 eye, const vec3 center, const vec3 up, mat4 out);
/* Right-handed perspective looking down -Z; fovy vertical, radians, in (0, pi), aspect > 0,
 * 0 < n < f, all finite, else ARG. NO maps near/far to -1/1, ZO to 0/1, ZO_REVERSED to 1/0. */
limen_status limen__perspective(float fovy, float aspect, float n, float f,
                                limen_depth_range range, mat4 out);
/* Oblique near-plane projection (Lengyel 2005; docs/DESIGN.md's three formulas): the near plane
 * of proj becomes c_view (view space, front = what stays visible) and the far plane is
 * tilted through the far corner Q = P^-1 (sgn C.x, sgn C.y, z_far, 1), which keeps the
 * original far face inside. Refusals, out untouched:
 *   ARG         NaN/Inf anywhere, or an unknown range;
 *   DEGENERATE  zero normal; proj singular or without a near plane; the eye not strictly
 *               behind the plane: c.w > -LIMEN__OBLIQUE_EPS * near (c normalised so |n| = 1,
 *               so c.w is the eye's signed distance; near = the projection's near distance);
 *               the plane missing the frustum in front of the eye (C.Q <= 0: the factor a
 *               would be infinite or negative, the near plane a non-positive multiple of C). */
limen_status limen__oblique(const mat4 proj, const vec4 c_view, limen_depth_range range,
                            mat4 out);
/* Near and far planes of proj's frustum (Gribb-Hartmann) in view space, normalised, facing
 * the inside: NO near = row4 + row3, far = row4 - row3; ZO near = row3, far = row4 - row3;
 * ZO_REVERSED near = row4 - row3, far = row3. Either pointer may be NULL. A plane with a
 * zero normal -> DEGENERATE. */
limen_status limen__projection_planes(const mat4 proj, limen_depth_range range, vec4 near_plane,
                                      vec4 far_plane);
/* The six planes of a frustum (Gribb-Hartmann), kept side >= 0, not normalised, in the space
 * m maps from (m = a projection: eye space; projection x view: world space): out[0..3] the
 * sides left, right, bottom, top of the window x/w in [ndc[0], ndc[1]], y/w in
 * [ndc[2], ndc[3]] (NULL: [-1, 1] both ways; a smaller one narrows the frustum to a
 * scissor rectangle): row1 - x0 row4, x1 row4 - row1, row2 - y0 row4, y1 row4 - row2;
 * out[4] near and out[5] far under range, as limen__projection_planes has them. The one
 * place the planner, its spatial queries and renderers build a frustum's planes. */
void limen__frustum_planes(const double m[16], const double ndc[4], limen_depth_range range,
                           double out[6][4]);

/* ---------------------------------------------------------------- small helpers */

/* dest = inverse of m, computed in double. Singular (|det| below 1e-12 of the scale of the
 * entries to the fourth power, or a non-finite result) -> DEGENERATE, dest untouched. */
limen_status limen__mat4_inverse(const mat4 m, mat4 dest);
/* Conversions between cglm matrices and the public float[16] (column-major), which need not
 * be 16-byte aligned. */
void limen__mat4_from_array(const float a[16], mat4 dest);
void limen__mat4_to_array(const mat4 m, float a[16]);

#endif
