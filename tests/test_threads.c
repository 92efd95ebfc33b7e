/* test_threads.c - no global state: two scenes and two renderers, each on its own thread,
 * render the same pictures as they do alone. */
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

static const check_case cases[] = {
    { "osmesa_osmesa", test_osmesa_osmesa },
    { "osmesa_egl", test_osmesa_egl },
    { 0 },
};

int main(int argc, char **argv)
{
    return check_run(argc, argv, cases);
}
