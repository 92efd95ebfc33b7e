/* math_check.h - what the maths tests (test_math.c, test_projection.c) share: random
 * cases from splitmix64 with a fixed seed, so that a failure reproduces, and small double
 * maths to evaluate the library's float matrices with. */
#ifndef LIMEN_TESTS_MATH_CHECK_H
#define LIMEN_TESTS_MATH_CHECK_H

#include <stdbool.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "core/lmath.h"
#include "limen.h"

#define FEPS 1.1920928955078125e-7

/* ---------------------------------------------------------------- random numbers */

static uint64_t rng_state = 0x1e3e5eedULL;

static inline double rnd(void)   /* [0, 1) */
{
    uint64_t z = (rng_state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

static inline double rnd_range(double a, double b) { return a + (b - a) * rnd(); }

static inline void rnd_unit(double v[3])
{
    double l2;
    do {
        for (int i = 0; i < 3; i++)
            v[i] = rnd_range(-1, 1);
        l2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
    } while (l2 > 1 || l2 < 1e-4);
    for (int i = 0; i < 3; i++)
        v[i] /= sqrt(l2);
}

/* ---------------------------------------------------------------- small double maths */

static inline double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static inline double len3(const double a[3]) { return sqrt(dot3(a, a)); }

static inline void cross3(const double a[3], const double b[3], double out[3])
{
    double t[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                   a[0] * b[1] - a[1] * b[0]};
    memcpy(out, t, sizeof t);
}

static inline void normalize3(double a[3])
{
    double l = len3(a);
    for (int i = 0; i < 3; i++)
        a[i] /= l;
}

/* Unit vectors u, v with (u, v, n) right-handed and orthonormal. */
static inline void tangents(const double n[3], double u[3], double v[3])
{
    double a[3] = {0, 0, 0};
    a[fabs(n[0]) < 0.6 ? 0 : 1] = 1;
    cross3(a, n, u);
    normalize3(u);
    cross3(n, u, v);
}

/* out = m * p for a float column-major matrix, in double. */
static inline void mul4(const float m[16], const double p[4], double out[4])
{
    double t[4];
    for (int r = 0; r < 4; r++)
        t[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r] * p[3];
    memcpy(out, t, sizeof t);
}

static inline void mul_point(const float m[16], const double p[3], double out[3])
{
    double h[4] = {p[0], p[1], p[2], 1}, r[4];
    mul4(m, h, r);
    for (int i = 0; i < 3; i++)
        out[i] = r[i] / r[3];
}

static inline void mul_dir(const float m[16], const double v[3], double out[3])
{
    double h[4] = {v[0], v[1], v[2], 0}, r[4];
    mul4(m, h, r);
    memcpy(out, r, 3 * sizeof(double));
}

static inline void mat_mul(const float a[16], const float b[16], double out[16])
{
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            double s = 0;
            for (int k = 0; k < 4; k++)
                s += (double)a[k * 4 + r] * b[c * 4 + k];
            out[c * 4 + r] = s;
        }
}

static inline double det3(const float m[16])   /* upper-left 3x3 */
{
    return (double)m[0] * ((double)m[5] * m[10] - (double)m[9] * m[6]) -
           (double)m[4] * ((double)m[1] * m[10] - (double)m[9] * m[2]) +
           (double)m[8] * ((double)m[1] * m[6] - (double)m[5] * m[2]);
}

static inline double plane_eval(const float c[4], const double p[3])
{
    return c[0] * p[0] + c[1] * p[1] + c[2] * p[2] + c[3];
}

static inline bool all_finite(const float *v, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(v[i]))
            return false;
    return true;
}

/* Random rotation (uniform unit quaternion) as a row-major 3x3. */
static inline void rnd_rotation(double r[9])
{
    double q[4], l2;
    do {
        for (int i = 0; i < 4; i++)
            q[i] = rnd_range(-1, 1);
        l2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
    } while (l2 > 1 || l2 < 1e-4);
    double l = sqrt(l2), w = q[0] / l, x = q[1] / l, y = q[2] / l, z = q[3] / l;
    double m[9] = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),
                   2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                   2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)};
    memcpy(r, m, sizeof m);
}

/* World matrix T(t) * R * S(s) with a uniform scale s. */
static inline void make_frame(const double r[9], const double t[3], double s, float out[16])
{
    for (int c = 0; c < 3; c++) {
        for (int row = 0; row < 3; row++)
            out[c * 4 + row] = (float)(r[row * 3 + c] * s);
        out[c * 4 + 3] = 0;
        out[12 + c] = (float)t[c];
    }
    out[15] = 1;
}

/* Column c (0..2) of a float matrix, as a direction. */
static inline void column(const float m[16], int c, double out[3])
{
    for (int i = 0; i < 3; i++)
        out[i] = m[c * 4 + i];
}

static inline void sentinel(float *v, int n)
{
    for (int i = 0; i < n; i++)
        v[i] = 12345.0f + (float)i;
}

static inline bool sentinel_intact(const float *v, int n)
{
    for (int i = 0; i < n; i++)
        if (v[i] != 12345.0f + (float)i)
            return false;
    return true;
}


static inline void rnd_affine(float m[16])
{
    /* T * R1 * S * R2: rotation, non-uniform scale (shear through the second rotation). */
    double r1[9], r2[9], s[3], a[9];
    rnd_rotation(r1);
    rnd_rotation(r2);
    for (int i = 0; i < 3; i++)
        s[i] = exp(rnd_range(log(0.2), log(5)));
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            a[r * 3 + c] = 0;
            for (int k = 0; k < 3; k++)
                a[r * 3 + c] += r1[r * 3 + k] * s[k] * r2[k * 3 + c];
        }
    for (int c = 0; c < 3; c++) {
        for (int r = 0; r < 3; r++)
            m[c * 4 + r] = (float)a[r * 3 + c];
        m[c * 4 + 3] = 0;
        m[12 + c] = (float)rnd_range(-20, 20);
    }
    m[15] = 1;
}

#endif
