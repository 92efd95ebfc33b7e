/* test_math.c - planes, mirror and portal matrices of limen.h and src/core/lmath.h, checked
 * by properties (cameras and projections: test_projection.c).
 *
 * Every check states a geometric fact (a point on a plane stays on it, a reflection is an
 * involution, the oblique near plane is the clip plane, ...) and evaluates it in double from
 * the float matrices the library returns; no expected number is copied from the code.
 * Tolerances are written as multiples of float rounding (FEPS = 2^-23 ~ 1.2e-7) times the
 * size of the quantities involved; each says where its factor comes from.
 *
 * Random cases come from splitmix64 with a fixed seed, so a failure reproduces.
 */
#include "core/dmath.h"
#include "core/testing.h"
#include "math_check.h"

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

/* The planner's and the sweeps' points (limen__d_clip3) are clipped as the renderer's
 * homogeneous ones (limen__d_clip4, behind limen_clip_polygon) with w = 1: the same
 * vertices, to the last bit, and the same cap. */
static void test_clip_points(void)
{
    for (int i = 0; i < 2000; i++) {
        int n = 3 + (int)(rnd() * 6);
        double p3[8][3], p4[8][4], o3[9][3], o4[9][4], pl[4];
        for (int k = 0; k < n; k++) {
            for (int c = 0; c < 3; c++)
                p4[k][c] = p3[k][c] = rnd_range(-10, 10);
            p4[k][3] = 1;
        }
        rnd_unit(pl);
        pl[3] = rnd_range(-5, 5);
        int cap = i % 4 ? 8 : 3;
        int m3 = limen__d_clip3((const double(*)[3])p3, n, pl, o3, cap);
        int m4 = limen__d_clip4((const double(*)[4])p4, n, pl, o4, cap);
        CHECK(m3 == m4 && m3 <= cap + 1);
        bool same = true;
        for (int k = 0; k < m3; k++)
            same = same && !memcmp(o3[k], o4[k], sizeof o3[k]) && o4[k][3] == 1;
        CHECK_MSG(same, "case %d: the clippers differ", i);
        for (int k = 0; k < m3; k++)
            CHECK(pl[0] * o3[k][0] + pl[1] * o3[k][1] + pl[2] * o3[k][2] + pl[3] >= -1e-9);
    }
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
    {"clip_polygon", test_clip_polygon},
    {"clip_points", test_clip_points},
    {0, 0},
};

int main(int argc, char **argv)
{
    return check_run(argc, argv, cases);
}
