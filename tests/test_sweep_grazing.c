/* test_sweep_grazing.c - stability sweep 2: a mirror and a portal turning edge-on.
 *
 * The surface (tests/sweeps/grazing_*.lua) turns from 80 to 89.999 degrees between its
 * normal and the direction to the eye, about an axis 30 degrees from the vertical, so that
 * the sliver it becomes runs diagonally across the pixel grid: its screen rectangle stays
 * large while the pixel centres it covers go to none. At every angle:
 *   - the plan holds only finite numbers (every clip method and depth range);
 *   - no view is of zero area: every nested view's surface, projected by its parent view in
 *     double precision here, covers at least one pixel centre of the view's scissor
 *     rectangle (a view that covers none is drawn for nothing, and a sliver of a few pixels
 *     must not open a full-rectangle view);
 *   - the default frame is within the ground-truth bound (no sliver artefacts).
 * Output: grazing.csv, frames grazing_*.png ([rendered | ray traced | difference]).
 */
#include "sweeps/sweep.h"

static double *angles(int *n)
{
    static double a[64];
    int k = 0;
    if (sweep_full()) {
        for (int i = 80; i <= 89; i++)
            a[k++] = i;
        for (int i = 1; i <= 9; i++)
            a[k++] = 89 + 0.1 * i;
        const double fine[] = { 89.95, 89.98, 89.99, 89.995, 89.998, 89.999 };
        for (size_t i = 0; i < sizeof fine / sizeof fine[0]; i++)
            a[k++] = fine[i];
    } else {
        const double q[] = { 80, 85, 88, 89, 89.5, 89.9, 89.95, 89.99, 89.999 };
        for (size_t i = 0; i < sizeof q / sizeof q[0]; i++)
            a[k++] = q[i];
    }
    *n = k;
    return a;
}

/* Turns the surface: normal cos(a) z + sin(a) t, t = (cos 30, sin 30, 0), local +Y along the
 * axis k = z x t. */
static void turn(limen_scene *s, limen_node n, double deg)
{
    double a = deg * M_PI / 180.0, phi = 30 * M_PI / 180.0;
    float normal[3] = { (float)(sin(a) * cos(phi)), (float)(sin(a) * sin(phi)), (float)cos(a) };
    float up[3] = { (float)-sin(phi), (float)cos(phi), 0 };
    CHECK_OK(limen_node_set_facing(s, n, normal, up));
}

/* Pixel centres of view v's scissor that its surface covers, seen from v's parent (double
 * precision; the surface cut by the parent's clip plane and kept in front of its eye). */
static long covered_pixels(limen_scene *s, const limen_plan *p, const limen_view *v, int w, int h)
{
    const limen_view *par = limen_plan_view(p, v->parent);
    float wm[16], dims[3];
    limen_node_world_matrix(s, v->through, wm);
    limen_node_get_dims(s, v->through, dims);
    double a[16][4], b[16][4];
    const double lx[4] = { -0.5, 0.5, 0.5, -0.5 }, ly[4] = { -0.5, -0.5, 0.5, 0.5 };
    for (int i = 0; i < 4; i++) {
        for (int r = 0; r < 3; r++)
            a[i][r] = (double)wm[r] * lx[i] * dims[0] + (double)wm[4 + r] * ly[i] * dims[1] + wm[12 + r];
        a[i][3] = 1;
    }
    int n = 4;
    if (par->depth > 0) {
        const double c[4] = { par->clip_plane[0], par->clip_plane[1], par->clip_plane[2], par->clip_plane[3] };
        n = limen__d_clip4(a, n, c, b, 15);
        memcpy(a, b, sizeof(double) * 4 * (size_t)n);
    }
    double V[16], P[16], PV[16];
    for (int i = 0; i < 16; i++)
        V[i] = par->view[i], P[i] = par->proj[i];
    limen__d_mul(P, V, PV);
    for (int i = 0; i < n; i++) {
        double q[4];
        for (int r = 0; r < 4; r++)
            q[r] = PV[r] * a[i][0] + PV[4 + r] * a[i][1] + PV[8 + r] * a[i][2] + PV[12 + r] * a[i][3];
        memcpy(a[i], q, sizeof q);
    }
    const double front[4] = { 0, 0, 0, 1 };   /* w >= 0, then a hair in front of the eye */
    n = limen__d_clip4(a, n, front, b, 15);
    double px[16][2];
    int m = 0;
    for (int i = 0; i < n; i++)
        if (b[i][3] > 1e-12) {
            px[m][0] = (b[i][0] / b[i][3] + 1) * 0.5 * w;
            px[m][1] = (b[i][1] / b[i][3] + 1) * 0.5 * h;
            m++;
        }
    if (m < 3)
        return 0;
    double area2 = 0;
    for (int i = 0; i < m; i++) {
        const double *e0 = px[i], *e1 = px[(i + 1) % m];
        area2 += e0[0] * e1[1] - e1[0] * e0[1];
    }
    double sg = area2 >= 0 ? 1 : -1;
    long count = 0;
    for (int y = v->scissor[1]; y < v->scissor[1] + v->scissor[3]; y++)
        for (int x = v->scissor[0]; x < v->scissor[0] + v->scissor[2]; x++) {
            double cx = x + 0.5, cy = y + 0.5;
            int in = 1;
            for (int i = 0; i < m && in; i++) {
                const double *e0 = px[i], *e1 = px[(i + 1) % m];
                double cr = (e1[0] - e0[0]) * (cy - e0[1]) - (e1[1] - e0[1]) * (cx - e0[0]);
                in = sg * cr >= 0;
            }
            count += in;
        }
    return count;
}

static void test_grazing(void)
{
    const int full = sweep_full();
    const int w = full ? 320 : 160, h = full ? 240 : 120;
    int na;
    const double *ang = angles(&na);
    limen_renderer *r = sweep_renderer(w, h, LIMEN_DEPTH_NO, 24);
    limen_plan *p = NULL;
    CHECK_OK(limen_plan_create(&p));
    FILE *csv = sweep_csv("grazing",
                          "surface turning edge-on; rect = scissor area of its view in pixels, "
                          "covered = pixel centres it covers (0 = a view of zero area)",
                          "surface,angle,views,nonfinite,rect_px,covered_px,zero_area_views,err_default");
    unsigned char *rgb = malloc((size_t)w * h * 3), *heat = malloc((size_t)w * h * 3);
    const char *names[2] = { "mirror", "portal" };
    printf("     %-7s %8s %5s %8s %8s %6s %9s\n", "surface", "angle", "views", "rect_px",
           "covered", "zero", "err_def");
    for (int si = 0; si < 2 && r && p && csv; si++) {
        limen_script *sc = check_load_script(si ? "tests/sweeps/grazing_portal.lua"
                                         : "tests/sweeps/grazing_mirror.lua");
        if (!sc)
            continue;
        limen_scene *s = limen_script_scene(sc);
        limen_node surf;
        CHECK_OK(limen_node_find(s, "surface", &surf));
        int last_view_written = 0;
        for (int k = 0; k < na; k++) {
            turn(s, surf, ang[k]);
            int nonfinite = 0;
            for (int range = 0; range < 3; range++)
                for (int clip = 0; clip < 3; clip++) {
                    limen_plan_desc pd = { .width = w, .height = h, .range = range,
                                           .limits.clip = clip };
                    CHECK_OK(limen_plan_build(p, s, &pd));
                    nonfinite += sweep_plan_nonfinite(p);
                }
            CHECK_MSG(nonfinite == 0, "%s at %g deg: %d views with NaN or Inf", names[si], ang[k],
                      nonfinite);
            unsigned char *truth = sweep_trace(s, w, h);
            double e = 1;
            if (!sweep_render(r, s, (limen_render_opts){ 0 }, rgb))
                e = sweep_diff(rgb, truth, w, h, heat);
            const limen_plan *rp = limen_renderer_plan(r);
            long rect = 0, covered = 0;
            int zero = 0, views = limen_plan_count(rp);
            for (int i = 1; i < views; i++) {
                const limen_view *v = limen_plan_view(rp, i);
                long c = covered_pixels(s, rp, v, w, h);
                rect += (long)v->scissor[2] * v->scissor[3];
                covered += c;
                zero += c == 0;
            }
            CHECK_MSG(zero == 0, "%s at %g deg: %d of %d nested views cover no pixel centre "
                      "(scissor %ld pixels)", names[si], ang[k], zero, views - 1, rect);
            CHECK_MSG(e <= SWEEP_BOUND, "%s at %g deg: the default is off on %.2f%% of pixels",
                      names[si], ang[k], 100 * e);
            fprintf(csv, "%s,%.4f,%d,%d,%ld,%ld,%d,%.6f\n", names[si], ang[k], views, nonfinite,
                    rect, covered, zero, e);
            printf("     %-7s %8.3f %5d %8ld %8ld %6d %8.3f%%\n", names[si], ang[k], views, rect,
                   covered, zero, 100 * e);
            if (truth && (ang[k] == 89 || e > SWEEP_BOUND || zero ||
                          (views > 1 && !last_view_written && k + 1 < na && ang[k + 1] > 89.9))) {
                const unsigned char *pan[3] = { rgb, truth, heat };
                sweep_png(w, h, 3, pan, "grazing_%s_%g", names[si], ang[k]);
                last_view_written = 1;
            }
            free(truth);
        }
        limen_script_destroy(sc);
    }
    if (csv)
        fclose(csv);
    free(rgb), free(heat);
    limen_plan_destroy(p);
    limen_renderer_destroy(r);
}

static const check_case cases[] = {
    { "grazing", test_grazing },
    { 0 },
};

int main(int argc, char **argv)
{
    return sweep_main(argc, argv, cases);
}
