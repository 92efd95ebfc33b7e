/* test_sweep_odd.c - stability sweep 6: configurations at the edge of what a portal or a
 * mirror is. Each scene script under tests/sweeps/odd_*.lua either renders correctly
 * against the ray tracer (stencil and texture methods, oblique and plane clipping, at most
 * 0.5% of pixels over 8/255, with at least one nested view) or is refused with a clear
 * error when the script is loaded (LIMEN_ERR_SCRIPT, the message naming the script and
 * line and saying what is wrong); the table below says which each must do.
 * Output: odd.csv, frames odd_*.png ([rendered | ray traced | difference]).
 */
#include "sweeps/sweep.h"

enum { RENDER, REFUSE };

typedef struct odd_case {
    const char *name;
    int expect;
    const char *words;      /* REFUSE: what the message must say */
} odd_case;

static const odd_case odd_cases[] = {
    { "odd_scale_up", RENDER, NULL },            /* portals 8x apart in scale, small -> large */
    { "odd_scale_down", RENDER, NULL },          /* large -> small */
    { "odd_mirror_sheared", RENDER, NULL },      /* mirror under a non-uniformly scaled parent */
    { "odd_portal_self", REFUSE, "itself" },     /* a portal whose two ends are one node */
    { "odd_portals_coincident", RENDER, NULL },  /* two portals facing at distance 0 */
    { "odd_portals_coincident_twisted", RENDER, NULL }, /* ... and turned 30 degrees */
    { NULL, 0, NULL },
};

static void test_odd(void)
{
    const int full = sweep_full();
    const int w = full ? 320 : 200, h = full ? 240 : 150;
    limen_renderer *r = sweep_renderer(w, h, LIMEN_DEPTH_NO, 24);
    FILE *csv = sweep_csv("odd", "odd configurations: rendered against the ray tracer, or "
                          "refused at load", "scene,expect,outcome,method,clip,views,err");
    unsigned char *rgb = malloc((size_t)w * h * 3), *heat = malloc((size_t)w * h * 3);
    for (const odd_case *c = odd_cases; c->name && r && csv; c++) {
        char path[256];
        snprintf(path, sizeof path, "tests/sweeps/%s.lua", c->name);
        limen_script *sc = NULL;
        limen_status st = limen_script_load(path, NULL, &sc);
        const char *msg = sc ? limen_script_error(sc) : "";
        if (c->expect == REFUSE) {
            int clear = st == LIMEN_ERR_SCRIPT && strstr(msg, path) && strstr(msg, c->words);
            printf("     %-24s refused: %s\n", c->name, st ? msg : "(loaded)");
            CHECK_MSG(clear, "%s: expected a clear refusal mentioning '%s', got status %d '%s'",
                      c->name, c->words, (int)st, msg);
            fprintf(csv, "%s,refuse,%s,-,-,0,0\n", c->name, clear ? "refused" : "loaded");
            limen_script_destroy(sc);
            continue;
        }
        CHECK_MSG(st == LIMEN_OK, "%s: expected to load, got '%s'", c->name, msg);
        if (st) {
            fprintf(csv, "%s,render,refused,-,-,0,1\n", c->name);
            limen_script_destroy(sc);
            continue;
        }
        limen_scene *s = limen_script_scene(sc);
        unsigned char *truth = sweep_trace(s, w, h);
        for (int m = 0; m < 2 && truth; m++)
            for (int clip = 0; clip < 2; clip++) {
                double e = 1;
                if (!sweep_render(r, s, (limen_render_opts){ .method = m, .limits.clip = clip },
                                  rgb))
                    e = sweep_diff(rgb, truth, w, h, heat);
                const limen_plan *p = limen_renderer_plan(r);
                int views = limen_plan_count(p);
                CHECK_MSG(sweep_plan_nonfinite(p) == 0, "%s: plan with NaN or Inf", c->name);
                CHECK_MSG(views > 1, "%s: no nested view", c->name);
                CHECK_MSG(e <= SWEEP_BOUND, "%s (%s, clip %s): %.2f%% of pixels off the ray tracer",
                          c->name, m ? "texture" : "stencil", clip ? "plane" : "oblique", 100 * e);
                fprintf(csv, "%s,render,rendered,%s,%s,%d,%.6f\n", c->name, m ? "texture" : "stencil",
                        clip ? "plane" : "oblique", views, e);
                printf("     %-24s %-8s %-8s %3d views  %6.3f%% off\n", c->name,
                       m ? "texture" : "stencil", clip ? "plane" : "oblique", views, 100 * e);
                if (m == 0 && clip == 0) {
                    const unsigned char *pan[3] = { rgb, truth, heat };
                    sweep_png(w, h, 3, pan, "%s", c->name);
                }
            }
        free(truth);
        limen_script_destroy(sc);
    }
    if (csv)
        fclose(csv);
    free(rgb), free(heat);
    limen_renderer_destroy(r);
}

static const check_case cases[] = {
    { "odd", test_odd },
    { 0 },
};

int main(int argc, char **argv)
{
    return sweep_main(argc, argv, cases);
}
