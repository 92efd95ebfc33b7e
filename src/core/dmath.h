/* dmath.h - double-precision 4x4 helpers for composing virtual views, where float error
 * would pile up over dozens of levels. Column-major like cglm: m[col * 4 + row]. */
#ifndef LIMEN_DMATH_H
#define LIMEN_DMATH_H

#include <math.h>
#include <stdbool.h>
#include <string.h>

static inline void limen__d_identity(double m[16])
{
    memset(m, 0, sizeof(double) * 16);
    m[0] = m[5] = m[10] = m[15] = 1.0;
}

static inline void limen__d_from_f(const float *f, double m[16])
{
    for (int i = 0; i < 16; i++)
        m[i] = f[i];
}

static inline void limen__d_to_f(const double m[16], float *f)
{
    for (int i = 0; i < 16; i++)
        f[i] = (float)m[i];
}

/* dest = a * b; dest may alias a or b. */
static inline void limen__d_mul(const double a[16], const double b[16], double dest[16])
{
    double r[16];
    for (int c = 0; c < 4; c++)
        for (int row = 0; row < 4; row++)
            r[c * 4 + row] = a[0 * 4 + row] * b[c * 4 + 0] + a[1 * 4 + row] * b[c * 4 + 1] +
                             a[2 * 4 + row] * b[c * 4 + 2] + a[3 * 4 + row] * b[c * 4 + 3];
    memcpy(dest, r, sizeof r);
}

/* The adjugate of m (its cofactors, transposed) in adj, and the determinant as the value:
 * m^-1 = adj / det. Layout-agnostic (the inverse of the transpose is the transpose of the
 * inverse); the caller decides what counts as singular. */
static inline double limen__d_adjugate(const double m[16], double adj[16])
{
    adj[0] = m[5] * m[10] * m[15] - m[5] * m[11] * m[14] - m[9] * m[6] * m[15] +
             m[9] * m[7] * m[14] + m[13] * m[6] * m[11] - m[13] * m[7] * m[10];
    adj[4] = -m[4] * m[10] * m[15] + m[4] * m[11] * m[14] + m[8] * m[6] * m[15] -
             m[8] * m[7] * m[14] - m[12] * m[6] * m[11] + m[12] * m[7] * m[10];
    adj[8] = m[4] * m[9] * m[15] - m[4] * m[11] * m[13] - m[8] * m[5] * m[15] +
             m[8] * m[7] * m[13] + m[12] * m[5] * m[11] - m[12] * m[7] * m[9];
    adj[12] = -m[4] * m[9] * m[14] + m[4] * m[10] * m[13] + m[8] * m[5] * m[14] -
              m[8] * m[6] * m[13] - m[12] * m[5] * m[10] + m[12] * m[6] * m[9];
    adj[1] = -m[1] * m[10] * m[15] + m[1] * m[11] * m[14] + m[9] * m[2] * m[15] -
             m[9] * m[3] * m[14] - m[13] * m[2] * m[11] + m[13] * m[3] * m[10];
    adj[5] = m[0] * m[10] * m[15] - m[0] * m[11] * m[14] - m[8] * m[2] * m[15] +
             m[8] * m[3] * m[14] + m[12] * m[2] * m[11] - m[12] * m[3] * m[10];
    adj[9] = -m[0] * m[9] * m[15] + m[0] * m[11] * m[13] + m[8] * m[1] * m[15] -
             m[8] * m[3] * m[13] - m[12] * m[1] * m[11] + m[12] * m[3] * m[9];
    adj[13] = m[0] * m[9] * m[14] - m[0] * m[10] * m[13] - m[8] * m[1] * m[14] +
              m[8] * m[2] * m[13] + m[12] * m[1] * m[10] - m[12] * m[2] * m[9];
    adj[2] = m[1] * m[6] * m[15] - m[1] * m[7] * m[14] - m[5] * m[2] * m[15] +
             m[5] * m[3] * m[14] + m[13] * m[2] * m[7] - m[13] * m[3] * m[6];
    adj[6] = -m[0] * m[6] * m[15] + m[0] * m[7] * m[14] + m[4] * m[2] * m[15] -
             m[4] * m[3] * m[14] - m[12] * m[2] * m[7] + m[12] * m[3] * m[6];
    adj[10] = m[0] * m[5] * m[15] - m[0] * m[7] * m[13] - m[4] * m[1] * m[15] +
              m[4] * m[3] * m[13] + m[12] * m[1] * m[7] - m[12] * m[3] * m[5];
    adj[14] = -m[0] * m[5] * m[14] + m[0] * m[6] * m[13] + m[4] * m[1] * m[14] -
              m[4] * m[2] * m[13] - m[12] * m[1] * m[6] + m[12] * m[2] * m[5];
    adj[3] = -m[1] * m[6] * m[11] + m[1] * m[7] * m[10] + m[5] * m[2] * m[11] -
             m[5] * m[3] * m[10] - m[9] * m[2] * m[7] + m[9] * m[3] * m[6];
    adj[7] = m[0] * m[6] * m[11] - m[0] * m[7] * m[10] - m[4] * m[2] * m[11] +
             m[4] * m[3] * m[10] + m[8] * m[2] * m[7] - m[8] * m[3] * m[6];
    adj[11] = -m[0] * m[5] * m[11] + m[0] * m[7] * m[9] + m[4] * m[1] * m[11] -
              m[4] * m[3] * m[9] - m[8] * m[1] * m[7] + m[8] * m[3] * m[5];
    adj[15] = m[0] * m[5] * m[10] - m[0] * m[6] * m[9] - m[4] * m[1] * m[10] +
              m[4] * m[2] * m[9] + m[8] * m[1] * m[6] - m[8] * m[2] * m[5];
    return m[0] * adj[0] + m[1] * adj[4] + m[2] * adj[8] + m[3] * adj[12];
}

/* General inverse by cofactors; false (dest untouched) when singular. */
static inline bool limen__d_inv(const double m[16], double dest[16])
{
    double inv[16];
    double det = limen__d_adjugate(m, inv);
    if (!(fabs(det) > 1e-300) || !isfinite(det))
        return false;
    for (int i = 0; i < 16; i++)
        dest[i] = inv[i] / det;
    return true;
}

/* (x, y, z, 1) -> M p, divided by w. */
static inline void limen__d_point(const double m[16], const double p[3], double out[3])
{
    double r[4];
    for (int i = 0; i < 4; i++)
        r[i] = m[i] * p[0] + m[4 + i] * p[1] + m[8 + i] * p[2] + m[12 + i];
    for (int i = 0; i < 3; i++)
        out[i] = r[i] / r[3];
}

/* plane' = (M^-1)^T plane given minv = M^-1, renormalised to |n| = 1. */
static inline bool limen__d_plane(const double minv[16], const double plane[4], double out[4])
{
    double r[4];
    for (int j = 0; j < 4; j++)
        r[j] = minv[j * 4 + 0] * plane[0] + minv[j * 4 + 1] * plane[1] +
               minv[j * 4 + 2] * plane[2] + minv[j * 4 + 3] * plane[3];
    double len = sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]);
    if (!(len > 0) || !isfinite(len))
        return false;
    for (int j = 0; j < 4; j++)
        out[j] = r[j] / len;
    return true;
}

static inline double limen__d_plane_dist(const double plane[4], const double p[3])
{
    return plane[0] * p[0] + plane[1] * p[1] + plane[2] * p[2] + plane[3];
}

/* The one polygon clipper (Sutherland-Hodgman): keeps the part of polygon in (n vertices of
 * dim = 3 doubles, points, or dim = 4, homogeneous points) where plane . (x, y, z, w) >= 0,
 * w = 1 for points, writing it to out; stops taking vertices once cap are written, so out
 * must hold cap + 1. Returns the count. */
static inline int limen__d_clip(const double *in, int n, int dim, const double plane[4],
                                double *out, int cap)
{
    int m = 0;
    for (int i = 0; i < n && m < cap; i++) {
        const double *a = in + (size_t)i * dim, *b = in + (size_t)((i + 1) % n) * dim;
        double da = plane[0] * a[0] + plane[1] * a[1] + plane[2] * a[2];
        double db = plane[0] * b[0] + plane[1] * b[1] + plane[2] * b[2];
        da += dim == 4 ? plane[3] * a[3] : plane[3];
        db += dim == 4 ? plane[3] * b[3] : plane[3];
        if (da >= 0)
            memcpy(out + (size_t)m++ * dim, a, sizeof(double) * (size_t)dim);
        if ((da >= 0) != (db >= 0)) {
            double t = da / (da - db);
            for (int k = 0; k < dim; k++)
                out[(size_t)m * dim + k] = a[k] + t * (b[k] - a[k]);
            m++;
        }
    }
    return m;
}

/* limen__d_clip of homogeneous points. */
static inline int limen__d_clip4(const double in[][4], int n, const double plane[4],
                                 double out[][4], int cap)
{
    return limen__d_clip(&in[0][0], n, 4, plane, &out[0][0], cap);
}

/* limen__d_clip of points. */
static inline int limen__d_clip3(const double in[][3], int n, const double plane[4],
                                 double out[][3], int cap)
{
    return limen__d_clip(&in[0][0], n, 3, plane, &out[0][0], cap);
}

#endif
