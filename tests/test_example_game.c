/* test_example_game.c - examples/own_renderer.c, a game that draws limen's draw list with
 * OpenGL of its own, against limen's own renderer: its frames must match (the stencil
 * method's list), and must stop matching where the game leaves out a step the list asks for. */
#define LIMEN_EXAMPLE_NO_MAIN
#include "../examples/own_renderer.c"

#include <dirent.h>

#include "check.h"
#include "load.h"

#define W 320
#define H 240

static game *the_game;
static limen_renderer *limen_r[2];              /* limen's own renderer, for NO and ZO */

static game *get_game(void)
{
    if (!the_game)
        the_game = game_create(W, H);
    CHECK_MSG(the_game, "cannot set up the game's OpenGL context");
    return the_game;
}

static void write_png(const char *name, const unsigned char *rgb)
{
    const char *dir = getenv("LIMEN_BUILD");
    char path[512];
    snprintf(path, sizeof path, "%s/example_%s.png", dir ? dir : "build", name);
    CHECK_OK(limen_write_png(path, W, H, rgb));
}

/* A change to the list before the game draws it (tests of what a left-out step does):
 * returns 0 to drop command c. */
typedef int (*tamper_fn)(limen_draw_cmd *c);

/* The game's frame with the list changed by tamper: the list built (and drawn) as the game
 * does, then a changed copy drawn. */
static int tampered_frame(game *g, limen_scene *s, limen_depth_range range,
                          limen_clip_method clip, tamper_fn tamper,
                          unsigned char *rgb)
{
    int rc = game_frame(g, s, range, clip, rgb);
    if (rc || !tamper)
        return rc;
    const limen_draw_cmd *cmd;
    int n = limen_drawlist_commands(g->list, &cmd), m = 0;
    limen_draw_cmd *copy = malloc(sizeof *copy * (size_t)(n ? n : 1));
    for (int i = 0; copy && i < n; i++)
        if ((copy[m] = cmd[i], tamper(&copy[m])))
            m++;
    rc = copy ? game_draw(g, copy, m, range, rgb) : -1;
    free(copy);
    return rc;
}

/* Draws the scene with the game and with limen's renderer; returns how the frames differ
 * (largest difference 256 where a frame failed). */
static limen_diff frame_diff(const char *name, limen_scene *s, limen_depth_range range,
                             limen_clip_method clip, tamper_fn tamper)
{
    static unsigned char mine[W * H * 3], ref[W * H * 3], heat[W * H * 3];
    limen_diff d = { 1.0, 0, 0, 256 };
    game *g = get_game();
    if (!g || !s)
        return d;
    int ok = tampered_frame(g, s, range, clip, tamper, mine) == 0;
    CHECK_MSG(ok, "%s: the game's frame failed", name);
    int views = limen_plan_count(g->plan), planes = 0;
    for (int i = 1; i < views; i++)
        planes += limen_plan_view(g->plan, i)->clip == LIMEN_CLIP_PLANE;

    limen_renderer **r = &limen_r[range == LIMEN_DEPTH_ZO];
    if (!*r) {
        limen_renderer_desc rd = { .width = W, .height = H, .depth_range = range };
        limen_status st = limen_renderer_create(&rd, r);
        CHECK_MSG(st == LIMEN_OK, "limen renderer: %s", limen_renderer_error(*r));
        if (st) {
            limen_renderer_destroy(*r);
            *r = NULL;
            return d;
        }
    }
    limen_render_opts o = { .method = LIMEN_METHOD_STENCIL, .limits.clip = clip };
    CHECK_OK(limen_render_frame(*r, s, &o, NULL));
    CHECK_OK(limen_renderer_read_rgb(*r, ref));
    CHECK_OK(limen_image_diff(mine, ref, W, H, 8, &d, heat));
    printf("     %-22s %3d views (%2d clip planes): %.3f%% of pixels differ (largest %d/255, "
           "PSNR %.1f dB)\n", name, views, planes, 100.0 * d.bad_share, d.max_delta, d.psnr);
    write_png(name, mine);
    if (!ok || (!tamper && d.max_delta > 1)) {
        char diff_name[128];
        snprintf(diff_name, sizeof diff_name, "%s_diff", name);
        write_png(diff_name, heat);
    }
    if (!ok)
        d.max_delta = 256;
    return d;
}

/* No pixel of the game's frame may differ from limen's by more than 1/255: the game draws
 * the same list with the same tessellation, so only rounding may differ. */
static void compare(const char *name, limen_scene *s, limen_depth_range range,
                    limen_clip_method clip)
{
    limen_diff d = frame_diff(name, s, range, clip, NULL);
    CHECK_MSG(d.max_delta <= 1, "%s: pixels differ from limen's by up to %d/255 (%.3f%% by "
              "more than 8/255)", name, d.max_delta, 100.0 * d.bad_share);
}

static void compare_script(const char *path, const char *name, limen_depth_range range,
                           limen_clip_method clip, int min_views)
{
    limen_script *sc = check_load_script(path);
    if (!sc)
        return;
    compare(name, limen_script_scene(sc), range, clip);
    CHECK_MSG(the_game && limen_plan_count(the_game->plan) >= min_views,
              "%s: expected at least %d views", name, min_views);
    limen_script_destroy(sc);
}

static void test_mirror_room(void)
{
    compare_script("scenes/mirror_room.lua", "mirror_room", LIMEN_DEPTH_NO, LIMEN_CLIP_OBLIQUE, 2);
}

static void test_portals(void)
{
    compare_script("scenes/portals.lua", "portals", LIMEN_DEPTH_NO, LIMEN_CLIP_OBLIQUE, 2);
}

/* Mirror walls wider than their room poke through each other: in the reflected corners
 * what lies beyond the exit plane must be cut, surfaces included. */
static void test_crossing_walls(void)
{
    compare_script("tests/scenes/mirror_box_crossing.lua", "crossing_walls", LIMEN_DEPTH_NO,
                   LIMEN_CLIP_OBLIQUE, 20);
}

static void test_corridor(void)
{
    compare_script("scenes/corridor.lua", "corridor", LIMEN_DEPTH_NO, LIMEN_CLIP_OBLIQUE, 8);
}

/* Triangle meshes from files (flat and smooth), drawn at the level of detail limen picks
 * for each view, between mirrors that repeat them. */
static void test_meshes(void)
{
    compare_script("scenes/hall_of_mirrors.lua", "hall_of_mirrors", LIMEN_DEPTH_NO,
                   LIMEN_CLIP_OBLIQUE, 6);
}

/* Textures on planes, a box and meshes, and lamps with a range. */
static void test_textures_ranges(void)
{
    compare_script("scenes/portal_rooms.lua", "portal_rooms", LIMEN_DEPTH_NO, LIMEN_CLIP_OBLIQUE,
                   2);
}

/* A bunny halfway through a portal: drawn cut at it, and its copy cut at the partner, where
 * it comes out facing the camera (a tenth of the frame: missing, the frame fails). */
static void test_clones(void)
{
    compare_script("scenes/portal_statue.lua", "portal_statue", LIMEN_DEPTH_NO,
                   LIMEN_CLIP_OBLIQUE, 3);
    const limen_clone *clones;
    CHECK_MSG(the_game && limen_plan_clones(the_game->plan, &clones) == 1,
              "portal_statue: the bunny should be passing through the blue portal");
}

/* The clip-space convention is the game's choice: Direct3D/Vulkan-style depth in [0, 1]
 * (here glClipControl) just asks the planner for LIMEN_DEPTH_ZO projections. */
static void test_depth_zo(void)
{
    compare_script("scenes/corridor.lua", "corridor_zo", LIMEN_DEPTH_ZO, LIMEN_CLIP_OBLIQUE, 8);
}

/* User clip planes instead of oblique projections: every nested view uses gl_ClipDistance.
 * The yellow sphere right behind the mirror must not leak into the reflection. */
static void test_clip_plane(void)
{
    compare_script("scenes/mirror_room.lua", "mirror_room_plane", LIMEN_DEPTH_NO,
                   LIMEN_CLIP_PLANE, 2);
    for (int i = 1; the_game && i < limen_plan_count(the_game->plan); i++)
        CHECK(limen_plan_view(the_game->plan, i)->clip == LIMEN_CLIP_PLANE);
}

/* A game loop: the player walks into the blue portal (limen_node_move carries the camera
 * out of the orange one) while the game bobs the red ball; every frame matches limen's. */
static void test_game_loop(void)
{
    limen_script *sc = check_load_script("scenes/portals.lua");
    if (!sc)
        return;
    limen_scene *s = limen_script_scene(sc);
    limen_node cam = limen_scene_get_camera(s), ball;
    CHECK_OK(limen_node_find(s, "red", &ball));
    float start[3], pos[3];
    CHECK_OK(limen_node_get_position(s, cam, start));
    /* towards the blue portal's centre at eye height, and a little beyond it */
    const float goal[3] = { -3.99f, start[1], 0.0f };
    const int frames = 8;
    float step[3];
    for (int k = 0; k < 3; k++)
        step[k] = 1.1f * (goal[k] - start[k]) / (float)frames;
    int crossed = 0;
    for (int f = 0; f < frames; f++) {
        /* game logic: input moves the player, scripts move things */
        limen_move_result mv;
        CHECK_OK(limen_node_move(s, cam, step, &mv));
        crossed += mv.crossed;
        CHECK_OK(limen_node_set_position(s, ball,
                                         (float[3]){ 0, 0.5f + 0.4f * sinf((float)f), -2 }));
        char name[32];
        snprintf(name, sizeof name, "walk_%d", f);
        compare(name, s, LIMEN_DEPTH_NO, LIMEN_CLIP_OBLIQUE);
    }
    CHECK_OK(limen_node_get_position(s, cam, pos));
    CHECK_MSG(crossed == 1, "the camera passed %d portals, expected 1", crossed);
    CHECK_MSG(pos[0] > 3.0f, "the camera is at x = %g, not beside the orange portal", pos[0]);
    limen_script_destroy(sc);
}

static int by_name(const void *a, const void *b)
{
    return strcmp(*(const char *const *)a, *(const char *const *)b);
}

/* Every gallery scene (each .lua in scenes/, however many there are). */
static void test_gallery(void)
{
    char *names[256];
    int n = 0;
    DIR *dir = opendir("scenes");
    CHECK_MSG(dir, "cannot list scenes/");
    for (struct dirent *e; dir && n < 256 && (e = readdir(dir));) {
        size_t len = strlen(e->d_name);
        if (len > 4 && !strcmp(e->d_name + len - 4, ".lua") && (names[n] = strdup(e->d_name)))
            n++;
    }
    if (dir)
        closedir(dir);
    qsort(names, (size_t)n, sizeof *names, by_name);
    CHECK_MSG(n >= 17, "only %d gallery scenes", n);
    for (int i = 0; i < n; i++) {
        char path[512], name[300];
        snprintf(path, sizeof path, "scenes/%s", names[i]);
        limen_script *sc = check_load_script(path);
        snprintf(name, sizeof name, "g_%.*s", (int)strlen(names[i]) - 4, names[i]);
        if (sc)
            compare(name, limen_script_scene(sc), LIMEN_DEPTH_NO, LIMEN_CLIP_OBLIQUE);
        limen_script_destroy(sc);
        free(names[i]);
    }
}

static int drop_stencil_writes(limen_draw_cmd *c)
{
    return c->op == LIMEN_DRAW_CLEAR || c->state.stencil_pass == LIMEN_STENCIL_KEEP;
}

static int drop_seals(limen_draw_cmd *c)
{
    return c->state.stencil_pass != LIMEN_STENCIL_DECR;
}

static int drop_clip_planes(limen_draw_cmd *c)
{
    c->state.clip_on = 0;
    return 1;
}

/* The matches above mean something only if a game that leaves out a step of the list no
 * longer matches: without the marks and seals (the commands that write stencil) the
 * mirrors of the mirror box show no reflection; without the seals alone (its 272 views
 * count depth in stencil) a sibling's view lands in its neighbour's pixels; without the
 * clip planes of the plane method what stands behind the mirror leaks into it. */
static void test_steps_matter(void)
{
    static const struct {
        const char *path, *name, *tampered;
        limen_clip_method clip;
        tamper_fn fn;
    } cases[] = { { "tests/scenes/mirror_box.lua", "mirror_box", "mirror_box_no_marks",
                    LIMEN_CLIP_OBLIQUE, drop_stencil_writes },
                  { "tests/scenes/mirror_box.lua", NULL, "mirror_box_no_seals",
                    LIMEN_CLIP_OBLIQUE, drop_seals },
                  { "scenes/mirror_room.lua", "mirror_room_plane2", "mirror_room_no_clip",
                    LIMEN_CLIP_PLANE, drop_clip_planes } };
    for (int i = 0; i < 3; i++) {
        limen_script *sc = check_load_script(cases[i].path);
        if (!sc)
            continue;
        limen_scene *s = limen_script_scene(sc);
        if (cases[i].name)                      /* (the untouched list matches) */
            compare(cases[i].name, s, LIMEN_DEPTH_NO, cases[i].clip);
        limen_diff d = frame_diff(cases[i].tampered, s, LIMEN_DEPTH_NO, cases[i].clip, cases[i].fn);
        CHECK_MSG(d.max_delta <= 255 && d.bad_share > 0.01, "%s: only %.3f%% of pixels differ",
                  cases[i].tampered, 100 * d.bad_share);
        limen_script_destroy(sc);
    }
}

static const check_case cases[] = {
    { "mirror_room", test_mirror_room }, { "portals", test_portals },
    { "corridor", test_corridor },       { "depth_zo", test_depth_zo },
    { "clip_plane", test_clip_plane },   { "game_loop", test_game_loop },
    { "crossing_walls", test_crossing_walls }, { "meshes", test_meshes },
    { "textures_ranges", test_textures_ranges }, { "clones", test_clones },
    { "steps_matter", test_steps_matter },
    { "gallery", test_gallery },
    { 0 },
};

int main(int argc, char **argv)
{
    int rc = check_run(argc, argv, cases);
    limen_renderer_destroy(limen_r[0]);
    limen_renderer_destroy(limen_r[1]);
    if (the_game)
        game_destroy(the_game);
    return rc;
}
