/* contact.h - the exact geometry of collisions (core/contact.c): convex pieces (polygons,
 * balls, capped cylinders), bodies (a point or a segment with a radius) moving along a
 * straight path, their distances and first contacts. core/collide.c builds the pieces from
 * the scene and its portals. Not part of the public API. */
#ifndef LIMEN_CONTACT_H
#define LIMEN_CONTACT_H

#include <math.h>
#include <stdbool.h>
#include <string.h>

#define LIMEN__PIECE_MAXV 40    /* a box face cut to a sweep's box and by four portals' holes
                                 * stays below */

enum { LIMEN__PIECE_POLY, LIMEN__PIECE_BALL, LIMEN__PIECE_CYL };

typedef struct limen__piece {
    int kind, node, nv;
    double v[LIMEN__PIECE_MAXV][3];          /* polygon, convex, in order */
    double n[3];                /* polygon: its normal (Newell's, not normalised; 0: no area) */
    double c[3], axis[3];       /* ball: centre; cylinder: base centre and unit axis */
    double r, h;                /* radius; cylinder height */
} limen__piece;

/* A body: the segment a-b (a point for a sphere) with radius r, at a + t v, b + t v. Its
 * reference point (which passes portals, and whose side of a portal opens its hole) is the
 * midpoint, or a for a node that slides (its origin, as limen_node_move carries it). */
typedef struct limen__body {
    double a[3], b[3], v[3], r;
    bool capsule, ref_a;
} limen__body;

/* Newell's normal of a polygon (not normalised; zero when it has no area). */
void limen__piece_normal(const limen__piece *pc, double n[3]);
/* Distance from the body at t to a piece (signed inside a ball), with the closest points:
 * pb on the body, pk on the piece. */
double limen__body_dist(const limen__body *bd, double t, const limen__piece *pc, double pb[3],
                        double pk[3]);
/* First t in [t0, t1] where the body touches the piece (distance = radius), by Newton's
 * method from t0: on a convex distance it approaches the first root from below. A body
 * already touching at t0 counts only if it is moving further in. */
bool limen__piece_contact(const limen__body *bd, const limen__piece *pc, double t0, double t1,
                          double *t_out);

/* ------------------------------------------------------------------ vectors */

static inline double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline void sub3(const double a[3], const double b[3], double o[3])
{
    o[0] = a[0] - b[0];
    o[1] = a[1] - b[1];
    o[2] = a[2] - b[2];
}

static inline void mad3(const double a[3], double k, const double b[3], double o[3])
{
    o[0] = a[0] + k * b[0];
    o[1] = a[1] + k * b[1];
    o[2] = a[2] + k * b[2];
}

static inline void cross3(const double a[3], const double b[3], double o[3])
{
    double r[3] = { a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                    a[0] * b[1] - a[1] * b[0] };
    memcpy(o, r, sizeof r);
}

static inline double len3(const double a[3])
{
    return sqrt(dot3(a, a));
}

static inline double dist3(const double a[3], const double b[3])
{
    double d[3];
    sub3(a, b, d);
    return len3(d);
}

static inline void vec_d(const double m[16], const double v[3], double o[3])
{
    double r[3];
    for (int i = 0; i < 3; i++)
        r[i] = m[i] * v[0] + m[4 + i] * v[1] + m[8 + i] * v[2];
    memcpy(o, r, sizeof r);
}

static inline double clamp01(double x)
{
    return x < 0 ? 0 : x > 1 ? 1 : x;
}

#endif
