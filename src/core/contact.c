/* contact.c - the exact geometry of collisions: closest points between a moving point or
 * segment and a convex piece (a polygon, a ball, a capped cylinder), and the first contact
 * along a straight path. The distance from a body carried along a line to a convex piece is
 * a convex function of the path parameter, so Newton's method started before the contact
 * never passes it: the first contact is found to rounding, at any speed, with no steps to
 * tunnel between. */
#include "core/contact.h"

/* ------------------------------------------------------------------ closest points */

static void closest_on_segment(const double p[3], const double a[3], const double b[3],
                               double q[3])
{
    double ab[3], ap[3];
    sub3(b, a, ab);
    sub3(p, a, ap);
    double l2 = dot3(ab, ab);
    double t = l2 > 0 ? clamp01(dot3(ap, ab) / l2) : 0;
    mad3(a, t, ab, q);
}

/* Closest points of segments p0-p1 and q0-q1 (Ericson, Real-Time Collision Detection 5.1.9). */
static void closest_segments(const double p0[3], const double p1[3], const double q0[3],
                             const double q1[3], double cp[3], double cq[3])
{
    double d1[3], d2[3], r[3];
    sub3(p1, p0, d1);
    sub3(q1, q0, d2);
    sub3(p0, q0, r);
    double a = dot3(d1, d1), e = dot3(d2, d2), f = dot3(d2, r), s, t;
    if (a <= 1e-300 && e <= 1e-300) {
        s = t = 0;
    } else if (a <= 1e-300) {
        s = 0;
        t = clamp01(f / e);
    } else {
        double c = dot3(d1, r);
        if (e <= 1e-300) {
            t = 0;
            s = clamp01(-c / a);
        } else {
            double b = dot3(d1, d2), den = a * e - b * b;
            s = den > 1e-300 ? clamp01((b * f - c * e) / den) : 0;
            t = (b * s + f) / e;
            if (t < 0) {
                t = 0;
                s = clamp01(-c / a);
            } else if (t > 1) {
                t = 1;
                s = clamp01((b - c) / a);
            }
        }
    }
    mad3(p0, s, d1, cp);
    mad3(q0, t, d2, cq);
}

/* Newell's normal of a polygon (not normalised; zero when it has no area). */
void limen__piece_normal(const limen__piece *pc, double n[3])
{
    n[0] = n[1] = n[2] = 0;
    for (int i = 0; i < pc->nv; i++) {
        const double *a = pc->v[i], *b = pc->v[(i + 1) % pc->nv];
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
}

/* Whether p (on the polygon's plane) lies inside it. */
static bool poly_inside(const limen__piece *pc, const double n[3], const double p[3])
{
    for (int i = 0; i < pc->nv; i++) {
        const double *a = pc->v[i], *b = pc->v[(i + 1) % pc->nv];
        double e[3], ap[3], c[3];
        sub3(b, a, e);
        sub3(p, a, ap);
        cross3(e, ap, c);
        if (dot3(c, n) < 0)
            return false;
    }
    return true;
}

static double point_poly(const double p[3], const limen__piece *pc, double q[3])
{
    const double *n = pc->n;
    double ln = len3(n);
    if (ln > 1e-300) {
        double u[3] = { n[0] / ln, n[1] / ln, n[2] / ln }, ap[3], f[3];
        sub3(p, pc->v[0], ap);
        mad3(p, -dot3(ap, u), u, f);
        if (poly_inside(pc, n, f)) {
            memcpy(q, f, sizeof f);
            return dist3(p, q);
        }
    }
    double best = INFINITY;
    for (int i = 0; i < pc->nv; i++) {
        double c[3];
        closest_on_segment(p, pc->v[i], pc->v[(i + 1) % pc->nv], c);
        double d = dist3(p, c);
        if (d < best) {
            best = d;
            memcpy(q, c, sizeof c);
        }
    }
    return best;
}

static double seg_poly(const double a[3], const double b[3], const limen__piece *pc, double pa[3],
                       double pq[3])
{
    const double *n = pc->n;
    double ln = len3(n);
    if (ln > 1e-300) {
        double da = dot3(n, a) - dot3(n, pc->v[0]), db = dot3(n, b) - dot3(n, pc->v[0]);
        if ((da <= 0 && db >= 0) || (da >= 0 && db <= 0)) {
            if (da != db) {
                double t = da / (da - db), x[3], ab[3];
                sub3(b, a, ab);
                mad3(a, t, ab, x);
                if (poly_inside(pc, n, x)) {
                    memcpy(pa, x, sizeof x);
                    memcpy(pq, x, sizeof x);
                    return 0;
                }
            }
        }
    }
    double best = INFINITY, c[3], cq[3];
    const double *ends[2] = { a, b };
    for (int k = 0; k < 2; k++) {
        double d = point_poly(ends[k], pc, c);
        if (d < best) {
            best = d;
            memcpy(pa, ends[k], sizeof c);
            memcpy(pq, c, sizeof c);
        }
    }
    for (int i = 0; i < pc->nv; i++) {
        closest_segments(a, b, pc->v[i], pc->v[(i + 1) % pc->nv], c, cq);
        double d = dist3(c, cq);
        if (d < best) {
            best = d;
            memcpy(pa, c, sizeof c);
            memcpy(pq, cq, sizeof c);
        }
    }
    return best;
}

/* Signed: inside the ball the distance is negative, so that moving in counts as moving in. */
static double point_ball(const double p[3], const limen__piece *pc, double q[3])
{
    double d[3];
    sub3(p, pc->c, d);
    double l = len3(d);
    if (!(l > 1e-300)) {
        memcpy(q, pc->c, sizeof d);
        q[0] += pc->r;
        return -pc->r;
    }
    mad3(pc->c, pc->r / l, d, q);
    return l - pc->r;
}

static double point_cyl(const double p[3], const limen__piece *pc, double q[3])
{
    double rel[3], rad[3];
    sub3(p, pc->c, rel);
    double y = dot3(rel, pc->axis);
    mad3(rel, -y, pc->axis, rad);
    double rho = len3(rad);
    double yc = y < 0 ? 0 : y > pc->h ? pc->h : y;
    double k = rho > pc->r ? pc->r / rho : 1;
    for (int i = 0; i < 3; i++)
        q[i] = pc->c[i] + yc * pc->axis[i] + k * rad[i];
    return dist3(p, q);
}

/* The segment's closest point to a cylinder: the distance along the segment is convex, so
 * a golden-section search finds its least value. */
static double seg_cyl(const double a[3], const double b[3], const limen__piece *pc, double pa[3],
                      double pq[3])
{
    double ab[3], lo = 0, hi = 1, p[3], q[3];
    sub3(b, a, ab);
    const double g = 0.6180339887498949;
    for (int it = 0; it < 60 && hi - lo > 1e-13; it++) {
        double m1 = hi - g * (hi - lo), m2 = lo + g * (hi - lo), p1[3], p2[3];
        mad3(a, m1, ab, p1);
        mad3(a, m2, ab, p2);
        if (point_cyl(p1, pc, q) <= point_cyl(p2, pc, q))
            hi = m2;
        else
            lo = m1;
    }
    mad3(a, 0.5 * (lo + hi), ab, p);
    double d = point_cyl(p, pc, q);
    memcpy(pa, p, sizeof p);
    memcpy(pq, q, sizeof q);
    return d;
}

/* Distance from the body at t to a piece, with the closest points (body side, piece side). */
double limen__body_dist(const limen__body *bd, double t, const limen__piece *pc, double pb[3],
                        double pk[3])
{
    double a[3];
    mad3(bd->a, t, bd->v, a);
    if (!bd->capsule) {
        memcpy(pb, a, sizeof a);
        switch (pc->kind) {
        case LIMEN__PIECE_POLY: return point_poly(a, pc, pk);
        case LIMEN__PIECE_BALL: return point_ball(a, pc, pk);
        default: return point_cyl(a, pc, pk);
        }
    }
    double b[3];
    mad3(bd->b, t, bd->v, b);
    switch (pc->kind) {
    case LIMEN__PIECE_POLY: return seg_poly(a, b, pc, pb, pk);
    case LIMEN__PIECE_BALL: {
        closest_on_segment(pc->c, a, b, pb);
        return point_ball(pb, pc, pk);
    }
    default: return seg_cyl(a, b, pc, pb, pk);
    }
}

/* First t in [t0, t1] where the body touches the piece (distance = radius), by Newton's
 * method from t0: on a convex distance it approaches the first root from below. A body
 * already touching at t0 counts only if it is moving further in. */
bool limen__piece_contact(const limen__body *bd, const limen__piece *pc, double t0, double t1,
                          double *t_out)
{
    double t = t0, vlen = len3(bd->v), tol = 1e-10 * fmax(1.0, bd->r);
    for (int it = 0; it < 200; it++) {
        double pb[3], pk[3], dv[3];
        double d = limen__body_dist(bd, t, pc, pb, pk);
        double f = d - bd->r, g;
        sub3(pb, pk, dv);
        g = fabs(d) > 1e-300 ? dot3(bd->v, dv) / d : -vlen;
        if (f <= tol) {
            if (it == 0 && !(g < -1e-9 * vlen))
                return false;
            *t_out = t;
            return true;
        }
        if (!(g < 0))
            return false;
        double dt = -f / g;
        t += dt;
        if (!(t <= t1))
            return false;
        if (dt <= 1e-15 * fmax(1.0, t)) {
            *t_out = t;
            return true;
        }
    }
    return false;
}
