/* test_threads.c - no global state: two scenes and two renderers, each on its own thread,
 * render the same pictures as they do alone; and const readers of one scene never write
 * it, so several threads may read it at once. */
#include <pthread.h>
#include <stdlib.h>

#include "check.h"
#include "limen.h"

#define W 160
#define H 120
#define FRAMES 4

typedef struct job {
    const char *scene;
    limen_backend backend;
    limen_method method;
    unsigned char *frames[FRAMES];
    int failed;
    char err[256];
} job;

static void *run(void *arg)
{
    job *j = arg;
    limen_script *sc = NULL;
    limen_renderer *r = NULL;
    if (limen_script_load(j->scene, NULL, &sc)) {
        snprintf(j->err, sizeof j->err, "%s", limen_script_error(sc));
        j->failed = 1;
    } else if (limen_renderer_create(&(limen_renderer_desc){ .backend = j->backend, .width = W,
                                                             .height = H },
                                     &r)) {
        snprintf(j->err, sizeof j->err, "%s", limen_renderer_error(r));
        j->failed = 1;
    }
    for (int f = 0; f < FRAMES && !j->failed; f++) {
        j->frames[f] = malloc(W * H * 3);
        if (limen_script_update(sc, 0.25 * f) ||
            limen_render_frame(r, limen_script_scene(sc), &(limen_render_opts){ .method = j->method },
                               NULL) ||
            limen_renderer_read_rgb(r, j->frames[f])) {
            snprintf(j->err, sizeof j->err, "%s", limen_renderer_error(r));
            j->failed = 1;
        }
    }
    limen_renderer_destroy(r);
    limen_script_destroy(sc);
    return NULL;
}

static void free_job(job *j)
{
    for (int f = 0; f < FRAMES; f++)
        free(j->frames[f]);
}

static void two_threads(limen_backend b0, limen_backend b1)
{
    job alone[2] = { { "scenes/moving_portal.lua", b0, LIMEN_METHOD_STENCIL, { 0 }, 0, "" },
                     { "scenes/corridor.lua", b1, LIMEN_METHOD_TEXTURE, { 0 }, 0, "" } };
    job together[2] = { alone[0], alone[1] };
    run(&alone[0]);
    run(&alone[1]);
    pthread_t t[2];
    for (int i = 0; i < 2; i++)
        CHECK(pthread_create(&t[i], NULL, run, &together[i]) == 0);
    for (int i = 0; i < 2; i++)
        pthread_join(t[i], NULL);
    for (int i = 0; i < 2; i++) {
        CHECK_MSG(!alone[i].failed && !together[i].failed, "%s: %s%s", alone[i].scene,
                  alone[i].err, together[i].err);
        for (int f = 0; f < FRAMES && !alone[i].failed && !together[i].failed; f++)
            CHECK_MSG(memcmp(alone[i].frames[f], together[i].frames[f], W * H * 3) == 0,
                      "%s frame %d differs when rendered beside another scene", alone[i].scene, f);
        free_job(&alone[i]);
        free_job(&together[i]);
    }
}

static void test_osmesa_osmesa(void)
{
    two_threads(LIMEN_BACKEND_OSMESA, LIMEN_BACKEND_OSMESA);
}

static void test_osmesa_egl(void)
{
    two_threads(LIMEN_BACKEND_OSMESA, LIMEN_BACKEND_EGL);
}

/* ------------------------------------------------------------------ readers of one scene */

typedef struct reader {
    const limen_scene *s;
    limen_node good, stale;
    int wrong;
} reader;

/* Const calls only, half of them failing (a stale handle, a missing name): before, each
 * failure wrote the scene's message, so two readers raced on it. */
static void *read_scene(void *arg)
{
    reader *r = arg;
    for (int i = 0; i < 20000; i++) {
        float v[3], a[3], b[3], cell, fovy;
        limen_node found;
        r->wrong += limen_node_get_position(r->s, r->good, v) != LIMEN_OK;
        r->wrong += limen_node_get_position(r->s, r->stale, v) != LIMEN_ERR_HANDLE;
        r->wrong += limen_node_get_dims(r->s, r->stale, v) != LIMEN_ERR_HANDLE;
        r->wrong += limen_node_get_checker(r->s, r->stale, a, b, &cell) != LIMEN_ERR_HANDLE;
        r->wrong += limen_camera_get_lens(r->s, r->stale, &fovy, NULL, NULL) != LIMEN_ERR_HANDLE;
        r->wrong += limen_surface_get(r->s, r->good, NULL, NULL, NULL, NULL) != LIMEN_ERR_HANDLE;
        r->wrong += limen_node_find(r->s, "nobody", &found) != LIMEN_ERR_HANDLE;
        r->wrong += limen_node_find(r->s, "ball", &found) != LIMEN_OK || found.id != r->good.id;
        r->wrong += limen_node_get_name(r->s, r->stale) != NULL;
        r->wrong += limen_scene_nodes(r->s, NULL, 0) != 2;
    }
    return NULL;
}

static void test_readers_share_a_scene(void)
{
    limen_scene *s = NULL;
    CHECK(limen_scene_create(NULL, &s) == LIMEN_OK);
    limen_node ball, cam, gone;
    CHECK(limen_node_create(s, LIMEN_NODE_SPHERE, "ball", &ball) == LIMEN_OK);
    CHECK(limen_node_create(s, LIMEN_NODE_CAMERA, "cam", &cam) == LIMEN_OK);
    CHECK(limen_node_create(s, LIMEN_NODE_GROUP, "gone", &gone) == LIMEN_OK);
    CHECK(limen_node_destroy(s, gone) == LIMEN_OK);
    CHECK(limen_scene_error(s)[0] == 0);
    reader rd[4];
    pthread_t t[4];
    for (int i = 0; i < 4; i++) {
        rd[i] = (reader){ s, ball, gone, 0 };
        CHECK(pthread_create(&t[i], NULL, read_scene, &rd[i]) == 0);
    }
    for (int i = 0; i < 4; i++) {
        pthread_join(t[i], NULL);
        CHECK_MSG(rd[i].wrong == 0, "reader %d: %d wrong answers", i, rd[i].wrong);
    }
    CHECK_MSG(limen_scene_error(s)[0] == 0, "readers wrote the message: %s", limen_scene_error(s));
    limen_scene_destroy(s);
}

static const check_case cases[] = {
    { "osmesa_osmesa", test_osmesa_osmesa },
    { "osmesa_egl", test_osmesa_egl },
    { "readers_share_a_scene", test_readers_share_a_scene },
    { 0 },
};

int main(int argc, char **argv)
{
    return check_run(argc, argv, cases);
}
