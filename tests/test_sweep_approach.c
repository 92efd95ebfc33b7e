/* test_sweep_approach.c - stability sweep 1: the eye approaching a mirror and a portal.
 *
 * The camera stands on the surface's normal through its centre, d = 1 down to 1e-7 units in
 * front of it, then on the plane and behind it (down to d = -1e-3), looking at it at 0, 5
 * and 85 degrees of incidence (tests/sweeps/approach_*.lua). At every step the frame is
 * compared with the ray tracer for
 *   default   what a user gets: stencil method, clip OBLIQUE, which the planner turns into
 *             the user clip plane where the eye is closer to the exit plane than the
 *             camera's near distance (src/core/plan.c, fill_public);
 *   plane     clip PLANE everywhere;
 *   none      no clipping (the baseline that leaks);
 *   oblique   the oblique projection FORCED at every step: the library's plan, with each
 *             nested view's projection rebuilt by limen_oblique_projection from the view's
 *             clip plane, drawn by tests/sweeps/plan_gl.h (plan_game.h's renderer);
 *             "refused" where even limen_oblique_projection says DEGENERATE (eye within
 *             1e-6 near distances of the plane). The surfaces' flat passes are drawn
 *             from their polygons clipped in double, so that only the projection differs;
 *   own_quads, own_polygons   the default plan drawn by that renderer with the surfaces as
 *             quads (as limen draws them) and as polygons clipped in double: whether the
 *             GPU's float clipping of a surface nearly touching the eye is what fails.
 * Asserted (QUICK and FULL): no NaN or Inf in any matrix of any plan (every clip method and
 * depth range); no failed call; the default within the ground-truth bound (0.5% of pixels
 * over 8/255) at every step but d = 0 (eye on the surface's plane: it is edge-on and
 * invisible; only checked for finiteness); and the fallback engaging before the oblique
 * projection degrades: the smallest d at which the library still uses OBLIQUE lies above
 * the largest d at which the forced oblique projection breaks the bound.
 * Output: approach.csv, frames approach_*.png ([rendered | ray traced | difference]).
 */
#include "sweeps/plan_gl.h"

#define NANG 3
static const double angles[NANG] = { 0, 5, 85 };
static const char *const surf_names[2] = { "mirror", "portal" };

static double *steps(int *n)
{
    static double d[64];
    int k = 0;
    if (sweep_full()) {
        for (int i = 0; i <= 28; i++)   /* 1 .. 1e-7, four steps a decade */
            d[k++] = pow(10.0, -i / 4.0);
        d[k++] = 0.07, d[k++] = 0.05, d[k++] = 0.045, d[k++] = 0.03;
        d[k++] = 0;
        d[k++] = -1e-7, d[k++] = -1e-5, d[k++] = -1e-4, d[k++] = -1e-3;
    } else {
        const double q[] = { 1, 0.06, 0.04, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 0, -1e-7, -1e-3 };
        for (size_t i = 0; i < sizeof q / sizeof q[0]; i++)
            d[k++] = q[i];
    }
    /* sort descending (the approach) */
    for (int i = 0; i < k; i++)
        for (int j = i + 1; j < k; j++)
            if (d[j] > d[i]) {
                double t = d[i];
                d[i] = d[j], d[j] = t;
            }
    *n = k;
    return d;
}

static void place_camera(limen_scene *s, double d, double angle_deg)
{
    double a = angle_deg * M_PI / 180.0;
    float eye[3] = { 0.0f, 1.2f, (float)d };
    float target[3] = { eye[0] + (float)sin(a), eye[1], eye[2] - (float)cos(a) };
    CHECK_OK(limen_node_look_at(s, limen_scene_get_camera(s), eye, target, (float[3]){ 0, 1, 0 }));
}

/* Plans with every clip method and depth range; counts views with NaN or Inf. */
static int plan_all_finite(limen_plan *p, limen_scene *s, int w, int h)
{
    int bad = 0;
    for (int range = 0; range < 3; range++)
        for (int clip = 0; clip < 3; clip++) {
            limen_plan_desc pd = { .width = w, .height = h, .range = range, .limits.clip = clip };
            limen_status st = limen_plan_build(p, s, &pd);
            CHECK_MSG(st == LIMEN_OK, "plan: %s", limen_scene_error(s));
            int nb = st ? 0 : sweep_plan_nonfinite(p);
            CHECK_MSG(nb == 0, "plan (range %d, clip %d): %d views with NaN or Inf", range, clip, nb);
            bad += nb;
        }
    return bad;
}

/* The clip method of the first nested view of the default plan ('-' if none). */
static const char *clip_name(int c)
{
    return c == LIMEN_CLIP_OBLIQUE ? "oblique" : c == LIMEN_CLIP_PLANE ? "plane" : c == LIMEN_CLIP_NONE ? "none" : "-";
}

typedef struct forced {
    int refused;            /* nested views where limen_oblique_projection said no */
    int nested;
} forced;

/* Draws the default plan with the own renderer: force = 1 replaces every nested view's
 * projection by the oblique one; cpu = 1 draws the surfaces' flat passes from their polygons
 * clipped in double (plan_gl.h). */
static double own_frame(pgl *g, limen_plan *p, limen_scene *s, int w, int h, int force, int cpu,
                        const unsigned char *truth, unsigned char *rgb, unsigned char *heat,
                        forced *f)
{
    limen_plan_desc pd = { .width = w, .height = h };
    CHECK_OK(limen_plan_build(p, s, &pd));
    int n = limen_plan_count(p);
    float(*proj)[16] = calloc((size_t)n, sizeof *proj);
    limen_clip_method *clip = calloc((size_t)n, sizeof *clip);
    const float *root = limen_plan_view(p, 0)->proj;
    f->refused = f->nested = 0;
    for (int i = 0; i < n; i++) {
        const limen_view *v = limen_plan_view(p, i);
        memcpy(proj[i], v->proj, sizeof proj[i]);
        clip[i] = v->clip;
        if (v->depth == 0 || !force)
            continue;
        f->nested++;
        double c[4];
        float cf[4];
        if (!sweep_plane_to_view(v->view, v->clip_plane, c)) {
            f->refused++;
            continue;
        }
        for (int k = 0; k < 4; k++)
            cf[k] = (float)c[k];
        if (limen_oblique_projection(root, cf, LIMEN_DEPTH_NO, proj[i]) == LIMEN_OK) {
            clip[i] = LIMEN_CLIP_OBLIQUE;
            CHECK_MSG(sweep_finite(proj[i], 16), "forced oblique projection not finite");
        } else {
            f->refused++;
        }
    }
    g->cpu_surfaces = cpu;
    int rc = pgl_draw(g, s, p, (const float(*)[16])proj, clip, rgb);
    CHECK_MSG(rc == 0, "own renderer failed");
    free(proj);
    free(clip);
    return rc ? 1.0 : sweep_diff(rgb, truth, w, h, heat);
}

static void test_approach(void)
{
    const int full = sweep_full();
    const int w = full ? 320 : 160, h = full ? 240 : 120;
    int nsteps;
    const double *d = steps(&nsteps);
    limen_renderer *r = sweep_renderer(w, h, LIMEN_DEPTH_NO, 24);
    pgl *g = pgl_create(w, h);
    CHECK_MSG(g != NULL, "cannot set up the own OpenGL renderer");
    limen_plan *p = NULL;
    CHECK_OK(limen_plan_create(&p));
    FILE *csv = sweep_csv("approach",
                          "eye approaching a mirror / portal along its normal; err_* = share of "
                          "pixels over 8/255 against the ray tracer",
                          "surface,angle,d,default_clip,views,nonfinite,err_default,err_plane,"
                          "err_none,err_oblique,oblique_refused,err_texture,err_own_quads,err_own_polygons");
    unsigned char *rgb = malloc((size_t)w * h * 3), *heat = malloc((size_t)w * h * 3);
    unsigned char *orgb = malloc((size_t)w * h * 3), *oheat = malloc((size_t)w * h * 3);
    if (!r || !g || !p || !csv) {
        nsteps = 0;
    }
    printf("     %-7s %5s  %-10s %-8s %9s %9s %9s %9s %9s %9s\n", "surface", "angle", "d",
           "default", "err_def", "err_plane", "err_none", "err_obl", "own_quad", "own_poly");
    for (int sfi = 0; sfi < 2 && nsteps; sfi++) {
        limen_script *sc = check_load_script(sfi ? "tests/sweeps/approach_portal.lua"
                                          : "tests/sweeps/approach_mirror.lua");
        if (!sc)
            continue;
        limen_scene *s = limen_script_scene(sc);
        float znear;
        limen_camera_get_lens(s, limen_scene_get_camera(s), NULL, &znear, NULL);
        for (int ai = 0; ai < NANG; ai++) {
            double min_oblique_d = INFINITY;   /* smallest d the library uses OBLIQUE at */
            double max_bad_forced = -INFINITY; /* largest d where forced oblique breaks the bound */
            int wrote_bad = 0;
            for (int k = 0; k < nsteps; k++) {
                place_camera(s, d[k], angles[ai]);
                int nonfinite = plan_all_finite(p, s, w, h);
                unsigned char *truth = sweep_trace(s, w, h);
                if (!truth)
                    continue;
                /* default */
                double e_def = 1, e_plane = 1, e_none = 1, e_obl = NAN, e_tex = NAN;
                if (!sweep_render(r, s, (limen_render_opts){ 0 }, rgb))
                    e_def = sweep_diff(rgb, truth, w, h, heat);
                const limen_plan *rp = limen_renderer_plan(r);
                int views = limen_plan_count(rp);
                int dclip = -1;
                for (int i = 1; i < views; i++)
                    if (limen_plan_view(rp, i)->depth == 1) {
                        dclip = limen_plan_view(rp, i)->clip;
                        break;
                    }
                if (dclip == LIMEN_CLIP_OBLIQUE && d[k] < min_oblique_d)
                    min_oblique_d = d[k];
                /* what the default uses at every step has to hold */
                if (d[k] != 0)
                    CHECK_MSG(e_def <= SWEEP_BOUND,
                              "%s at %g deg, d = %g: the default is off on %.2f%% of pixels",
                              surf_names[sfi], angles[ai], d[k], 100 * e_def);
                int pic = ai != 1 && (d[k] == 1 || d[k] == 1e-5 || d[k] == 1e-6 || d[k] == 1e-7);
                if (pic || e_def > SWEEP_BOUND) {
                    const unsigned char *pan[3] = { rgb, truth, heat };
                    sweep_png(w, h, 3, pan, "approach_%s_%02.0f_default_d%g", surf_names[sfi],
                              angles[ai], d[k]);
                }
                /* clip plane and no clipping */
                if (!sweep_render(r, s, (limen_render_opts){ .limits.clip = LIMEN_CLIP_PLANE },
                                  rgb))
                    e_plane = sweep_diff(rgb, truth, w, h, NULL);
                if (!sweep_render(r, s, (limen_render_opts){ .limits.clip = LIMEN_CLIP_NONE }, rgb))
                    e_none = sweep_diff(rgb, truth, w, h, heat);
                if (d[k] == 1 && ai == 0) {
                    const unsigned char *pan[3] = { rgb, truth, heat };
                    sweep_png(w, h, 3, pan, "approach_%s_%02.0f_none_d%g", surf_names[sfi],
                              angles[ai], d[k]);
                }
                if (full) {
                    if (!sweep_render(r, s, (limen_render_opts){ .method = LIMEN_METHOD_TEXTURE }, rgb))
                        e_tex = sweep_diff(rgb, truth, w, h, NULL);
                }
                /* forced oblique: where the library falls back, and in FULL mode everywhere
                 * (surfaces from their double polygons, so that only the projection differs) */
                forced f = { 0, 0 };
                if (g && (full || dclip == LIMEN_CLIP_PLANE)) {
                    e_obl = own_frame(g, p, s, w, h, 1, 1, truth, orgb, oheat, &f);
                    if (e_obl > SWEEP_BOUND && d[k] > max_bad_forced)
                        max_bad_forced = d[k];
                    if ((e_obl > SWEEP_BOUND && !wrote_bad) || pic) {
                        const unsigned char *pan[3] = { orgb, truth, oheat };
                        sweep_png(w, h, 3, pan, "approach_%s_%02.0f_forced_oblique_d%g",
                                  surf_names[sfi], angles[ai], d[k]);
                        wrote_bad |= e_obl > SWEEP_BOUND;
                    }
                }
                /* the library's plan drawn by the own renderer, surfaces as quads (as limen
                 * draws them) and as polygons clipped in double */
                double e_gpu = NAN, e_cpu = NAN;
                if (g && (full || fabs(d[k]) <= 1e-5)) {
                    forced f2;
                    e_gpu = own_frame(g, p, s, w, h, 0, 0, truth, orgb, oheat, &f2);
                    e_cpu = own_frame(g, p, s, w, h, 0, 1, truth, orgb, oheat, &f2);
                    if (e_gpu > SWEEP_BOUND && e_cpu <= SWEEP_BOUND) {
                        const unsigned char *pan[3] = { orgb, truth, oheat };
                        sweep_png(w, h, 3, pan, "approach_%s_%02.0f_polygons_d%g", surf_names[sfi],
                                  angles[ai], d[k]);
                    }
                }
                if (csv)
                    fprintf(csv, "%s,%g,%.9g,%s,%d,%d,%.6f,%.6f,%.6f,%.6f,%d,%.6f,%.6f,%.6f\n",
                            surf_names[sfi], angles[ai], d[k], clip_name(dclip), views,
                            nonfinite, e_def, e_plane, e_none, e_obl, f.refused, e_tex, e_gpu,
                            e_cpu);
                printf("     %-7s %5g  %-10.3g %-8s %8.3f%% %8.3f%% %8.3f%% %8.3f%% %8.3f%% %8.3f%%%s\n",
                       surf_names[sfi], angles[ai], d[k], clip_name(dclip), 100 * e_def,
                       100 * e_plane, 100 * e_none, 100 * e_obl, 100 * e_gpu, 100 * e_cpu,
                       f.refused ? " (refused)" : "");
                free(truth);
            }
            /* the fallback engages before the oblique projection degrades */
            printf("     %s at %g deg: library switches to the clip plane below d = %g (near "
                   "%g); forced oblique breaks the bound from d = %g down\n",
                   surf_names[sfi], angles[ai], min_oblique_d, znear, max_bad_forced);
            CHECK_MSG(max_bad_forced < min_oblique_d,
                      "%s at %g deg: the forced oblique projection breaks the bound at d = %g, "
                      "but the library still uses it down to d = %g",
                      surf_names[sfi], angles[ai], max_bad_forced, min_oblique_d);
        }
        limen_script_destroy(sc);
    }
    if (csv)
        fclose(csv);
    free(rgb), free(heat), free(orgb), free(oheat);
    limen_plan_destroy(p);
    pgl_destroy(g);
    limen_renderer_destroy(r);
}

static const check_case cases[] = {
    { "approach", test_approach },
    { 0 },
};

int main(int argc, char **argv)
{
    return sweep_main(argc, argv, cases);
}
