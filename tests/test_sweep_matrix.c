/* test_sweep_matrix.c - stability sweep 5: building a mirror's matrix.
 *
 * Mirror normals approach (0, -1, 0): n = normalize(eps u - y) with u = (0.6, 0, 0.8), eps
 * from 1 down to 1e-12 and then exactly 0 (four steps a decade in FULL mode); the plane
 * passes through (1.3, 2.1, -0.7). Each construction is measured against the exact
 * reflection about the same float plane (I - 2 n n^T, -2 d n, in double): the largest entry
 * error, and the involution error |X X - I|.
 *   axis-angle    seed 000's A^-1 F A (limen__mirror_mat4_axis_angle, float, as the seed);
 *   closed        limen__mirror_mat4 / limen_mirror_matrix (double, rounded once);
 *   node          limen__mirror_mat4_node(W) = W diag(1,1,-1) W^-1 for the mirror node's
 *                 world matrix W (built by limen_node_set_facing), against the reflection
 *                 about W's own plane;
 *   library       limen_surface_matrix of that mirror node: what the planner uses.
 * Asserted: the library's constructions (closed, library, and node) never give NaN or Inf
 * and stay within 16 float epsilons of the exact reflection; the facing basis keeps the
 * node's plane within 4 epsilons of the requested normal. Output: matrix.csv.
 */
#include "core/lmath.h"
#include "core/testing.h"
#include "sweeps/sweep.h"

#define FEPS 1.1920928955078125e-7

static void exact_reflection(const double p_in[4], double x[16])
{
    double p[4];
    double l = sqrt(p_in[0] * p_in[0] + p_in[1] * p_in[1] + p_in[2] * p_in[2]);
    for (int i = 0; i < 4; i++)
        p[i] = p_in[i] / l;
    memset(x, 0, sizeof(double) * 16);
    for (int c = 0; c < 3; c++) {
        for (int r = 0; r < 3; r++)
            x[c * 4 + r] = (r == c) - 2 * p[r] * p[c];
        x[12 + c] = -2 * p[3] * p[c];
    }
    x[15] = 1;
}

/* Largest entry error against the exact matrix, and |X X - I|; INFINITY if not finite. */
static void measure(const float m[16], const double exact[16], double *err, double *invol)
{
    double d[16], xx[16];
    *err = 0, *invol = 0;
    for (int i = 0; i < 16; i++) {
        if (!isfinite(m[i])) {
            *err = *invol = INFINITY;
            return;
        }
        d[i] = m[i];
        *err = fmax(*err, fabs(d[i] - exact[i]));
    }
    limen__d_mul(d, d, xx);
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++)
            *invol = fmax(*invol, fabs(xx[c * 4 + r] - (r == c)));
}

static void test_matrix(void)
{
    const int full = sweep_full();
    double eps[80];
    int ne = 0;
    for (int i = 0; i <= (full ? 48 : 12); i++)
        eps[ne++] = pow(10.0, full ? -i / 4.0 : -(double)i);
    eps[ne++] = 0;
    FILE *csv = sweep_csv("matrix",
                          "mirror matrices for normals approaching (0,-1,0); err = largest entry "
                          "error against the exact reflection, invol = |X X - I|",
                          "eps,angle_deg,method,err,invol,plane_err");
    limen_scene *s = NULL;
    CHECK_OK(limen_scene_create(NULL, &s));
    limen_node mirror;
    CHECK_OK(limen_node_create(s, LIMEN_NODE_MIRROR, "mirror", &mirror));
    CHECK_OK(limen_node_set_position(s, mirror, (float[3]){ 1.3f, 2.1f, -0.7f }));
    if (!csv || !s)
        return;
    printf("     %-9s %12s %12s %12s %12s\n", "eps", "axis-angle", "closed", "node", "library");
    double worst_seed = 0;
    for (int k = 0; k < ne; k++) {
        double n[3] = { 0.6 * eps[k], -1, 0.8 * eps[k] }, l = sqrt(n[0] * n[0] + 1 + n[2] * n[2]);
        float nf[3] = { (float)(n[0] / l), (float)(n[1] / l), (float)(n[2] / l) };
        const float p0[3] = { 1.3f, 2.1f, -0.7f };
        float plane[4];
        CHECK_OK(limen_plane_from_point_normal(p0, nf, plane));
        double pd[4] = { plane[0], plane[1], plane[2], plane[3] }, ex[16];
        exact_reflection(pd, ex);
        double angle = atan2(sqrt((double)nf[0] * nf[0] + (double)nf[2] * nf[2]), -(double)nf[1]) * 180 / M_PI;

        double err[4], invol[4], plane_err = 0;
        mat4 m;
        float f[16];
        vec4 pv = { plane[0], plane[1], plane[2], plane[3] };
        limen__mirror_mat4_axis_angle(pv, m);
        limen__mat4_to_array(m, f);
        measure(f, ex, &err[0], &invol[0]);
        CHECK_OK(limen_mirror_matrix(plane, f));
        measure(f, ex, &err[1], &invol[1]);
        limen__mirror_mat4(pv, m);
        limen__mat4_to_array(m, f);
        double e2, i2;
        measure(f, ex, &e2, &i2);
        err[1] = fmax(err[1], e2), invol[1] = fmax(invol[1], i2);

        /* the node: its facing basis, then W diag(1,1,-1) W^-1 and the planner's matrix,
         * both against the reflection about the node's own plane */
        CHECK_OK(limen_node_set_facing(s, mirror, nf, NULL));
        float wf[16];
        CHECK_OK(limen_node_world_matrix(s, mirror, wf));
        double w[16], wi[16];
        for (int i = 0; i < 16; i++)
            w[i] = wf[i];
        double own[16];
        if (sweep_inv4(w, wi)) {
            double np[4] = { wi[2], wi[6], wi[10], wi[14] };
            exact_reflection(np, own);
            double nl = sqrt(np[0] * np[0] + np[1] * np[1] + np[2] * np[2]);
            for (int i = 0; i < 3; i++)
                plane_err = fmax(plane_err, fabs(np[i] / nl - pd[i]));
        } else {
            memcpy(own, ex, sizeof ex);
            plane_err = INFINITY;
        }
        mat4 wm;
        limen__mat4_from_array(wf, wm);
        limen_status st = limen__mirror_mat4_node(wm, m);
        CHECK_MSG(st == LIMEN_OK, "eps %g: node form refused", eps[k]);
        limen__mat4_to_array(m, f);
        measure(f, own, &err[2], &invol[2]);
        CHECK_OK(limen_surface_matrix(s, mirror, f));
        measure(f, own, &err[3], &invol[3]);

        static const char *const names[4] = { "axis-angle", "closed", "node", "library" };
        for (int i = 0; i < 4; i++)
            fprintf(csv, "%.6g,%.6g,%s,%.6g,%.6g,%.6g\n", eps[k], angle, names[i], err[i],
                    invol[i], i >= 2 ? plane_err : 0.0);
        printf("     %-9.3g %12.3g %12.3g %12.3g %12.3g\n", eps[k], err[0], err[1], err[2], err[3]);
        worst_seed = fmax(worst_seed, err[0]);
        /* scale of the entries: |translation| <= 2 |d| ~ 4.4 */
        for (int i = 1; i < 4; i++)
            CHECK_MSG(isfinite(err[i]) && err[i] <= 16 * FEPS * 5 && invol[i] <= 16 * FEPS * 5,
                      "eps %g: %s is off by %g (involution %g)", eps[k], names[i], err[i], invol[i]);
        CHECK_MSG(plane_err <= 4 * FEPS, "eps %g: the facing basis moves the plane by %g", eps[k],
                  plane_err);
    }
    printf("     the seed's axis-angle construction: worst error %g (NaN or Inf counts as inf)\n",
           worst_seed);
    CHECK_MSG(!(worst_seed < 1e-4), "the sweep no longer shows the seed method failing");

    /* and in a picture: mirrors facing exactly and nearly straight down, drawn by limen
     * against the ray tracer */
    const int w = full ? 320 : 160, h = full ? 240 : 120;
    limen_script *sc = check_load_script("tests/sweeps/matrix_ceiling.lua");
    limen_renderer *r = sweep_renderer(w, h, LIMEN_DEPTH_NO, 24);
    if (sc && r) {
        limen_scene *cs = limen_script_scene(sc);
        unsigned char *truth = sweep_trace(cs, w, h), *rgb = malloc((size_t)w * h * 3),
                      *heat = malloc((size_t)w * h * 3);
        if (truth && !sweep_render(r, cs, (limen_render_opts){ 0 }, rgb)) {
            double e = sweep_diff(rgb, truth, w, h, heat);
            const limen_plan *p = limen_renderer_plan(r);
            printf("     ceiling mirrors (normal (0,-1,0) and 1e-6 off it): %d views, %.3f%% of "
                   "pixels off\n", limen_plan_count(p), 100 * e);
            CHECK_MSG(sweep_plan_nonfinite(p) == 0, "ceiling mirrors: NaN in the plan");
            CHECK_MSG(limen_plan_count(p) >= 3, "ceiling mirrors: expected a view through each");
            CHECK_MSG(e <= SWEEP_BOUND, "ceiling mirrors: %.2f%% of pixels off", 100 * e);
            const unsigned char *pan[3] = { rgb, truth, heat };
            sweep_png(w, h, 3, pan, "matrix_ceiling");
        }
        free(truth), free(rgb), free(heat);
    }
    limen_renderer_destroy(r);
    limen_script_destroy(sc);
    limen_scene_destroy(s);
    fclose(csv);
}

static const check_case cases[] = {
    { "matrix", test_matrix },
    { 0 },
};

int main(int argc, char **argv)
{
    return sweep_main(argc, argv, cases);
}
