/* test_math.c - the maths of limen.h and src/core/lmath.h, checked by properties.
 *
 * Every check states a geometric fact (a point on a plane stays on it, a reflection is an
 * involution, the oblique near plane is the clip plane, ...) and evaluates it in double from
 * the float matrices the library returns; no expected number is copied from the code.
 * Tolerances are written as multiples of float rounding (FEPS = 2^-23 ~ 1.2e-7) times the
 * size of the quantities involved; each says where its factor comes from.
 *
 * Random cases come from splitmix64 with a fixed seed, so a failure reproduces.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "check.h"
#include "core/lmath.h"
#include "limen.h"

#define FEPS 1.1920928955078125e-7

/* ---------------------------------------------------------------- random numbers */

static uint64_t rng_state = 0x1e3e5eedULL;

static double rnd(void)   /* [0, 1) */
{
    uint64_t z = (rng_state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    z ^= z >> 31;
    return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

static double rnd_range(double a, double b) { return a + (b - a) * rnd(); }

static void rnd_unit(double v[3])
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

static double dot3(const double a[3], const double b[3])
{
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}

static double len3(const double a[3]) { return sqrt(dot3(a, a)); }

static void cross3(const double a[3], const double b[3], double out[3])
{
    double t[3] = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
                   a[0] * b[1] - a[1] * b[0]};
    memcpy(out, t, sizeof t);
}

static void normalize3(double a[3])
{
    double l = len3(a);
    for (int i = 0; i < 3; i++)
        a[i] /= l;
}

/* Unit vectors u, v with (u, v, n) right-handed and orthonormal. */
static void tangents(const double n[3], double u[3], double v[3])
{
    double a[3] = {0, 0, 0};
    a[fabs(n[0]) < 0.6 ? 0 : 1] = 1;
    cross3(a, n, u);
    normalize3(u);
    cross3(n, u, v);
}

/* out = m * p for a float column-major matrix, in double. */
static void mul4(const float m[16], const double p[4], double out[4])
{
    double t[4];
    for (int r = 0; r < 4; r++)
        t[r] = m[r] * p[0] + m[4 + r] * p[1] + m[8 + r] * p[2] + m[12 + r] * p[3];
    memcpy(out, t, sizeof t);
}

static void mul_point(const float m[16], const double p[3], double out[3])
{
    double h[4] = {p[0], p[1], p[2], 1}, r[4];
    mul4(m, h, r);
    for (int i = 0; i < 3; i++)
        out[i] = r[i] / r[3];
}

static void mul_dir(const float m[16], const double v[3], double out[3])
{
    double h[4] = {v[0], v[1], v[2], 0}, r[4];
    mul4(m, h, r);
    memcpy(out, r, 3 * sizeof(double));
}

static void mat_mul(const float a[16], const float b[16], double out[16])
{
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            double s = 0;
            for (int k = 0; k < 4; k++)
                s += (double)a[k * 4 + r] * b[c * 4 + k];
            out[c * 4 + r] = s;
        }
}

static double det3(const float m[16])   /* upper-left 3x3 */
{
    return (double)m[0] * ((double)m[5] * m[10] - (double)m[9] * m[6]) -
           (double)m[4] * ((double)m[1] * m[10] - (double)m[9] * m[2]) +
           (double)m[8] * ((double)m[1] * m[6] - (double)m[5] * m[2]);
}

static double plane_eval(const float c[4], const double p[3])
{
    return c[0] * p[0] + c[1] * p[1] + c[2] * p[2] + c[3];
}

static bool all_finite(const float *v, int n)
{
    for (int i = 0; i < n; i++)
        if (!isfinite(v[i]))
            return false;
    return true;
}

/* Random rotation (uniform unit quaternion) as a row-major 3x3. */
static void rnd_rotation(double r[9])
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
static void make_frame(const double r[9], const double t[3], double s, float out[16])
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
static void column(const float m[16], int c, double out[3])
{
    for (int i = 0; i < 3; i++)
        out[i] = m[c * 4 + i];
}

static void sentinel(float *v, int n)
{
    for (int i = 0; i < n; i++)
        v[i] = 12345.0f + (float)i;
}

static bool sentinel_intact(const float *v, int n)
{
    for (int i = 0; i < n; i++)
        if (v[i] != 12345.0f + (float)i)
            return false;
    return true;
}

/* ---------------------------------------------------------------- planes */

static void test_plane_from_points(void)
{
    /* The right-hand rule on a case one can draw: counter-clockwise seen from +Z. */
    float pl[4];
    CHECK_OK(limen_plane_from_points((float[3]){0, 0, 2}, (float[3]){1, 0, 2},
                                     (float[3]){0, 1, 2}, pl));
    CHECK(pl[2] > 0.999999f && fabsf(pl[0]) < 1e-7f && fabsf(pl[1]) < 1e-7f);
    CHECK_NEAR(pl[3], -2.0, 1e-6);   /* z = 2 on the plane: n.p + d = 0 */

    for (int i = 0; i < 2000; i++) {
        float p[3][3];
        double e[3][3];
        for (int k = 0; k < 3; k++)
            for (int j = 0; j < 3; j++)
                p[k][j] = (float)rnd_range(-10, 10);
        for (int j = 0; j < 3; j++) {
            e[0][j] = (double)p[1][j] - p[0][j];
            e[1][j] = (double)p[2][j] - p[0][j];
        }
        cross3(e[0], e[1], e[2]);
        /* Skip slivers: their plane is legitimately ill-conditioned. */
        if (len3(e[2]) < 1e-2 * len3(e[0]) * len3(e[1]))
            continue;
        CHECK_OK(limen_plane_from_points(p[0], p[1], p[2], pl));
        double n[3] = {pl[0], pl[1], pl[2]};
        CHECK_NEAR(len3(n), 1.0, 4 * FEPS);
        CHECK(dot3(n, e[2]) > 0);   /* front is where (b-a)x(c-a) points */
        /* Float plane: n and d each carry ~FEPS relative error; |p| <= 17.4, |d| <= 17.4,
         * and the sliver bound (sine >= 1e-2) amplifies the normal's error by up to 100. */
        for (int k = 0; k < 3; k++) {
            double q[3] = {p[k][0], p[k][1], p[k][2]};
            CHECK_NEAR(plane_eval(pl, q), 0.0, 100 * FEPS * 40);
        }
    }
}

static void test_plane_degenerate(void)
{
    float pl[4];
    /* Exactly collinear (representable) points, in every order. */
    float a[3] = {1, 2, 3}, b[3] = {2, 0, 3.5f}, c[3] = {-1, 6, 2}, d[3] = {1.5f, 1, 3.25f};
    const float *trip[][3] = {{a, b, c}, {b, c, a}, {c, a, b}, {a, d, b}, {d, c, a}};
    for (size_t i = 0; i < sizeof trip / sizeof trip[0]; i++) {
        sentinel(pl, 4);
        CHECK(limen_plane_from_points(trip[i][0], trip[i][1], trip[i][2], pl) ==
              LIMEN_ERR_DEGENERATE);
        CHECK(sentinel_intact(pl, 4));
    }
    /* Collinear up to float rounding of a + t dir. */
    for (int i = 0; i < 500; i++) {
        double o[3], dir[3];
        rnd_unit(dir);
        for (int j = 0; j < 3; j++)
            o[j] = rnd_range(-5, 5);
        double t1 = rnd_range(0.5, 5), t2 = -rnd_range(0.5, 5);
        float p0[3], p1[3], p2[3];
        for (int j = 0; j < 3; j++) {
            p0[j] = (float)o[j];
            p1[j] = (float)(o[j] + t1 * dir[j]);
            p2[j] = (float)(o[j] + t2 * dir[j]);
        }
        sentinel(pl, 4);
        CHECK(limen_plane_from_points(p0, p1, p2, pl) == LIMEN_ERR_DEGENERATE);
        CHECK(sentinel_intact(pl, 4));
    }
    /* Repeated points. */
    sentinel(pl, 4);
    CHECK(limen_plane_from_points(a, a, c, pl) == LIMEN_ERR_DEGENERATE);
    CHECK(limen_plane_from_points(a, c, c, pl) == LIMEN_ERR_DEGENERATE);
    CHECK(limen_plane_from_points(c, a, c, pl) == LIMEN_ERR_DEGENERATE);
    CHECK(limen_plane_from_points(a, a, a, pl) == LIMEN_ERR_DEGENERATE);
    CHECK(sentinel_intact(pl, 4));
    /* NaN, Inf, NULL. */
    float nan3[3] = {0, NAN, 0}, inf3[3] = {INFINITY, 0, 0};
    CHECK(limen_plane_from_points(nan3, b, c, pl) == LIMEN_ERR_ARG);
    CHECK(limen_plane_from_points(a, inf3, c, pl) == LIMEN_ERR_ARG);
    CHECK(limen_plane_from_points(a, b, nan3, pl) == LIMEN_ERR_ARG);
    CHECK(limen_plane_from_points(NULL, b, c, pl) == LIMEN_ERR_ARG);
    CHECK(limen_plane_from_points(a, b, c, NULL) == LIMEN_ERR_ARG);
    CHECK(sentinel_intact(pl, 4));
}

static void test_plane_from_point_normal(void)
{
    float pl[4];
    for (int i = 0; i < 2000; i++) {
        double n[3];
        rnd_unit(n);
        double len = exp(rnd_range(log(1e-3), log(1e3)));
        float p[3], nf[3];
        for (int j = 0; j < 3; j++) {
            p[j] = (float)rnd_range(-50, 50);
            nf[j] = (float)(n[j] * len);
        }
        CHECK_OK(limen_plane_from_point_normal(p, nf, pl));
        double pn[3] = {pl[0], pl[1], pl[2]}, pd[3] = {p[0], p[1], p[2]};
        double nd[3] = {nf[0], nf[1], nf[2]};
        normalize3(nd);
        CHECK_NEAR(len3(pn), 1.0, 4 * FEPS);
        CHECK(dot3(pn, nd) > 1 - 8 * FEPS);   /* same direction, not flipped */
        CHECK_NEAR(plane_eval(pl, pd), 0.0, 8 * FEPS * 87);   /* |p| <= 87 */
    }
    /* A tiny normal is still a direction. */
    CHECK_OK(limen_plane_from_point_normal((float[3]){0, 0, 0}, (float[3]){0, 1e-30f, 0}, pl));
    CHECK_NEAR(pl[1], 1.0, FEPS);

    sentinel(pl, 4);
    CHECK(limen_plane_from_point_normal((float[3]){1, 2, 3}, (float[3]){0, 0, 0}, pl) ==
          LIMEN_ERR_DEGENERATE);
    CHECK(limen_plane_from_point_normal((float[3]){1, 2, 3}, (float[3]){-0.0f, 0, 0}, pl) ==
          LIMEN_ERR_DEGENERATE);
    CHECK(limen_plane_from_point_normal((float[3]){NAN, 2, 3}, (float[3]){0, 1, 0}, pl) ==
          LIMEN_ERR_ARG);
    CHECK(limen_plane_from_point_normal((float[3]){1, 2, 3}, (float[3]){0, INFINITY, 0}, pl) ==
          LIMEN_ERR_ARG);
    CHECK(limen_plane_from_point_normal(NULL, (float[3]){0, 1, 0}, pl) == LIMEN_ERR_ARG);
    CHECK(sentinel_intact(pl, 4));
}

static void rnd_affine(float m[16])
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

static void test_plane_transform(void)
{
    for (int i = 0; i < 2000; i++) {
        float m[16], c[4], c2[4];
        rnd_affine(m);
        double n[3], u[3], v[3];
        rnd_unit(n);
        tangents(n, u, v);
        double d = rnd_range(-10, 10);
        for (int j = 0; j < 3; j++)
            c[j] = (float)n[j];
        c[3] = (float)d;
        CHECK_OK(limen_plane_transform(m, c, c2));
        double n2[3] = {c2[0], c2[1], c2[2]};
        CHECK_NEAR(len3(n2), 1.0, 4 * FEPS);
        for (int k = 0; k < 20; k++) {
            /* p on C (to the float plane's accuracy), and a point in front of C */
            double p[3], q[3], mp[3], mq[3], s = rnd_range(-10, 10), t = rnd_range(-10, 10);
            for (int j = 0; j < 3; j++)
                p[j] = -d * n[j] + s * u[j] + t * v[j];
            double off = plane_eval(c, p);   /* float rounding of c: ~FEPS * 25 */
            double h = rnd_range(0.5, 5);
            for (int j = 0; j < 3; j++)
                q[j] = p[j] + h * n[j];
            mul_point(m, p, mp);
            mul_point(m, q, mq);
            /* |M p| <= 5 * 25 + 35; the plane's float rounding times that, plus the offset
             * carried through M (scale <= 5 after renormalisation, <= 25 squared). */
            CHECK_NEAR(plane_eval(c2, mp), 0.0, 16 * FEPS * 160 + 25 * fabs(off));
            CHECK(plane_eval(c2, mq) > 0);   /* the front stays the front */
        }
    }
    /* The mirror's own plane comes back reversed: its front maps to its back. */
    for (int i = 0; i < 200; i++) {
        double n[3];
        rnd_unit(n);
        float c[4] = {(float)n[0], (float)n[1], (float)n[2], (float)rnd_range(-10, 10)};
        float m[16], c2[4];
        CHECK_OK(limen_mirror_matrix(c, m));
        CHECK_OK(limen_plane_transform(m, c, c2));
        for (int j = 0; j < 4; j++)
            CHECK_NEAR(c2[j], -c[j], 16 * FEPS * (1 + fabs(c[3])));
    }
    float sing[16] = {1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 3, 4, 5, 1};   /* y scaled to 0 */
    float c[4] = {0, 1, 0, -1}, out[4];
    sentinel(out, 4);
    CHECK(limen_plane_transform(sing, c, out) == LIMEN_ERR_DEGENERATE);
    float nanm[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, NAN, 0, 0, 1};
    CHECK(limen_plane_transform(nanm, c, out) == LIMEN_ERR_ARG);
    CHECK(limen_plane_transform(NULL, c, out) == LIMEN_ERR_ARG);
    CHECK(sentinel_intact(out, 4));
}

/* ---------------------------------------------------------------- mirrors */

/* The normals a mirror test must include: each axis both ways, and near-axis normals
 * (a float can carry 1e-7 next to 1 only as a separate component). */
static const double special_normals[][3] = {
    {0, -1, 0}, {0, 1, 0}, {1, 0, 0}, {-1, 0, 0}, {0, 0, 1}, {0, 0, -1},
    {1e-7, -1, 0}, {1e-7, 1, 0}, {0, -1, 1e-7}, {-1e-7, -1, 1e-7}, {1e-4, -1, -1e-4},
    {1, 1e-7, 0}, {0, 1e-7, -1}, {1, 1, 1}, {-1, 2, -3},
};
#define N_SPECIAL (int)(sizeof special_normals / sizeof special_normals[0])

/* Plane number i of a sweep: the special normals first, then random ones; d random. */
static void mirror_plane(int i, double n[3], double *d)
{
    if (i < N_SPECIAL) {
        memcpy(n, special_normals[i], sizeof(double[3]));
        normalize3(n);
    } else {
        rnd_unit(n);
    }
    *d = i % 7 == 0 ? 0.0 : rnd_range(-20, 20);
}

static void test_mirror_properties(void)
{
    for (int i = 0; i < 4000; i++) {
        double n[3], d, u[3], v[3];
        mirror_plane(i, n, &d);
        float c[4] = {(float)n[0], (float)n[1], (float)n[2], (float)d}, m[16];
        /* The float plane is the mirror: take its normal, renormalised in double. */
        double nf[3] = {c[0], c[1], c[2]}, df = c[3] / len3(nf);
        normalize3(nf);
        tangents(nf, u, v);
        CHECK_OK(limen_mirror_matrix(c, m));
        CHECK(all_finite(m, 16));

        /* Involution: M M = I; translation entries scale with |d|. */
        double mm[16], worst = 0;
        mat_mul(m, m, mm);
        for (int k = 0; k < 16; k++)
            worst = fmax(worst, fabs(mm[k] - (k % 5 == 0 ? 1.0 : 0.0)) / (k >= 12 ? 1 + fabs(df) : 1));
        CHECK_MSG(worst <= 8 * FEPS, "plane %d: |MM - I| = %g", i, worst);
        CHECK_NEAR(det3(m), -1.0, 8 * FEPS);
        CHECK(m[3] == 0 && m[7] == 0 && m[11] == 0 && m[15] == 1);

        /* The normal (a direction) turns to -n. */
        double mn[3];
        mul_dir(m, nf, mn);
        for (int j = 0; j < 3; j++)
            CHECK_NEAR(mn[j], -nf[j], 4 * FEPS);

        for (int k = 0; k < 8; k++) {
            double p[3], q[3], mp[3], mq[3], s = rnd_range(-10, 10), t = rnd_range(-10, 10);
            double h = rnd_range(-10, 10);
            for (int j = 0; j < 3; j++) {
                p[j] = -df * nf[j] + s * u[j] + t * v[j];
                q[j] = p[j] + h * nf[j];
            }
            mul_point(m, p, mp);
            mul_point(m, q, mq);
            double scale = 1 + len3(p) + fabs(h);   /* |p| <= 35 */
            for (int j = 0; j < 3; j++)
                CHECK_NEAR(mp[j], p[j], 8 * FEPS * scale);   /* points on the plane stay */
            double dist = dot3(nf, mq) + df;
            CHECK_NEAR(dist, -h, 8 * FEPS * scale);           /* distance t -> -t */
        }
    }
}

static void test_mirror_node_form(void)
{
    /* W's local +Z is the mirror normal and local z = 0 the mirror; the node form
     * W diag(1,1,-1,1) W^-1 must be the same reflection, whatever the in-plane rotation,
     * origin on the plane and uniform scale of W. */
    for (int i = 0; i < 2000; i++) {
        double n[3], d, u[3], v[3];
        mirror_plane(i, n, &d);
        tangents(n, u, v);
        double ang = rnd_range(0, 2 * GLM_PI), s = i % 3 ? 1.0 : exp(rnd_range(-2, 2));
        double r[9], o[3], a = rnd_range(-5, 5), b = rnd_range(-5, 5);
        for (int j = 0; j < 3; j++) {
            double x = cos(ang) * u[j] + sin(ang) * v[j], y = -sin(ang) * u[j] + cos(ang) * v[j];
            r[j * 3 + 0] = x;
            r[j * 3 + 1] = y;
            r[j * 3 + 2] = n[j];
            o[j] = -d * n[j] + a * u[j] + b * v[j];
        }
        float w[16], c[4] = {(float)n[0], (float)n[1], (float)n[2], (float)d}, mc[16];
        make_frame(r, o, s, w);
        mat4 wm, mn;
        limen__mat4_from_array(w, wm);
        CHECK_OK(limen__mirror_mat4_node(wm, mn));
        CHECK_OK(limen_mirror_matrix(c, mc));
        float mnf[16];
        limen__mat4_to_array(mn, mnf);
        /* Two float roundings of the same frame (W rounded, c rounded): ~FEPS * (1 + |o|). */
        for (int k = 0; k < 16; k++)
            CHECK_NEAR(mnf[k], mc[k], 16 * FEPS * (1 + len3(o)));
    }
}

/* Largest distance between M p and the exact reflection of p about (n, d), over a grid of
 * points within 17 of the origin. */
static double mirror_error(const float m[16], const double n[3], double d)
{
    double worst = 0;
    for (int i = -2; i <= 2; i++)
        for (int j = -2; j <= 2; j++)
            for (int k = -2; k <= 2; k++) {
                double p[3] = {5.0 * i, 5.0 * j, 5.0 * k}, q[3];
                double s = dot3(n, p) + d;
                mul_point(m, p, q);
                for (int a = 0; a < 3; a++) {
                    double e = fabs(q[a] - (p[a] - 2 * s * n[a]));
                    if (!(e <= worst))
                        worst = e;   /* NaN sticks */
                }
            }
    return worst;
}

static void seed_and_closed(const double n0[3], double d, double *err_seed, double *err_closed,
                            bool *seed_finite)
{
    vec4 c = {(float)n0[0], (float)n0[1], (float)n0[2], (float)d};
    double n[3] = {c[0], c[1], c[2]}, l = len3(n);
    normalize3(n);
    mat4 ms, mc;
    limen__mirror_mat4_axis_angle(c, ms);
    limen__mirror_mat4(c, mc);
    float fs[16], fc[16];
    limen__mat4_to_array(ms, fs);
    limen__mat4_to_array(mc, fc);
    *seed_finite = all_finite(fs, 16);
    *err_seed = mirror_error(fs, n, c[3] / l);
    *err_closed = mirror_error(fc, n, c[3] / l);
}

static void test_mirror_seed_method(void)
{
    /* Seed 000's A^-1 F A with the axis-angle rotation of n onto +Y is kept as a compared
     * method. This test documents what it does, so that a later benchmark knows:
     *  - it is right in general (normals away from +-Y);
     *  - at n = (0,-1,0) its axis n x Y is zero and glm-style normalisation makes NaN
     *    (so does n = (0,+1,0) in the seed's code: the axis vanishes there too);
     *  - near either pole acos(n.y) is ill-conditioned (d acos / dx = -1/sin), so the
     *    rotation angle is off by ~FEPS / angle and the image by that times the distance.
     * The closed form has none of this. */
    double err_s, err_c;
    bool fin;
    const double down[3] = {0, -1, 0}, up[3] = {0, 1, 0};
    seed_and_closed(down, 2.0, &err_s, &err_c, &fin);
    CHECK(!fin);                      /* seed: NaN at n = (0,-1,0) */
    CHECK(err_c <= 8 * FEPS * 20);    /* closed form: exact to float rounding */
    seed_and_closed(up, 2.0, &err_s, &err_c, &fin);
    CHECK(!fin);
    CHECK(err_c <= 8 * FEPS * 20);

    /* Near the poles: sweep the tilt eps from 1e-6 to 1e-2 rad. */
    for (int pole = -1; pole <= 1; pole += 2) {
        double worst_s = 0, worst_c = 0;
        for (double eps = 1e-6; eps <= 1e-2; eps *= 1.5) {
            double n[3] = {0.6 * sin(eps), pole * cos(eps), 0.8 * sin(eps)};
            seed_and_closed(n, 3.0, &err_s, &err_c, &fin);
            worst_s = fmax(worst_s, err_s);
            worst_c = fmax(worst_c, err_c);
        }
        CHECK_MSG(worst_c <= 8 * FEPS * 20, "closed form near pole %d: %g", pole, worst_c);
        CHECK_MSG(worst_s > 1e-4 && worst_s > 100 * worst_c,
                  "seed near pole %d: error %g (closed form %g)", pole, worst_s, worst_c);
    }

    /* Away from the poles (|n.y| <= 0.9) the seed and the closed form agree. */
    for (int i = 0; i < 1000; i++) {
        double n[3];
        do
            rnd_unit(n);
        while (fabs(n[1]) > 0.9);
        seed_and_closed(n, rnd_range(-5, 5), &err_s, &err_c, &fin);
        CHECK(fin);
        CHECK_MSG(err_s <= 1e-4, "seed away from the poles: %g", err_s);
        CHECK(err_c <= 8 * FEPS * 25);
    }
}

static void test_mirror_args(void)
{
    float m[16];
    sentinel(m, 16);
    CHECK(limen_mirror_matrix((float[4]){0, 0, 0, 1}, m) == LIMEN_ERR_DEGENERATE);
    CHECK(limen_mirror_matrix((float[4]){0, NAN, 1, 1}, m) == LIMEN_ERR_ARG);
    CHECK(limen_mirror_matrix((float[4]){0, 1, 0, INFINITY}, m) == LIMEN_ERR_ARG);
    CHECK(limen_mirror_matrix(NULL, m) == LIMEN_ERR_ARG);
    CHECK(limen_mirror_matrix((float[4]){0, 1, 0, 0}, NULL) == LIMEN_ERR_ARG);
    CHECK(sentinel_intact(m, 16));
    /* A plane with |n| != 1 is the same plane. */
    float m1[16], m2[16];
    CHECK_OK(limen_mirror_matrix((float[4]){0, 3, 4, 10}, m1));
    CHECK_OK(limen_mirror_matrix((float[4]){0, 0.6f, 0.8f, 2}, m2));
    for (int k = 0; k < 16; k++)
        CHECK_NEAR(m1[k], m2[k], 8 * FEPS * 4);
}

/* ---------------------------------------------------------------- portals */

/* What is geometrically right for a portal pair (A entered, B seen), with X = W_B R_y(180)
 * W_A^-1:
 *  - W_B^-1 X W_A = R_y(180): in the two portals' own frames X is the half turn about +Y.
 *    A's origin goes to B's origin, A's +Y (up) to B's +Y, A's +Z (its normal, where the
 *    viewer stands) to B's -Z (B's back), A's +X to B's -X: you turn round, so right and
 *    left swap while up stays up. No reflection: det X > 0 (= s^3 for B scaled by s).
 *  - A viewer in front of A (local z > 0) is carried behind B (local z < 0): the virtual
 *    camera X * camera_world stands behind B's surface, and its line of sight into A
 *    (towards A's -Z) leaves through B's front (+Z). So the view continues through, and
 *    the clip plane of the virtual view is B's own plane with the eye behind it, which is
 *    what the oblique projection needs (C.w < 0). Seen as a covector, A's plane maps to B's
 *    plane reversed. */
static void test_portal(void)
{
    for (int i = 0; i < 2000; i++) {
        double ra[9], rb[9], ta[3], tb[3];
        rnd_rotation(ra);
        rnd_rotation(rb);
        for (int j = 0; j < 3; j++) {
            ta[j] = rnd_range(-20, 20);
            tb[j] = rnd_range(-20, 20);
        }
        double s = i % 2 ? 1.0 : exp(rnd_range(log(0.25), log(4)));
        float wa[16], wb[16], x[16];
        make_frame(ra, ta, 1.0, wa);
        make_frame(rb, tb, s, wb);
        CHECK_OK(limen_portal_matrix(wa, wb, x));
        double scale = 1 + 40 * s;   /* sizes of positions involved */

        double oa[3] = {wa[12], wa[13], wa[14]}, ob[3] = {wb[12], wb[13], wb[14]}, xo[3];
        mul_point(x, oa, xo);
        for (int j = 0; j < 3; j++)
            CHECK_NEAR(xo[j], ob[j], 16 * FEPS * scale);
        /* axes: A's X, Y, Z go to B's -X, +Y, -Z (B's axes carry its scale) */
        const double sign[3] = {-1, 1, -1};
        for (int ax = 0; ax < 3; ax++) {
            double da[3], db[3], xd[3];
            column(wa, ax, da);
            column(wb, ax, db);
            mul_dir(x, da, xd);
            for (int j = 0; j < 3; j++)
                CHECK_NEAR(xd[j], sign[ax] * db[j], 16 * FEPS * s);
        }
        CHECK(det3(x) > 0);
        CHECK_NEAR(det3(x), s * s * s, 32 * FEPS * s * s * s);

        /* a point in front of A lands behind B; the line of sight continues */
        for (int k = 0; k < 8; k++) {
            double loc[3] = {rnd_range(-3, 3), rnd_range(-3, 3), rnd_range(0.01, 5)};
            double p[3], xp[3], bl[3];
            mul_point(wa, loc, p);
            mul_point(x, p, xp);
            /* B-local coordinates of X p: W_B^-1 through B's orthonormal axes and scale */
            double rel[3] = {xp[0] - ob[0], xp[1] - ob[1], xp[2] - ob[2]};
            for (int ax = 0; ax < 3; ax++) {
                double db[3];
                column(wb, ax, db);
                bl[ax] = dot3(rel, db) / (s * s);
            }
            CHECK(bl[2] < 0);
            CHECK_NEAR(bl[0], -loc[0], 16 * FEPS * scale / s);
            CHECK_NEAR(bl[1], loc[1], 16 * FEPS * scale / s);
            CHECK_NEAR(bl[2], -loc[2], 16 * FEPS * scale / s);
            double into_a[3], zb[3], xv[3];
            column(wa, 2, into_a);
            for (int j = 0; j < 3; j++)
                into_a[j] = -into_a[j];
            column(wb, 2, zb);
            mul_dir(x, into_a, xv);
            CHECK(dot3(xv, zb) > 0.999999 * len3(xv) * len3(zb));   /* out of B's front */
        }
        /* A's plane (front +Z_A) maps to B's plane reversed. */
        double za[3], zb[3];
        column(wa, 2, za);
        column(wb, 2, zb);
        normalize3(zb);
        float ca[4] = {(float)za[0], (float)za[1], (float)za[2], (float)-dot3(za, oa)}, cx[4];
        CHECK_OK(limen_plane_transform(x, ca, cx));
        for (int j = 0; j < 3; j++)
            CHECK_NEAR(cx[j], -zb[j], 32 * FEPS);
        CHECK_NEAR(cx[3], dot3(zb, ob), 32 * FEPS * scale);
    }
    float id[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
    float flat[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1}, m[16];
    sentinel(m, 16);
    CHECK(limen_portal_matrix(flat, id, m) == LIMEN_ERR_DEGENERATE);
    float nanm[16] = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, NAN, 0, 1};
    CHECK(limen_portal_matrix(id, nanm, m) == LIMEN_ERR_ARG);
    CHECK(limen_portal_matrix(NULL, id, m) == LIMEN_ERR_ARG);
    CHECK(sentinel_intact(m, 16));
    /* Entering through a portal and coming back through its partner is the identity. */
    float back[16], x[16];
    double r[9], t[3] = {1, 2, 3};
    rnd_rotation(r);
    make_frame(r, t, 1.0, m);
    CHECK_OK(limen_portal_matrix(id, m, x));
    CHECK_OK(limen_portal_matrix(m, id, back));
    double xb[16];
    mat_mul(back, x, xb);
    for (int k = 0; k < 16; k++)
        CHECK_NEAR(xb[k], k % 5 == 0 ? 1.0 : 0.0, 32 * FEPS * 4);
}

/* ---------------------------------------------------------------- cameras */

static void test_look_at(void)
{
    for (int i = 0; i < 2000; i++) {
        double e[3], c[3], up[3], f[3];
        for (int j = 0; j < 3; j++) {
            e[j] = rnd_range(-20, 20);
            c[j] = rnd_range(-20, 20);
        }
        for (int j = 0; j < 3; j++)
            f[j] = c[j] - e[j];
        do
            rnd_unit(up);
        while (len3((double[3]){f[1] * up[2] - f[2] * up[1], f[2] * up[0] - f[0] * up[2],
                                f[0] * up[1] - f[1] * up[0]}) < 1e-2 * len3(f));
        float ef[3], cf[3], uf[3], v[16];
        for (int j = 0; j < 3; j++) {
            ef[j] = (float)e[j];
            cf[j] = (float)c[j];
            uf[j] = (float)(up[j] * rnd_range(0.1, 10));
            e[j] = ef[j];
            c[j] = cf[j];
            up[j] = uf[j];
        }
        CHECK_OK(limen_look_at(ef, cf, uf, v));
        double ve[3], vc[3], vu[3], dist = sqrt((c[0] - e[0]) * (c[0] - e[0]) +
                                                 (c[1] - e[1]) * (c[1] - e[1]) +
                                                 (c[2] - e[2]) * (c[2] - e[2]));
        mul_point(v, e, ve);
        mul_point(v, c, vc);
        mul_dir(v, up, vu);
        for (int j = 0; j < 3; j++)
            CHECK_NEAR(ve[j], 0.0, 16 * FEPS * 35);           /* eye -> origin */
        CHECK_NEAR(vc[0], 0.0, 16 * FEPS * 35);               /* center on -Z */
        CHECK_NEAR(vc[1], 0.0, 16 * FEPS * 35);
        CHECK_NEAR(vc[2], -dist, 16 * FEPS * 35);
        CHECK(vu[1] > 0);                                     /* up in the +Y half-plane */
        CHECK_NEAR(vu[0], 0.0, 16 * FEPS * len3(up));         /* ... of the y-z plane */
        CHECK_NEAR(det3(v), 1.0, 8 * FEPS);                   /* a rotation, no mirror */
        double mm[16];
        float vt[16];
        for (int r = 0; r < 3; r++)
            for (int k = 0; k < 3; k++)
                vt[k * 4 + r] = v[r * 4 + k];
        for (int k = 0; k < 3; k++) {
            vt[k * 4 + 3] = 0;
            vt[12 + k] = 0;
        }
        vt[15] = 1;
        mat_mul(vt, v, mm);   /* R^T R = I on the 3x3 part */
        for (int r = 0; r < 3; r++)
            for (int k = 0; k < 3; k++)
                CHECK_NEAR(mm[k * 4 + r], r == k ? 1.0 : 0.0, 8 * FEPS);
    }
    float v[16];
    sentinel(v, 16);
    float e[3] = {1, 2, 3};
    CHECK(limen_look_at(e, e, (float[3]){0, 1, 0}, v) == LIMEN_ERR_DEGENERATE);
    CHECK(limen_look_at(e, (float[3]){1, 5, 3}, (float[3]){0, 1, 0}, v) == LIMEN_ERR_DEGENERATE);
    CHECK(limen_look_at(e, (float[3]){1, -5, 3}, (float[3]){0, 2, 0}, v) == LIMEN_ERR_DEGENERATE);
    CHECK(limen_look_at(e, (float[3]){2, 4, 5}, (float[3]){-3, -6, -6}, v) ==
          LIMEN_ERR_DEGENERATE);
    CHECK(limen_look_at(e, (float[3]){0, 0, 0}, (float[3]){0, 0, 0}, v) == LIMEN_ERR_DEGENERATE);
    CHECK(limen_look_at(e, (float[3]){0, 0, NAN}, (float[3]){0, 1, 0}, v) == LIMEN_ERR_ARG);
    CHECK(limen_look_at(e, (float[3]){0, 0, 0}, (float[3]){0, INFINITY, 0}, v) == LIMEN_ERR_ARG);
    CHECK(limen_look_at(NULL, e, (float[3]){0, 1, 0}, v) == LIMEN_ERR_ARG);
    CHECK(limen_look_at(e, (float[3]){0, 0, 0}, (float[3]){0, 1, 0}, NULL) == LIMEN_ERR_ARG);
    CHECK(sentinel_intact(v, 16));
}

static const limen_depth_range ranges[3] = {LIMEN_DEPTH_NO, LIMEN_DEPTH_ZO,
                                            LIMEN_DEPTH_ZO_REVERSED};
static const double z_near_ndc[3] = {-1, 0, 1}, z_far_ndc[3] = {1, 1, 0};

static void rnd_lens(double *fovy, double *aspect, double *zn, double *zf)
{
    *fovy = rnd_range(0.2, 2.8);
    *aspect = exp(rnd_range(log(0.3), log(3)));
    *zn = exp(rnd_range(log(0.01), log(1)));
    *zf = *zn * exp(rnd_range(log(2), log(1e4)));
}

static void to_ndc(const float p[16], const double x[3], double ndc[3])
{
    double h[4] = {x[0], x[1], x[2], 1}, c[4];
    mul4(p, h, c);
    for (int i = 0; i < 3; i++)
        ndc[i] = c[i] / c[3];
}

static void test_perspective(void)
{
    for (int r = 0; r < 3; r++) {
        for (int i = 0; i < 1000; i++) {
            double fovy, aspect, zn, zf;
            rnd_lens(&fovy, &aspect, &zn, &zf);
            float p[16];
            float ffov = (float)fovy, fasp = (float)aspect, fn = (float)zn, ff = (float)zf;
            CHECK_OK(limen_perspective(ffov, fasp, fn, ff, ranges[r], p));
            double ty = tan(ffov / 2.0), tx = ty * fasp, ndc[3];
            const double depth[2] = {fn, ff}, want[2] = {z_near_ndc[r], z_far_ndc[r]};
            for (int k = 0; k < 2; k++) {
                double dz = depth[k];
                double a = rnd_range(-1, 1), b = rnd_range(-1, 1);
                to_ndc(p, (double[3]){a * tx * dz, b * ty * dz, -dz}, ndc);
                CHECK_NEAR(ndc[2], want[k], 8 * FEPS);
                CHECK_NEAR(ndc[0], a, 8 * FEPS);
                CHECK_NEAR(ndc[1], b, 8 * FEPS);
                /* the fovy edges */
                to_ndc(p, (double[3]){0, ty * dz, -dz}, ndc);
                CHECK_NEAR(ndc[1], 1.0, 8 * FEPS);
                to_ndc(p, (double[3]){0, -ty * dz, -dz}, ndc);
                CHECK_NEAR(ndc[1], -1.0, 8 * FEPS);
                to_ndc(p, (double[3]){tx * dz, 0, -dz}, ndc);
                CHECK_NEAR(ndc[0], 1.0, 8 * FEPS);
            }
            /* depth is monotonic between near and far, towards the far value */
            double prev = z_near_ndc[r];
            for (int k = 1; k <= 8; k++) {
                double dz = zn * pow(zf / zn, k / 8.0);
                to_ndc(p, (double[3]){0, 0, -dz}, ndc);
                double step = (ndc[2] - prev) * (z_far_ndc[r] - z_near_ndc[r]);
                CHECK(step > -8 * FEPS);
                prev = ndc[2];
            }
            CHECK(p[11] == -1.0f && p[15] == 0.0f);   /* w = -z: distance in front of the eye */
        }
    }
    float p[16];
    sentinel(p, 16);
    const float bad[][4] = {
        {0, 1, 0.1f, 10},        {-1, 1, 0.1f, 10},        {GLM_PIf, 1, 0.1f, 10},
        {4, 1, 0.1f, 10},        {NAN, 1, 0.1f, 10},       {1, 0, 0.1f, 10},
        {1, -1, 0.1f, 10},       {1, INFINITY, 0.1f, 10},  {1, 1, 0, 10},
        {1, 1, -0.1f, 10},       {1, 1, 10, 10},           {1, 1, 10, 5},
        {1, 1, 0.1f, INFINITY},  {1, 1, 0.1f, NAN},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        CHECK_MSG(limen_perspective(bad[i][0], bad[i][1], bad[i][2], bad[i][3],
                                    LIMEN_DEPTH_NO, p) == LIMEN_ERR_ARG, "bad lens %zu", i);
    CHECK(limen_perspective(1, 1, 0.1f, 10, (limen_depth_range)7, p) == LIMEN_ERR_ARG);
    CHECK(limen_perspective(1, 1, 0.1f, 10, LIMEN_DEPTH_NO, NULL) == LIMEN_ERR_ARG);
    CHECK(sentinel_intact(p, 16));
}

static void test_projection_planes(void)
{
    for (int r = 0; r < 3; r++) {
        for (int i = 0; i < 300; i++) {
            double fovy, aspect, zn, zf;
            rnd_lens(&fovy, &aspect, &zn, &zf);
            float p[16], np[4], fp[4];
            CHECK_OK(limen_perspective((float)fovy, (float)aspect, (float)zn, (float)zf,
                                       ranges[r], p));
            CHECK_OK(limen_projection_planes(p, ranges[r], np, fp));
            double nn[3] = {np[0], np[1], np[2]}, fn[3] = {fp[0], fp[1], fp[2]};
            CHECK_NEAR(len3(nn), 1.0, 4 * FEPS);
            CHECK_NEAR(len3(fn), 1.0, 4 * FEPS);
            double a = rnd_range(-1, 1) * tan(fovy / 2) * aspect, b = rnd_range(-1, 1) * tan(fovy / 2);
            double on_near[3] = {a * zn, b * zn, -zn}, on_far[3] = {a * zf, b * zf, -zf};
            double mid = sqrt(zn * zf), inside[3] = {a * mid, b * mid, -mid};
            /* Float entries. NO and ZO keep the far plane only as row4 - row3, where row3's
             * depth coefficient is -1 - O(n/f): the cancellation leaves the far distance a
             * relative error of ~FEPS f/n (ZO_REVERSED stores it directly: one of the
             * reasons it is the precise one). */
            CHECK_NEAR(plane_eval(np, on_near), 0.0, 8 * FEPS * zn);
            CHECK_NEAR(plane_eval(fp, on_far), 0.0, 8 * FEPS * zf * (r == 2 ? 1 : 1 + zf / zn));
            CHECK(plane_eval(np, inside) > 0 && plane_eval(fp, inside) > 0);   /* face inside */
            CHECK(plane_eval(np, (double[3]){0, 0, 0}) < 0);   /* the eye is before the near plane */
        }
    }
    float p[16] = {0}, np[4], fp[4];
    CHECK(limen_projection_planes(p, LIMEN_DEPTH_NO, np, fp) == LIMEN_ERR_DEGENERATE);
    p[0] = NAN;
    CHECK(limen_projection_planes(p, LIMEN_DEPTH_NO, np, fp) == LIMEN_ERR_ARG);
    CHECK(limen_projection_planes(NULL, LIMEN_DEPTH_NO, np, fp) == LIMEN_ERR_ARG);
    CHECK(limen_projection_planes(p, LIMEN_DEPTH_NO, NULL, fp) == LIMEN_ERR_ARG);
}

/* ---------------------------------------------------------------- oblique projection */

/* Clip coordinates of a view-space point. */
static void to_clip(const float p[16], const double x[3], double c[4])
{
    double h[4] = {x[0], x[1], x[2], 1};
    mul4(p, h, c);
}

/* How far a clip-space point lies outside each side of the clip volume of range r, in units
 * of w (<= 0: on the inner side): the x and y sides, the near and the far side. */
typedef struct excess { double xy, near, far; } excess;

static excess clip_excess(const double c[4], int r)
{
    double w = c[3];
    excess e;
    e.xy = fmax(fabs(c[0]) - w, fabs(c[1]) - w) / w;
    switch (r) {
    case 0:  e.near = (-w - c[2]) / w; e.far = (c[2] - w) / w; break;
    case 1:  e.near = -c[2] / w;       e.far = (c[2] - w) / w; break;
    default: e.near = (c[2] - w) / w;  e.far = -c[2] / w;      break;
    }
    return e;
}

/* Largest excess over all sides (or over near and far only). */
static double outside(const double c[4], int r, bool depth_only)
{
    excess e = clip_excess(c, r);
    double o = fmax(e.near, e.far);
    return depth_only ? o : fmax(o, e.xy);
}

/* Oblique case number i: a random lens and a random clip plane through a point inside the
 * frustum, oriented so the eye is behind it. Some normals lie near an axis. */
static void oblique_case(int i, double lens[4], double c[4])
{
    rnd_lens(&lens[0], &lens[1], &lens[2], &lens[3]);
    lens[3] = fmin(lens[3], lens[2] * 2e3);
    double ty = tan(lens[0] / 2), tx = ty * lens[1];
    for (;;) {
        double n[3];
        if (i % 4 == 0) {   /* near an axis: +-X, +-Y, +-Z tilted by 1e-7 .. 1e-3 */
            memset(n, 0, sizeof n);
            n[(i / 4) % 3] = (i / 12) % 2 ? 1 : -1;
            double tilt = exp(rnd_range(log(1e-7), log(1e-3)));
            n[((i / 4) + 1) % 3] += tilt * rnd_range(-1, 1);
            n[((i / 4) + 2) % 3] += tilt * rnd_range(-1, 1);
            normalize3(n);
        } else {
            rnd_unit(n);
        }
        double z = lens[2] * pow(lens[3] / lens[2], rnd_range(0.02, 0.98));
        double p0[3] = {rnd_range(-0.95, 0.95) * tx * z, rnd_range(-0.95, 0.95) * ty * z, -z};
        double d = -dot3(n, p0);
        if (fabs(d) < 1e-3 * lens[2])
            continue;   /* the refusal zone is tested on its own */
        double sg = d < 0 ? 1 : -1;
        for (int j = 0; j < 3; j++)
            c[j] = sg * n[j];
        c[3] = sg * d;
        return;
    }
}

static void test_oblique(void)
{
    double worst_plane = 0;
    long n_on_c = 0, n_front = 0, n_behind = 0, n_far_visible = 0;
    for (int r = 0; r < 3; r++) {
        for (int i = 0; i < 3000; i++) {
            double lens[4], c[4];
            oblique_case(i, lens, c);
            float p[16], o[16], cf[4] = {(float)c[0], (float)c[1], (float)c[2], (float)c[3]};
            CHECK_OK(limen_perspective((float)lens[0], (float)lens[1], (float)lens[2],
                                       (float)lens[3], ranges[r], p));
            limen_status st = limen_oblique_projection(p, cf, ranges[r], o);
            CHECK_MSG(st == LIMEN_OK, "range %d case %d: status %d", r, i, st);
            if (st != LIMEN_OK)
                continue;
            /* The float plane is the one asked for: renormalise it in double. */
            double cn[4] = {cf[0], cf[1], cf[2], cf[3]}, l = len3(cn);
            for (int j = 0; j < 4; j++)
                cn[j] /= l;

            /* 1. The extracted near plane is C with a positive factor. Each component is
             * compared after normalising |n| = 1, d relative to max(|c.w|, near). The
             * matrix holds a C in float beside row4, so the error is ~FEPS max(1, 1/a);
             * a = 2 w(Q) / C.Q >= 0.1 for these lenses: 1e-5 (~80 FEPS) bounds it. */
            float np[4], fp[4];
            CHECK_OK(limen_projection_planes(o, ranges[r], np, fp));
            double e = 0;
            for (int j = 0; j < 3; j++)
                e = fmax(e, fabs(np[j] - cn[j]));
            e = fmax(e, fabs(np[3] - cn[3]) / fmax(fabs(cn[3]), lens[2]));
            worst_plane = fmax(worst_plane, e);
            CHECK_MSG(e <= 1e-5, "range %d case %d: near plane off C by %g", r, i, e);

            /* Scale of float rounding in this matrix: the largest entry of row 3 and 4. */
            double big = 1;
            for (int k = 0; k < 4; k++)
                big = fmax(big, fmax(fabs(o[k * 4 + 2]), fabs(o[k * 4 + 3])));
            /* The original frustum is the float matrix's own: its x, y slopes and its near
             * and far distances solved from its entries (z_ndc = (A z + B) / -z). */
            double tx = 1.0 / p[0], ty = 1.0 / p[5];
            double zn = (double)p[14] / (p[10] + z_near_ndc[r]);
            double zf = (double)p[14] / (p[10] + z_far_ndc[r]);

            /* 2. Points of C seen inside the original view land on the near depth. */
            for (int k = 0; k < 16; k++) {
                double dir[3] = {rnd_range(-1, 1) * tx, rnd_range(-1, 1) * ty, -1};
                double t = -cn[3] / dot3(cn, dir);   /* ray from the eye hits C at t dir */
                if (!(t > zn && t < zf))
                    continue;
                double x[3] = {t * dir[0], t * dir[1], t * dir[2]}, cl[4];
                n_on_c++;
                to_clip(o, x, cl);
                double lenx = len3(x);
                CHECK_NEAR(cl[2] / cl[3], z_near_ndc[r], 8 * FEPS * big * (1 + lenx / cl[3]));
                CHECK(fabs(cl[0]) <= cl[3] * (1 + 8 * FEPS) && fabs(cl[1]) <= cl[3] * (1 + 8 * FEPS));
            }

            /* 3. The original far face stays inside the new far plane: all four corners
             * are on its inner side (the one through Q lies on it), and those in front of C
             * are inside the whole new volume. (Corners behind C are cut by the new near
             * plane, as they must be.) */
            for (int k = 0; k < 4; k++) {
                double x[3] = {(k & 1 ? 1 : -1) * tx * zf, (k & 2 ? 1 : -1) * ty * zf, -zf}, cl[4];
                to_clip(o, x, cl);
                double tol = 8 * FEPS * big * (1 + len3(x) / cl[3]);
                excess ex = clip_excess(cl, r);
                CHECK_MSG(ex.far <= tol && ex.xy <= tol,
                          "range %d case %d: far corner %d beyond the far plane by %g", r, i, k,
                          ex.far);
                if (dot3(cn, x) + cn[3] >= 0 && ++n_far_visible)
                    CHECK_MSG(ex.near <= tol, "range %d case %d: visible far corner %d cut", r,
                              i, k);
            }

            /* 4. Points of the original frustum: in front of C inside, behind C clipped. */
            for (int k = 0; k < 32; k++) {
                double z = zn * pow(zf / zn, rnd());
                double x[3] = {rnd_range(-1, 1) * tx * z, rnd_range(-1, 1) * ty * z, -z}, cl[4];
                double side = dot3(cn, x) + cn[3];
                to_clip(o, x, cl);
                double tol = 8 * FEPS * big * (1 + len3(x) / cl[3]);
                /* |side| below the rounding band of C.x is left undecided */
                if (side > 1e-5 * (len3(x) + fabs(cn[3])) && ++n_front)
                    CHECK_MSG(outside(cl, r, false) <= tol, "range %d case %d: visible point out by %g",
                              r, i, outside(cl, r, false));
                else if (side < -1e-5 * (len3(x) + fabs(cn[3])) && ++n_behind)
                    CHECK_MSG(outside(cl, r, true) > 0, "range %d case %d: hidden point kept", r, i);
            }
        }
    }
    /* the sampling really reaches each kind of point */
    CHECK(n_on_c > 10000 && n_front > 50000 && n_behind > 50000 && n_far_visible > 10000);
    printf("     oblique: %ld points on C, %ld in front, %ld behind, %ld visible far corners;"
           " worst near-plane deviation from C %.3g\n", n_on_c, n_front, n_behind,
           n_far_visible, worst_plane);
}

static void test_oblique_refused(void)
{
    for (int r = 0; r < 3; r++) {
        float p[16], o[16];
        float zn = 0.1f, zf = 100;
        CHECK_OK(limen_perspective(1.0f, 1.5f, zn, zf, ranges[r], p));
        /* A head-on plane 2 units ahead whose front faces away from the eye: fine. */
        float ok[4] = {0, 0, -1, -2};
        CHECK_OK(limen_oblique_projection(p, ok, ranges[r], o));
        const float refused[][4] = {
            {0, 0, -1, 0},                 /* eye on the plane */
            {0, 0, 1, 2},                  /* eye in front of it (and the frustum behind) */
            {0, 0.6f, -0.8f, 0.5f},        /* eye in front */
            {0, 0, -1, -1e-9f},            /* eye closer than eps * near: refused */
            {0, 0, -1, -2 * zf},           /* behind the eye, but the plane is beyond far */
            {1, 0, 0, -200},               /* x = 200: beside the frustum (|x| <= 82 there) */
            {0, 0, 0, -1},                 /* zero normal */
        };
        /* The fifth and sixth have the eye behind the plane but no part of the frustum in
         * front of it: C.Q < 0, a would be negative, refused rather than flipped. */
        for (size_t i = 0; i < sizeof refused / sizeof refused[0]; i++) {
            float c[4];
            memcpy(c, refused[i], sizeof c);
            sentinel(o, 16);
            limen_status st = limen_oblique_projection(p, c, ranges[r], o);
            CHECK_MSG(st == LIMEN_ERR_DEGENERATE, "range %d refused[%zu]: %d", r, i, st);
            CHECK(sentinel_intact(o, 16));
        }
        /* Just outside the eps band it works and is still right. */
        float close[4] = {0, 0.6f, -0.8f, -1e-5f * zn}, np[4], fp[4];
        CHECK_OK(limen_oblique_projection(p, close, ranges[r], o));
        CHECK_OK(limen_projection_planes(o, ranges[r], np, fp));
        for (int j = 0; j < 3; j++)
            CHECK_NEAR(np[j], close[j], 8 * FEPS);
        CHECK_NEAR(np[3], close[3], 8 * FEPS * zn);
        sentinel(o, 16);
        CHECK(limen_oblique_projection(p, (float[4]){0, NAN, -1, -1}, ranges[r], o) == LIMEN_ERR_ARG);
        CHECK(limen_oblique_projection(p, (float[4]){0, 0, -1, -INFINITY}, ranges[r], o) ==
              LIMEN_ERR_ARG);
        CHECK(limen_oblique_projection(NULL, ok, ranges[r], o) == LIMEN_ERR_ARG);
        CHECK(limen_oblique_projection(p, NULL, ranges[r], o) == LIMEN_ERR_ARG);
        CHECK(limen_oblique_projection(p, ok, (limen_depth_range)9, o) == LIMEN_ERR_ARG);
        CHECK(sentinel_intact(o, 16));
    }
}

/* The mirror case end to end (DESIGN.md): camera at the origin looking down -Z (V = I), a
 * mirror facing it; the virtual view is V' = V X^-1 = M (a reflection is its own inverse),
 * the clip plane in its space C_view = (V'^-1)^T C_world has the virtual eye behind it, and
 * the oblique projection keeps exactly the world in front of the mirror. */
static void test_oblique_mirror_view(void)
{
    int tried = 0;
    for (int i = 0; i < 500; i++) {
        double n[3];
        rnd_unit(n);
        double z = rnd_range(3, 10), p0[3] = {rnd_range(-1, 1), rnd_range(-1, 1), -z};
        if (dot3(n, p0) > 0)
            for (int j = 0; j < 3; j++)
                n[j] = -n[j];                /* the mirror faces the eye */
        if (n[2] < 0.3)
            continue;                        /* and is seen at a reasonable angle */
        tried++;
        float c[4] = {(float)n[0], (float)n[1], (float)n[2], (float)-dot3(n, p0)};
        float m[16], cv[4], proj[16], o[16];
        CHECK_OK(limen_mirror_matrix(c, m));
        CHECK_OK(limen_plane_transform(m, c, cv));   /* (V'^-1)^T C with V' = M */
        CHECK(cv[3] < 0);                            /* the virtual eye is behind it */
        int r = i % 3;
        CHECK_OK(limen_perspective(1.0f, 1.3f, 0.1f, 100, ranges[r], proj));
        if (limen_oblique_projection(proj, cv, ranges[r], o) != LIMEN_OK) {
            CHECK_MSG(0, "mirror case %d refused", i);
            continue;
        }
        for (int k = 0; k < 64; k++) {
            double x[3] = {rnd_range(-60, 60), rnd_range(-60, 60), rnd_range(-60, 60)};
            double y[3], cl[4], cl0[4];
            mul_point(m, x, y);               /* view-space position in the virtual view */
            to_clip(proj, y, cl0);
            if (outside(cl0, r, false) > -1e-3)
                continue;                     /* only points well inside the plain view */
            to_clip(o, y, cl);
            double side = plane_eval(c, x);   /* world side of the mirror */
            if (side > 1e-3)
                CHECK_MSG(outside(cl, r, false) <= 1e-4, "mirror case %d: visible point lost", i);
            else if (side < -1e-3)
                CHECK_MSG(outside(cl, r, true) > 0, "mirror case %d: point behind kept", i);
        }
    }
    CHECK(tried > 100);
}

/* ---------------------------------------------------------------- internal helpers */

static bool same_mat(mat4 x, mat4 y) { return memcmp(x, y, sizeof(mat4)) == 0; }

/* Destination last and safe when it aliases an input (cglm's rule): each function gives the
 * same bits written over its input as into a separate output. */
static void test_internal_aliasing(void)
{
    for (int i = 0; i < 50; i++) {
        float wa[16], wb[16];
        rnd_affine(wa);
        rnd_affine(wb);
        mat4 a, b, sep, al;
        limen__mat4_from_array(wa, a);
        limen__mat4_from_array(wb, b);
        double n[3];
        rnd_unit(n);
        vec4 c = {(float)n[0], (float)n[1], (float)n[2], (float)rnd_range(-5, 5)}, cs, ca;

        glm_vec4_copy(c, ca);
        CHECK_OK(limen__plane_transform(a, c, cs));
        CHECK_OK(limen__plane_transform(a, ca, ca));
        CHECK(memcmp(cs, ca, sizeof cs) == 0);

        glm_mat4_copy(a, al);
        CHECK_OK(limen__portal_mat4(a, b, sep));
        CHECK_OK(limen__portal_mat4(al, b, al));
        CHECK(same_mat(sep, al));
        glm_mat4_copy(b, al);
        CHECK_OK(limen__portal_mat4(a, al, al));
        CHECK(same_mat(sep, al));

        glm_mat4_copy(a, al);
        CHECK_OK(limen__mirror_mat4_node(a, sep));
        CHECK_OK(limen__mirror_mat4_node(al, al));
        CHECK(same_mat(sep, al));

        glm_mat4_copy(a, al);
        CHECK_OK(limen__mat4_inverse(a, sep));
        CHECK_OK(limen__mat4_inverse(al, al));
        CHECK(same_mat(sep, al));

        mat4 pr;
        CHECK_OK(limen__perspective(1.0f, 1.2f, 0.1f, 50, LIMEN_DEPTH_ZO_REVERSED, pr));
        vec4 cv = {0, 0.3f, -0.9539392f, -2};
        glm_mat4_copy(pr, al);
        CHECK_OK(limen__oblique(pr, cv, LIMEN_DEPTH_ZO_REVERSED, sep));
        CHECK_OK(limen__oblique(al, cv, LIMEN_DEPTH_ZO_REVERSED, al));
        CHECK(same_mat(sep, al));
    }
}

/* Clipping a convex polygon by a plane (homogeneous points): what is kept, where the cut
 * falls, and the cap on what is written. */
static void test_clip_polygon(void)
{
    /* the unit square at z = 0, w = 1; keep x <= 0.25 */
    const double sq[4][4] = { { 0, 0, 0, 1 }, { 1, 0, 0, 1 }, { 1, 1, 0, 1 }, { 0, 1, 0, 1 } };
    const double cut[4] = { -1, 0, 0, 0.25 };
    double out[8][4];
    int n = limen_clip_polygon(&sq[0][0], 4, cut, &out[0][0], 8);
    CHECK(n == 4);
    double area = 0;
    for (int i = 0; i < n; i++) {
        CHECK(out[i][0] <= 0.25 + 1e-12 && out[i][3] == 1);
        const double *a = out[i], *b = out[(i + 1) % n];
        area += a[0] * b[1] - b[0] * a[1];
    }
    CHECK_NEAR(0.5 * area, 0.25, 1e-12);    /* the same winding, a quarter of the square */
    /* a corner cut off leaves a pentagon; a plane missing it keeps all; one beyond it, none */
    const double corner[4] = { -1, -1, 0, 1.5 }, all[4] = { 0, 0, 0, 1 }, none[4] = { 1, 0, 0, -2 };
    CHECK(limen_clip_polygon(&sq[0][0], 4, corner, &out[0][0], 8) == 5);
    CHECK(limen_clip_polygon(&sq[0][0], 4, all, &out[0][0], 8) == 4);
    CHECK(memcmp(out, sq, sizeof sq) == 0);
    CHECK(limen_clip_polygon(&sq[0][0], 4, none, &out[0][0], 8) < 3);
    /* clip space: w scales the test (x <= w), as the frustum's sides need */
    const double far_pt[3][4] = { { 0, 0, 0, 1 }, { 4, 0, 0, 2 }, { 0, 4, 0, 2 } };
    const double right[4] = { -1, 0, 0, 1 };
    n = limen_clip_polygon(&far_pt[0][0], 3, right, &out[0][0], 8);
    CHECK(n == 4);
    for (int i = 0; i < n; i++)
        CHECK(out[i][0] <= out[i][3] + 1e-12);
    /* at most cap points are written */
    double small[4][4];
    memset(small, 0x7f, sizeof small);
    CHECK(limen_clip_polygon(&sq[0][0], 4, corner, &small[0][0], 3) == 3);
    CHECK(limen_clip_polygon(&sq[0][0], 4, corner, &small[0][0], 0) == 0);
    CHECK(limen_clip_polygon(NULL, 4, corner, &small[0][0], 3) == 0);
    CHECK(limen_clip_polygon(&sq[0][0], 2, corner, &small[0][0], 3) == 0);
    unsigned char tail[sizeof small[3]];
    memset(tail, 0x7f, sizeof tail);
    CHECK(memcmp(small[3], tail, sizeof tail) == 0);
}

static const check_case cases[] = {
    {"plane_from_points", test_plane_from_points},
    {"plane_degenerate", test_plane_degenerate},
    {"plane_from_point_normal", test_plane_from_point_normal},
    {"plane_transform", test_plane_transform},
    {"mirror_properties", test_mirror_properties},
    {"mirror_node_form", test_mirror_node_form},
    {"mirror_seed_method", test_mirror_seed_method},
    {"mirror_args", test_mirror_args},
    {"portal", test_portal},
    {"look_at", test_look_at},
    {"perspective", test_perspective},
    {"projection_planes", test_projection_planes},
    {"oblique", test_oblique},
    {"oblique_refused", test_oblique_refused},
    {"oblique_mirror_view", test_oblique_mirror_view},
    {"internal_aliasing", test_internal_aliasing},
    {"clip_polygon", test_clip_polygon},
    {0, 0},
};

int main(int argc, char **argv)
{
    return check_run(argc, argv, cases);
}
