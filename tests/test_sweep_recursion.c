/* test_sweep_recursion.c - stability sweep 4: deep recursion.
 *
 * Two facing mirrors, two facing portals, and two facing portals with a 10-degree twist
 * (a screw: the tunnel turns as it goes), each placed by an arbitrary rigid motion G so
 * that no number is round. The virtual camera at depth k is the camera's world matrix
 * carried k times, C_k = X_{s_k} ... X_{s_1} C_0, and its view matrix V_k = V_{k-1} X^-1.
 * Compared, for k = 1 .. 64 (every k in FULL mode), with the EXACT answer, the closed form
 * in double (translation 4 j L for two reflections, a screw of k phi about the axis):
 *   f32, f32+ortho   V_k = V_{k-1} X^-1 in single precision (X rounded to float), without
 *                    and with re-orthonormalising the 3x3 part after each step;
 *   f64, f64+ortho   the same in double;
 *   library          limen's plan of the scene (nodes built from G in float) at depth k:
 *                    float inputs, double composition, float output.
 * Measured: the error of the virtual eye's position and of the view's 3x3 part (largest
 * entry) against the exact answer.
 * Asserted: the library's view at every depth matches the double composition of its own
 * inputs to float rounding of its output (8 ulps of the largest entry: no drift of its own);
 * its depth-64 camera is within 1e-3 units / 1e-5 of the exact one (what float inputs
 * allow); f64 drifts less than 1e-9 at depth 64; no NaN anywhere.
 * Output: recursion.csv.
 */
#include "sweeps/sweep.h"

#define KMAX 64

typedef struct config {
    const char *name;
    int mirrors;            /* 1: two mirrors; 0: two portals */
    double phi;             /* portals: twist of B about its normal, radians */
    double L;               /* half the distance between the surfaces */
    double size;            /* the surfaces are size x size */
} config;

/* G = T(t0) R(axis (1, 2, 3), 37 degrees) */
static void make_g(double g[16])
{
    double ax[3] = { 1, 2, 3 }, len = sqrt(14.0), a = 37 * M_PI / 180;
    for (int i = 0; i < 3; i++)
        ax[i] /= len;
    double c = cos(a), s = sin(a), t = 1 - c;
    double x = ax[0], y = ax[1], z = ax[2];
    double r[9] = { t * x * x + c,     t * x * y + s * z, t * x * z - s * y,    /* column 0 */
                    t * x * y - s * z, t * y * y + c,     t * y * z + s * x,    /* column 1 */
                    t * x * z + s * y, t * y * z - s * x, t * z * z + c };      /* column 2 */
    memset(g, 0, sizeof(double) * 16);
    for (int col = 0; col < 3; col++)
        for (int row = 0; row < 3; row++)
            g[col * 4 + row] = r[col * 3 + row];
    g[12] = 3.7, g[13] = -1.3, g[14] = 12.9, g[15] = 1;
}

static void ident(double m[16])
{
    memset(m, 0, sizeof(double) * 16);
    m[0] = m[5] = m[10] = m[15] = 1;
}

static void trans(double m[16], double x, double y, double z)
{
    ident(m);
    m[12] = x, m[13] = y, m[14] = z;
}

static void rot_z(double m[16], double a)
{
    ident(m);
    m[0] = cos(a), m[1] = sin(a), m[4] = -sin(a), m[5] = cos(a);
}

/* G * S * G^-1 */
static void conjugate(const double g[16], const double ginv[16], const double s[16], double out[16])
{
    limen__d_mul(g, s, out);
    limen__d_mul(out, ginv, out);
}

/* Frame-local surface matrices (before G): mirror 1 (z = -L, facing +z), mirror 2 (z = +L,
 * facing -z); portal A (z = -L, facing +z), B (z = +L, facing -z, twisted by phi). */
static void local_frames(const config *c, double wa[16], double wb[16])
{
    double t[16], r[16];
    trans(wa, 0, 0, -c->L);
    trans(t, 0, 0, c->L);
    rot_z(r, c->phi);
    limen__d_mul(t, r, wb);
    ident(r);
    r[0] = -1, r[10] = -1;               /* R_y(180): facing -z */
    limen__d_mul(wb, r, wb);
}

/* The exact carrying matrix M_k (world), closed form. */
static void exact_m(const config *c, const double g[16], const double ginv[16], int k, double m[16])
{
    double s[16];
    if (c->mirrors) {
        /* F1: z -> -2L - z, F2: z -> 2L - z; (F2 F1)^j = T(4 j L); M_2j+1 = F1 (F2 F1)^j */
        int j = k / 2;
        trans(s, 0, 0, 4.0 * j * c->L);
        if (k % 2) {
            double f1[16];
            ident(f1);
            f1[10] = -1, f1[14] = -2 * c->L;
            limen__d_mul(f1, s, s);
        }
    } else {
        /* X = T(0, 0, 2L) R_z(phi): X^k = T(0, 0, 2kL) R_z(k phi) */
        double r[16];
        trans(s, 0, 0, 2.0 * k * c->L);
        rot_z(r, k * c->phi);
        limen__d_mul(s, r, s);
    }
    conjugate(g, ginv, s, m);
}

/* Single-surface carrying matrices in world space: x[0] = through surface 1 (mirror 1 or
 * portal A), x[1] = through mirror 2 (mirrors only). */
static void exact_x(const config *c, const double g[16], const double ginv[16], double x[2][16])
{
    double s[16];
    if (c->mirrors) {
        ident(s);
        s[10] = -1, s[14] = -2 * c->L;
        conjugate(g, ginv, s, x[0]);
        ident(s);
        s[10] = -1, s[14] = 2 * c->L;
        conjugate(g, ginv, s, x[1]);
    } else {
        double r[16];
        trans(s, 0, 0, 2 * c->L);
        rot_z(r, c->phi);
        limen__d_mul(s, r, s);
        conjugate(g, ginv, s, x[0]);
        memcpy(x[1], x[0], sizeof(double) * 16);
    }
}

/* Re-orthonormalises the 3x3 part (Gram-Schmidt on columns, keeping the sign of det). */
static void ortho_d(double m[16])
{
    double *c0 = m, *c1 = m + 4, *c2 = m + 8;
    double det = c0[0] * (c1[1] * c2[2] - c1[2] * c2[1]) - c1[0] * (c0[1] * c2[2] - c0[2] * c2[1]) +
                 c2[0] * (c0[1] * c1[2] - c0[2] * c1[1]);
    double l = sqrt(c0[0] * c0[0] + c0[1] * c0[1] + c0[2] * c0[2]);
    for (int i = 0; i < 3; i++)
        c0[i] /= l;
    double d = c0[0] * c1[0] + c0[1] * c1[1] + c0[2] * c1[2];
    for (int i = 0; i < 3; i++)
        c1[i] -= d * c0[i];
    l = sqrt(c1[0] * c1[0] + c1[1] * c1[1] + c1[2] * c1[2]);
    for (int i = 0; i < 3; i++)
        c1[i] /= l;
    double sg = det < 0 ? -1 : 1;
    c2[0] = sg * (c0[1] * c1[2] - c0[2] * c1[1]);
    c2[1] = sg * (c0[2] * c1[0] - c0[0] * c1[2]);
    c2[2] = sg * (c0[0] * c1[1] - c0[1] * c1[0]);
}

static void ortho_f(float m[16])
{
    float *c0 = m, *c1 = m + 4, *c2 = m + 8;
    float det = c0[0] * (c1[1] * c2[2] - c1[2] * c2[1]) - c1[0] * (c0[1] * c2[2] - c0[2] * c2[1]) +
                c2[0] * (c0[1] * c1[2] - c0[2] * c1[1]);
    float l = sqrtf(c0[0] * c0[0] + c0[1] * c0[1] + c0[2] * c0[2]);
    for (int i = 0; i < 3; i++)
        c0[i] /= l;
    float d = c0[0] * c1[0] + c0[1] * c1[1] + c0[2] * c1[2];
    for (int i = 0; i < 3; i++)
        c1[i] -= d * c0[i];
    l = sqrtf(c1[0] * c1[0] + c1[1] * c1[1] + c1[2] * c1[2]);
    for (int i = 0; i < 3; i++)
        c1[i] /= l;
    float sg = det < 0 ? -1.0f : 1.0f;
    c2[0] = sg * (c0[1] * c1[2] - c0[2] * c1[1]);
    c2[1] = sg * (c0[2] * c1[0] - c0[0] * c1[2]);
    c2[2] = sg * (c0[0] * c1[1] - c0[1] * c1[0]);
}

static void mul_f(const float a[16], const float b[16], float c[16])
{
    float t[16];
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 4; i++)
            t[j * 4 + i] = a[i] * b[j * 4] + a[4 + i] * b[j * 4 + 1] + a[8 + i] * b[j * 4 + 2] +
                           a[12 + i] * b[j * 4 + 3];
    memcpy(c, t, sizeof t);
}

/* Errors of view v (double copy) against the exact view e: eye position, 3x3 entries. */
static void view_error(const double v[16], const double e[16], double *pos, double *rot)
{
    double vi[16], ei[16];
    *pos = *rot = INFINITY;
    if (!sweep_inv4(v, vi) || !sweep_inv4(e, ei))
        return;
    double dp = 0, dr = 0;
    for (int i = 0; i < 3; i++)
        dp += (vi[12 + i] - ei[12 + i]) * (vi[12 + i] - ei[12 + i]);
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++)
            dr = fmax(dr, fabs(v[c * 4 + r] - e[c * 4 + r]));
    *pos = sqrt(dp);
    *rot = dr;
    if (!isfinite(*pos) || !isfinite(*rot))
        *pos = *rot = INFINITY;
}

/* The library's scene for config c: camera, the two surfaces (float world matrices from G),
 * max_depth KMAX; returns the camera's exact world matrix. */
static limen_scene *build_scene(const config *c, const double g[16], double cam_world[16],
                                limen_node *s1, limen_node *s2)
{
    limen_scene *s = NULL;
    CHECK_OK(limen_scene_create(NULL, &s));
    if (!s)
        return NULL;
    double wa[16], wb[16], m[16];
    float f[16];
    local_frames(c, wa, wb);
    limen_node cam, light, a, b;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_CAMERA, "camera", &cam));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_LIGHT, "light", &light));
    limen_node_kind kind = c->mirrors ? LIMEN_NODE_MIRROR : LIMEN_NODE_PORTAL;
    CHECK_OK(limen_node_create(s, kind, "one", &a));
    CHECK_OK(limen_node_create(s, kind, "two", &b));
    /* the camera: near the axis, 0.2 in front of the middle, looking at surface one */
    double ct[16];
    trans(ct, 0.05, 0.03, 0.2);
    limen__d_mul(g, ct, cam_world);
    const double *src[3] = { cam_world, wa, wb };
    limen_node nodes[3] = { cam, a, b };
    for (int i = 0; i < 3; i++) {
        if (i)
            limen__d_mul(g, src[i], m);
        else
            memcpy(m, src[i], sizeof m);
        for (int k = 0; k < 16; k++)
            f[k] = (float)m[k];
        CHECK_OK(limen_node_set_local_matrix(s, nodes[i], f));
    }
    CHECK_OK(limen_scene_set_camera(s, cam));
    CHECK_OK(limen_camera_set_lens(s, cam, (float)(60 * M_PI / 180), 0.05f, 1000.0f));
    CHECK_OK(limen_node_set_dims(s, a, (float[3]){ (float)c->size, (float)c->size, 0 }));
    CHECK_OK(limen_node_set_dims(s, b, (float[3]){ (float)c->size, (float)c->size, 0 }));
    CHECK_OK(limen_surface_set_max_depth(s, a, KMAX));
    CHECK_OK(limen_surface_set_max_depth(s, b, KMAX));
    if (!c->mirrors)
        CHECK_OK(limen_portal_link(s, a, b));
    /* something to see in the corridor: a floor below the axis and a ball beside it */
    limen_node floor_n, ball;
    double lf[16], lb[16], r[16];
    CHECK_OK(limen_node_create(s, LIMEN_NODE_QUAD, "floor", &floor_n));
    CHECK_OK(limen_node_create(s, LIMEN_NODE_SPHERE, "ball", &ball));
    trans(lf, 0, -0.9, 0);
    ident(r);                                   /* local +Z to +Y: a floor */
    r[5] = 0, r[6] = -1, r[9] = 1, r[10] = 0;
    limen__d_mul(lf, r, lf);
    trans(lb, 0.55, -0.5, -0.3);
    const double *loc[2] = { lf, lb };
    limen_node extra[2] = { floor_n, ball };
    for (int i = 0; i < 2; i++) {
        limen__d_mul(g, loc[i], m);
        for (int k = 0; k < 16; k++)
            f[k] = (float)m[k];
        CHECK_OK(limen_node_set_local_matrix(s, extra[i], f));
    }
    CHECK_OK(limen_node_set_dims(s, floor_n, (float[3]){ (float)c->size, (float)(2 * c->L), 0 }));
    CHECK_OK(limen_node_set_checker(s, floor_n, (float[3]){ 0.85f, 0.85f, 0.8f },
                                    (float[3]){ 0.25f, 0.25f, 0.3f }, 0.25f));
    CHECK_OK(limen_node_set_dims(s, ball, (float[3]){ 0.25f, 0, 0 }));
    CHECK_OK(limen_node_set_color(s, ball, (float[3]){ 0.9f, 0.2f, 0.1f }));
    double lt[16];
    trans(lt, 0, 0.8, 0.5);
    limen__d_mul(g, lt, m);
    CHECK_OK(limen_node_set_position(s, light, (float[3]){ (float)m[12], (float)m[13], (float)m[14] }));
    *s1 = a, *s2 = b;
    return s;
}

/* X of a surface from the scene's float world matrices, in double, by docs/DESIGN.md's formulas
 * (the reflection about the plane W^-T (0,0,1,0); W_B R_y(180) W_A^-1 for a portal). */
static void lib_x(limen_scene *s, limen_node n, limen_node partner, int mirror, double x[16])
{
    float wf[16];
    double w[16], wi[16];
    limen_node_world_matrix(s, n, wf);
    for (int i = 0; i < 16; i++)
        w[i] = wf[i];
    sweep_inv4(w, wi);
    if (mirror) {
        double p[4] = { wi[2], wi[6], wi[10], wi[14] };   /* row 2 of W^-1 */
        double l = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        for (int i = 0; i < 4; i++)
            p[i] /= l;
        ident(x);
        for (int c = 0; c < 3; c++)
            for (int r = 0; r < 3; r++)
                x[c * 4 + r] -= 2 * p[r] * p[c];
        for (int r = 0; r < 3; r++)
            x[12 + r] = -2 * p[3] * p[r];
    } else {
        double wb[16], t[16];
        limen_node_world_matrix(s, partner, wf);
        for (int i = 0; i < 16; i++)
            wb[i] = wf[i];
        ident(t);
        t[0] = -1, t[10] = -1;
        limen__d_mul(wb, t, t);
        limen__d_mul(t, wi, x);
    }
}

static void test_recursion(void)
{
    const int full = sweep_full();
    const config configs[] = {
        { "mirrors", 1, 0, 1.0, 3.0 },
        { "portals", 0, 0, 1.0, 2.0 },
        { "twisted portals", 0, 10 * M_PI / 180, 1.0, 2.0 },
    };
    FILE *csv = sweep_csv("recursion",
                          "deepest virtual camera against the exact closed form; pos = eye "
                          "position error (units), rot = largest error of the view's 3x3 part",
                          "config,depth,variant,pos_err,rot_err");
    if (!csv)
        return;
    double g[16], ginv[16];
    make_g(g);
    sweep_inv4(g, ginv);
    printf("     %-16s %5s %10s %10s %10s %10s %10s   (eye position error at depth k)\n",
           "config", "k", "f32", "f32+ortho", "f64", "f64+ortho", "library");
    for (size_t ci = 0; ci < sizeof configs / sizeof configs[0]; ci++) {
        const config *c = &configs[ci];
        double x[2][16], xinv[2][16];
        exact_x(c, g, ginv, x);
        sweep_inv4(x[0], xinv[0]);
        sweep_inv4(x[1], xinv[1]);
        float xinv_f[2][16];
        for (int j = 0; j < 2; j++)
            for (int i = 0; i < 16; i++)
                xinv_f[j][i] = (float)xinv[j][i];
        /* the library's plan */
        double cam_world[16];
        limen_node s1, s2;
        limen_scene *s = build_scene(c, g, cam_world, &s1, &s2);
        limen_plan *p = NULL;
        CHECK_OK(limen_plan_create(&p));
        const limen_view *lib[KMAX + 1] = { 0 };
        if (s && p) {
            limen_plan_desc pd = { .width = 1024, .height = 768, .limits.max_views = 4096 };
            CHECK_OK(limen_plan_build(p, s, &pd));
            CHECK_MSG(sweep_plan_nonfinite(p) == 0, "%s: plan with NaN or Inf", c->name);
            for (int i = 0; i < limen_plan_count(p); i++) {
                const limen_view *v = limen_plan_view(p, i);
                if (v->depth <= KMAX && !lib[v->depth])
                    lib[v->depth] = v;
            }
            CHECK_MSG(lib[KMAX] != NULL, "%s: the plan does not reach depth %d", c->name, KMAX);
        }
        /* the library's own X in double, for the no-drift check */
        double lx[2][16], lxinv[2][16], lv[16];
        if (s) {
            lib_x(s, s1, s2, c->mirrors, lx[0]);
            if (c->mirrors)
                lib_x(s, s2, s1, 1, lx[1]);
            else
                memcpy(lx[1], lx[0], sizeof lx[0]);
            sweep_inv4(lx[0], lxinv[0]);
            sweep_inv4(lx[1], lxinv[1]);
            float cf[16];
            double cw[16];
            limen_node_world_matrix(s, limen_scene_get_camera(s), cf);
            for (int i = 0; i < 16; i++)
                cw[i] = cf[i];
            sweep_inv4(cw, lv);
        }
        /* the four compositions */
        double v64[16], v64o[16], e0[16];
        float v32[16], v32o[16];
        sweep_inv4(cam_world, e0);
        memcpy(v64, e0, sizeof e0);
        memcpy(v64o, e0, sizeof e0);
        for (int i = 0; i < 16; i++)
            v32[i] = v32o[i] = (float)e0[i];
        for (int k = 1; k <= KMAX; k++) {
            int which = c->mirrors ? (k - 1) % 2 : 0;   /* mirror 1, 2, 1, ... */
            limen__d_mul(v64, xinv[which], v64);
            limen__d_mul(v64o, xinv[which], v64o);
            ortho_d(v64o);
            mul_f(v32, xinv_f[which], v32);
            mul_f(v32o, xinv_f[which], v32o);
            ortho_f(v32o);
            if (s)
                limen__d_mul(lv, lxinv[which], lv);
            double m[16], cw[16], ev[16];
            exact_m(c, g, ginv, k, m);
            limen__d_mul(m, cam_world, cw);
            sweep_inv4(cw, ev);
            double vd[4][16];
            for (int i = 0; i < 16; i++) {
                vd[0][i] = v32[i];
                vd[1][i] = v32o[i];
            }
            memcpy(vd[2], v64, sizeof v64);
            memcpy(vd[3], v64o, sizeof v64o);
            static const char *const names[5] = { "f32", "f32+ortho", "f64", "f64+ortho", "library" };
            double pos[5], rot[5];
            for (int vi = 0; vi < 4; vi++)
                view_error(vd[vi], ev, &pos[vi], &rot[vi]);
            pos[4] = rot[4] = NAN;
            if (lib[k]) {
                double lvd[16], big = 0, dmax = 0;
                for (int i = 0; i < 16; i++)
                    lvd[i] = lib[k]->view[i];
                view_error(lvd, ev, &pos[4], &rot[4]);
                /* no drift of its own: equal to the double composition of its inputs, to
                 * the float rounding of its output */
                for (int i = 0; i < 16; i++) {
                    big = fmax(big, fabs(lv[i]));
                    dmax = fmax(dmax, fabs(lvd[i] - lv[i]));
                }
                CHECK_MSG(dmax <= 8 * big * 0x1p-24,
                          "%s depth %d: the library's view is %g off the double composition "
                          "of its own inputs (entries up to %g)", c->name, k, dmax, big);
                CHECK_MSG(sweep_finite(lib[k]->view, 16), "%s depth %d: NaN in the view", c->name, k);
            }
            {
                /* the spacing of floats at the exact eye position: the floor of any float answer */
                double big = 0;
                for (int i = 0; i < 3; i++)
                    big = fmax(big, fabs(cw[12 + i]));
                int e;
                frexp(big, &e);
                fprintf(csv, "%s,%d,float spacing,%.6g,%.6g\n", c->name, k, ldexp(1.0, e - 24),
                        ldexp(1.0, -24));
            }
            for (int vi = 0; vi < 5; vi++)
                if (!isnan(pos[vi]))
                    fprintf(csv, "%s,%d,%s,%.6g,%.6g\n", c->name, k, names[vi], pos[vi], rot[vi]);
            if (k == 1 || k == 8 || k == 16 || k == 32 || k == 64)
                printf("     %-16s %5d %10.2e %10.2e %10.2e %10.2e %10.2e\n", c->name, k, pos[0],
                       pos[1], pos[2], pos[3], pos[4]);
            if (k == KMAX) {
                CHECK_MSG(pos[2] < 1e-9 && rot[2] < 1e-9, "%s: f64 drifts %g / %g at depth %d",
                          c->name, pos[2], rot[2], k);
                CHECK_MSG(pos[4] < 1e-3 && rot[4] < 1e-5,
                          "%s: the library's depth-%d camera is %g units / %g off the exact one",
                          c->name, k, pos[4], rot[4]);
            }
        }
        /* the picture: the corridor drawn by limen against the ray tracer */
        if (s) {
            const int w = full ? 320 : 160, h = full ? 240 : 120;
            limen_renderer *r = sweep_renderer(w, h, LIMEN_DEPTH_NO, 24);
            unsigned char *truth = sweep_trace(s, w, h), *rgb = malloc((size_t)w * h * 3),
                          *heat = malloc((size_t)w * h * 3);
            if (r && truth && !sweep_render(r, s, (limen_render_opts){ 0 }, rgb)) {
                double e = sweep_diff(rgb, truth, w, h, heat);
                int deepest = 0;
                const limen_plan *rp = limen_renderer_plan(r);
                for (int i = 0; i < limen_plan_count(rp); i++)
                    deepest = limen_plan_view(rp, i)->depth > deepest ? limen_plan_view(rp, i)->depth : deepest;
                printf("     %-16s frame %dx%d: %d views, depth %d, %.3f%% of pixels off\n", c->name,
                       w, h, limen_plan_count(rp), deepest, 100 * e);
                CHECK_MSG(e <= SWEEP_BOUND, "%s: the frame is off on %.2f%% of pixels", c->name, 100 * e);
                const unsigned char *pan[3] = { rgb, truth, heat };
                sweep_png(w, h, 3, pan, "recursion_%s", c->mirrors ? "mirrors" : c->phi ? "twisted" : "portals");
            }
            free(truth), free(rgb), free(heat);
            limen_renderer_destroy(r);
        }
        limen_plan_destroy(p);
        limen_scene_destroy(s);
    }
    fclose(csv);
}

static const check_case cases[] = {
    { "recursion", test_recursion },
    { 0 },
};

int main(int argc, char **argv)
{
    return sweep_main(argc, argv, cases);
}
