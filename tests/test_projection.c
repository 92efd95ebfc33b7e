/* test_projection.c - cameras, projections and the oblique near plane of limen.h and
 * src/core/lmath.h, checked by properties, as test_math.c checks planes and mirrors.
 * Every check states a geometric fact (a point on a plane stays on it, a reflection is an
 * involution, the oblique near plane is the clip plane, ...) and evaluates it in double from
 * the float matrices the library returns; no expected number is copied from the code.
 * Tolerances are written as multiples of float rounding (FEPS = 2^-23 ~ 1.2e-7) times the
 * size of the quantities involved; each says where its factor comes from.
 *
 * Random cases come from splitmix64 with a fixed seed, so a failure reproduces.
 */
#include "math_check.h"

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

/* The mirror case end to end (docs/DESIGN.md): camera at the origin looking down -Z (V = I), a
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

static double plane_eval4(const double pl[4], const double q[4])
{
    return pl[0] * q[0] + pl[1] * q[1] + pl[2] * q[2] + pl[3] * q[3];
}

/* limen__frustum_planes: one function for every frustum's planes. A point carried to clip
 * space lies inside the window (x/w, y/w within it) and the depth range exactly when every
 * plane keeps it; the planes of the whole window pass through the frustum's edges; near and
 * far are limen_projection_planes' (normalised); on view x projection the planes are the
 * world's. */
static void test_frustum_planes(void)
{
    for (int r = 0; r < 3; r++) {
        for (int i = 0; i < 300; i++) {
            double fovy, aspect, zn, zf;
            rnd_lens(&fovy, &aspect, &zn, &zf);
            float pf[16], np[4], fp[4];
            CHECK_OK(limen_perspective((float)fovy, (float)aspect, (float)zn, (float)zf,
                                       ranges[r], pf));
            CHECK_OK(limen_projection_planes(pf, ranges[r], np, fp));
            double p[16], planes[6][4];
            for (int k = 0; k < 16; k++)
                p[k] = pf[k];
            /* a window inside [-1, 1]^2, as a scissor rectangle makes */
            double x0 = rnd_range(-1, 0.9), y0 = rnd_range(-1, 0.9);
            double win[4] = { x0, rnd_range(x0 + 0.05, 1), y0, rnd_range(y0 + 0.05, 1) };
            limen__frustum_planes(p, win, ranges[r], planes);
            for (int k = 4; k < 6; k++) {     /* near and far: the same planes, unnormalised */
                const float *want = k == 4 ? np : fp;
                double len = len3(planes[k]);
                for (int c = 0; c < 4; c++)
                    CHECK_NEAR(planes[k][c] / len, want[c], 8 * FEPS * (1 + fabs(want[c])));
            }
            for (int t = 0; t < 20; t++) {
                /* an eye-space point between near and far, in or out of the window */
                double z = -rnd_range(zn * 1.01, zf * 0.99);
                double ty = tan(fovy / 2), tx = ty * aspect;
                double q[4] = { rnd_range(-1.5, 1.5) * tx * -z, rnd_range(-1.5, 1.5) * ty * -z,
                                z, 1 }, c[4] = { 0, 0, 0, 0 };
                for (int row = 0; row < 4; row++)
                    for (int col = 0; col < 4; col++)
                        c[row] += p[col * 4 + row] * q[col];
                double xn = c[0] / c[3], yn = c[1] / c[3];
                /* away from the edges by more than rounding */
                double margin = 1e-9;
                if (fabs(xn - win[0]) < margin || fabs(xn - win[1]) < margin ||
                    fabs(yn - win[2]) < margin || fabs(yn - win[3]) < margin)
                    continue;
                bool in = xn > win[0] && xn < win[1] && yn > win[2] && yn < win[3];
                bool kept = true;
                for (int k = 0; k < 6; k++)
                    kept = kept && plane_eval4(planes[k], q) >= 0;
                CHECK_MSG(in == kept, "range %d: (%g, %g) in [%g, %g] x [%g, %g]: kept %d", r,
                          xn, yn, win[0], win[1], win[2], win[3], kept);
            }
        }
    }
    /* the whole window (NULL): a point on the frustum's right edge at any depth is on the
     * right plane; the sides pass through the eye */
    float pf[16];
    CHECK_OK(limen_perspective(1.0f, 1.5f, 0.1f, 100.0f, LIMEN_DEPTH_NO, pf));
    double p[16], planes[6][4];
    for (int k = 0; k < 16; k++)
        p[k] = pf[k];
    limen__frustum_planes(p, NULL, LIMEN_DEPTH_NO, planes);
    double tx = 1.0 / p[0], ty = 1.0 / p[5];
    for (int k = 0; k < 4; k++)
        CHECK(planes[k][3] == 0);
    for (double z = -0.5; z > -90; z *= 3) {
        double edge[4][4] = { { -tx * -z, 0, z, 1 }, { tx * -z, 0, z, 1 },
                              { 0, -ty * -z, z, 1 }, { 0, ty * -z, z, 1 } };
        for (int k = 0; k < 4; k++)
            CHECK_NEAR(plane_eval4(planes[k], edge[k]) / len3(planes[k]), 0.0, 1e-12 * -z);
    }
}

static const check_case cases[] = {
    {"look_at", test_look_at},
    {"perspective", test_perspective},
    {"projection_planes", test_projection_planes},
    {"frustum_planes", test_frustum_planes},
    {"oblique", test_oblique},
    {"oblique_refused", test_oblique_refused},
    {"oblique_mirror_view", test_oblique_mirror_view},
    {"internal_aliasing", test_internal_aliasing},
    {0, 0},
};

int main(int argc, char **argv)
{
    return check_run(argc, argv, cases);
}
