/* test_sweep_depth.c - stability sweep 3: depth precision in a mirror.
 *
 * Two parallel quads a small gap apart (red in front of blue, tests/sweeps/depth_mirror.lua)
 * seen in a mirror through an oblique projection, for every clip-space convention (NO, ZO,
 * ZO_REVERSED) with a 24-bit integer and a 32-bit float depth buffer, as the mirror's plane
 * tilts against the line of sight from 0 to 85 degrees (the camera 2 units from the
 * mirror's centre, the quads 3 units beyond it on the reflected line of sight). Measured:
 * the share of the red quad's pixels (in the ray-traced truth) that the renderer gets
 * wrong: z-fighting. The same frames with the user clip plane (the camera's own projection,
 * which the tilt does not touch) are the reference.
 * Asserted: finite plans; the oblique projection in use wherever the eye is farther from
 * the mirror than the near distance (what the default promises); and the default settings
 * (NO, 24 bits, oblique) free of z-fighting (at most 0.5% of the red quad) at the default
 * gap of 1e-3 units 5 units away, at every tilt.
 * Output: depth.csv, frames depth_*.png ([rendered | ray traced | difference]).
 */
#include "sweeps/sweep.h"

static const char *const range_names[3] = { "no", "zo", "zo-reversed" };

static void place(limen_scene *s, double tilt_deg, double gap)
{
    const double D = 2.0, L = 3.0, my = 1.5;
    double t = tilt_deg * M_PI / 180.0;
    float eye[3] = { (float)(D * sin(t)), (float)my, (float)(D * cos(t)) };
    CHECK_OK(limen_node_look_at(s, limen_scene_get_camera(s), eye, (float[3]){ 0, (float)my, 0 },
                                (float[3]){ 0, 1, 0 }));
    /* the reflected line of sight r = (-sin t, 0, cos t); the quads face back along it */
    double r[3] = { -sin(t), 0, cos(t) };
    float nrm[3] = { (float)-r[0], 0, (float)-r[2] };
    limen_node front, back;
    CHECK_OK(limen_node_find(s, "front", &front));
    CHECK_OK(limen_node_find(s, "back", &back));
    float pb[3] = { (float)(L * r[0]), (float)my, (float)(L * r[2]) };
    float pf[3] = { (float)((L - gap) * r[0]), (float)my, (float)((L - gap) * r[2]) };
    CHECK_OK(limen_node_set_position(s, back, pb));
    CHECK_OK(limen_node_set_position(s, front, pf));
    CHECK_OK(limen_node_set_facing(s, back, nrm, NULL));
    CHECK_OK(limen_node_set_facing(s, front, nrm, NULL));
}

/* Window depth of world point x in view v of plan p (double: what depth the mathematics
 * gives; float: the GPU's way, view_proj = proj * view in float, then view_proj * x). */
static double window_depth(const limen_view *v, limen_depth_range range, const double x[3], int in_float)
{
    double z, w;
    if (in_float) {
        float vp[16], xf[4] = { (float)x[0], (float)x[1], (float)x[2], 1.0f };
        for (int j = 0; j < 4; j++)
            for (int i = 0; i < 4; i++)
                vp[j * 4 + i] = v->proj[i] * v->view[j * 4] + v->proj[4 + i] * v->view[j * 4 + 1] +
                                v->proj[8 + i] * v->view[j * 4 + 2] + v->proj[12 + i] * v->view[j * 4 + 3];
        float zf = vp[2] * xf[0] + vp[6] * xf[1] + vp[10] * xf[2] + vp[14];
        float wf = vp[3] * xf[0] + vp[7] * xf[1] + vp[11] * xf[2] + vp[15];
        z = (float)(zf / wf), w = 1;
    } else {
        double V[16], P[16], PV[16];
        for (int i = 0; i < 16; i++)
            V[i] = v->view[i], P[i] = v->proj[i];
        limen__d_mul(P, V, PV);
        z = PV[2] * x[0] + PV[6] * x[1] + PV[10] * x[2] + PV[14];
        w = PV[3] * x[0] + PV[7] * x[1] + PV[11] * x[2] + PV[15];
    }
    double ndc = z / w;
    return range == LIMEN_DEPTH_NO ? 0.5 * ndc + 0.5 : ndc;
}

/* The two quads' depths on the line of sight through their centres, apart by how many steps
 * of the depth buffer (24-bit integer: 2^-24; 32-bit float: the spacing of floats there). */
static double steps_apart(const limen_view *v, limen_depth_range range, int bits, double gap, int in_float)
{
    const double L = 3.0;
    /* the quads' centres: on the reflected line of sight r, at L - gap and L from the mirror */
    double r[3] = { -v->eye[0], 0, -v->eye[2] };   /* virtual eye = M - D r, M = (0, 1.5, 0) */
    double len = sqrt(r[0] * r[0] + r[2] * r[2]);
    r[0] /= len, r[2] /= len;
    double f[3] = { (L - gap) * r[0], 1.5, (L - gap) * r[2] }, b[3] = { L * r[0], 1.5, L * r[2] };
    double df = window_depth(v, range, f, in_float), db = window_depth(v, range, b, in_float);
    double step;
    if (bits == 24) {
        step = ldexp(1.0, -24);
    } else {
        int e;
        frexp(fmax(fabs(df), fabs(db)), &e);
        step = ldexp(1.0, e - 24);
    }
    return fabs(db - df) / step;
}

/* Share of the truth's red-quad pixels that the frame gets wrong (over 8/255). */
static double zfight(const unsigned char *img, const unsigned char *truth, int w, int h, long *red)
{
    long n = 0, bad = 0;
    for (long i = 0; i < (long)w * h; i++) {
        const unsigned char *t = truth + 3 * i, *c = img + 3 * i;
        int mx = t[1] > t[2] ? t[1] : t[2];
        if (!(t[0] > 40 && t[0] > 2 * mx))
            continue;
        n++;
        int d = 0;
        for (int k = 0; k < 3; k++) {
            int e = abs((int)c[k] - (int)t[k]);
            d = e > d ? e : d;
        }
        bad += d > SWEEP_THRESHOLD;
    }
    *red = n;
    return n ? (double)bad / (double)n : 0.0;
}

static void test_depth(void)
{
    const int full = sweep_full();
    const int w = full ? 320 : 160, h = full ? 240 : 120;
    static const double tilts_full[] = { 0, 10, 20, 30, 40, 50, 60, 65, 70, 75, 78, 80, 82, 84, 85 };
    static const double tilts_quick[] = { 0, 45, 70, 80, 85 };
    static const double gaps_full[] = { 1e-3, 1e-4, 3e-5, 1e-5, 3e-6 };
    static const double gaps_quick[] = { 1e-3 };
    const double *tilts = full ? tilts_full : tilts_quick;
    const int nt = full ? (int)(sizeof tilts_full / sizeof *tilts_full) : (int)(sizeof tilts_quick / sizeof *tilts_quick);
    const double *gaps = full ? gaps_full : gaps_quick;
    const int ng = full ? 5 : 1;
    limen_renderer *r[3][2];
    for (int rg = 0; rg < 3; rg++)
        for (int b = 0; b < 2; b++)
            r[rg][b] = sweep_renderer(w, h, rg, b ? 32 : 24);
    limen_script *sc = check_load_script("tests/sweeps/depth_mirror.lua");
    limen_plan *p = NULL;
    CHECK_OK(limen_plan_create(&p));
    FILE *csv = sweep_csv("depth",
                          "two quads a gap apart seen in a mirror tilted against the line of "
                          "sight; zfight = share of the front quad's pixels wrong",
                          "gap,tilt,range,bits,clip,view_clip,red_px,zfight,err_frame,steps,steps_float");
    unsigned char *rgb = malloc((size_t)w * h * 3), *heat = malloc((size_t)w * h * 3);
    if (!sc || !p || !csv)
        return;
    limen_scene *s = limen_script_scene(sc);
    printf("     %-7s %5s  z-fighting share per convention and depth buffer (oblique / plane)\n",
           "gap", "tilt");
    for (int gi = 0; gi < ng; gi++) {
        for (int ti = 0; ti < nt; ti++) {
            place(s, tilts[ti], gaps[gi]);
            unsigned char *truth = sweep_trace(s, w, h);
            if (!truth)
                continue;
            printf("     %-7g %5g ", gaps[gi], tilts[ti]);
            for (int rg = 0; rg < 3; rg++)
                for (int b = 0; b < 2; b++) {
                    if (!r[rg][b])
                        continue;
                    for (int clip = 0; clip < 2; clip++) {
                        limen_plan_desc pd = { .width = w, .height = h, .range = rg,
                                               .limits.clip = clip };
                        CHECK_OK(limen_plan_build(p, s, &pd));
                        CHECK_MSG(sweep_plan_nonfinite(p) == 0, "plan with NaN or Inf");
                        if (sweep_render(r[rg][b], s, (limen_render_opts){ .limits.clip = clip },
                                         rgb))
                            continue;
                        const limen_plan *rp = limen_renderer_plan(r[rg][b]);
                        int vclip = limen_plan_count(rp) > 1 ? (int)limen_plan_view(rp, 1)->clip : -1;
                        long red;
                        double zf = zfight(rgb, truth, w, h, &red);
                        double e = sweep_diff(rgb, truth, w, h, heat);
                        double st = NAN, stf = NAN;
                        if (limen_plan_count(rp) > 1) {
                            st = steps_apart(limen_plan_view(rp, 1), rg, b ? 32 : 24, gaps[gi], 0);
                            stf = steps_apart(limen_plan_view(rp, 1), rg, b ? 32 : 24, gaps[gi], 1);
                        }
                        fprintf(csv, "%g,%g,%s,%d,%s,%s,%ld,%.6f,%.6f,%.4g,%.4g\n", gaps[gi],
                                tilts[ti], range_names[rg], b ? 32 : 24, clip ? "plane" : "oblique",
                                vclip == 0 ? "oblique" : vclip == 1 ? "plane" : "-", red, zf, e, st,
                                stf);
                        if (clip == 0)
                            printf(" %s/%d %5.1f%%", range_names[rg], b ? 32 : 24, 100 * zf);
                        if (clip == 0 && rg == 0 && b == 0) {
                            /* the default: oblique in use, and no z-fighting */
                            CHECK_MSG(vclip == LIMEN_CLIP_OBLIQUE,
                                      "tilt %g: the mirror's view does not use the oblique "
                                      "projection", tilts[ti]);
                            CHECK_MSG(red > 0, "tilt %g: the red quad is not in the picture", tilts[ti]);
                            if (gaps[gi] == 1e-3)
                                CHECK_MSG(zf <= SWEEP_BOUND,
                                          "tilt %g, gap %g: the default z-fights on %.1f%% of "
                                          "the front quad", tilts[ti], gaps[gi], 100 * zf);
                        }
                        if (clip == 0 && (gaps[gi] == 1e-3 || gaps[gi] == 1e-5) &&
                            (tilts[ti] == 0 || tilts[ti] == 80 || tilts[ti] == 85) &&
                            ((rg == 0 && b == 0) || (rg == 2 && b == 1))) {
                            const unsigned char *pan[3] = { rgb, truth, heat };
                            sweep_png(w, h, 3, pan, "depth_%s%d_gap%g_tilt%g", range_names[rg],
                                      b ? 32 : 24, gaps[gi], tilts[ti]);
                        }
                    }
                }
            printf("\n");
            free(truth);
        }
    }
    fclose(csv);
    free(rgb), free(heat);
    limen_plan_destroy(p);
    limen_script_destroy(sc);
    for (int rg = 0; rg < 3; rg++)
        for (int b = 0; b < 2; b++)
            limen_renderer_destroy(r[rg][b]);
}

static const check_case cases[] = {
    { "depth", test_depth },
    { 0 },
};

int main(int argc, char **argv)
{
    return sweep_main(argc, argv, cases);
}
