/* view.c - `limen view SCENE.lua`: a window to walk through the scene. It draws every frame
 * through the host backend (limen drawing into this program's own SDL window and context,
 * as a game would), moves the camera as a person (limen_node_slide_capsule: it stops at
 * walls, slides along them and passes through portals as objects do; N toggles free flight
 * with limen_node_move), and reloads the script whenever the file changes, keeping the camera where
 * the person stood and the last good scene while the script is broken. Lines on stdout say
 * what happened (ready, crossed, reloaded, screenshot), so that a person or a test can follow. */
#include <SDL.h>
#include <SDL_opengl.h>
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli/cli.h"
#include "limen.h"

static const char *usage =
    "usage: limen view SCENE.lua [--size WxH] [--method stencil|texture] [--depth N]\n"
    "                  [--clip oblique|plane|none] [other render options]\n"
    "                  [--eye X,Y,Z --look X,Y,Z [--up X,Y,Z]] [--shots DIR]\n"
    "                  [--speed UNITS_PER_SECOND]\n";

static const char *keys_help =
    "keys:\n"
    "  W A S D              walk forward, left, back, right (along the ground)\n"
    "  mouse (drag), arrows look around\n"
    "  E or Space           rise\n"
    "  Q or C               sink\n"
    "  Shift                run (4 times as fast)\n"
    "  N                    walk as a person who collides (the default) or fly freely\n"
    "  P                    pause or resume the scene's update(t)\n"
    "  Backspace            back to the scene's own camera\n"
    "  F12                  screenshot: SCENE-0001.png, ... in the current folder or --shots\n"
    "                       DIR, and the pose that renders or traces it again\n"
    "  F1                   these keys\n"
    "  Escape               quit\n"
    "The script reloads when its file, or a mesh or texture file it read, changes; a broken\n"
    "script leaves the last good scene.\n";

#define MAX_WATCHED 64
#define PERSON_RADIUS 0.25f         /* the walking body: a capsule of this radius, ... */
#define PERSON_BELOW_EYES 0.8f      /* ... from the eyes this far down */

/* A file the scene was read from, as it was then. */
typedef struct watched {
    char path[PATH_MAX];
    struct stat st;
} watched;

typedef struct viewer {
    const char *path, *shots;
    char name[256];                     /* the script's file name without .lua */
    limen_script_desc desc;
    limen_script *sc;
    limen_renderer *r;
    limen_render_opts ro;
    SDL_Window *win;
    SDL_GLContext gl;
    int fb_w, fb_h;
    /* the frame is drawn into a framebuffer of the viewer's own (colour, depth24/stencil8
     * renderbuffers, as limen's offscreen renderers draw), then copied to the window: a
     * window's buffer may be laid out upside down, and edges exactly on pixel centres then
     * fall to the other side, so its pixels would not be `limen render`'s */
    GLuint fbo, rb[2];
    struct {
        PFNGLGENFRAMEBUFFERSPROC GenFramebuffers;
        PFNGLDELETEFRAMEBUFFERSPROC DeleteFramebuffers;
        PFNGLBINDFRAMEBUFFERPROC BindFramebuffer;
        PFNGLGENRENDERBUFFERSPROC GenRenderbuffers;
        PFNGLDELETERENDERBUFFERSPROC DeleteRenderbuffers;
        PFNGLBINDRENDERBUFFERPROC BindRenderbuffer;
        PFNGLRENDERBUFFERSTORAGEPROC RenderbufferStorage;
        PFNGLFRAMEBUFFERRENDERBUFFERPROC FramebufferRenderbuffer;
        PFNGLCHECKFRAMEBUFFERSTATUSPROC CheckFramebufferStatus;
        PFNGLBLITFRAMEBUFFERPROC BlitFramebuffer;
    } gl_fn;
    struct stat seen;                   /* the script file as last loaded or tried */
    watched files[MAX_WATCHED];         /* the meshes and textures the last good scene read */
    int nfiles;
    int held;                           /* the person moves the camera: pose wins */
    float pose[16];                     /* the camera's world matrix while held */
    limen_cli_pose snapped;             /* the pose that made ... */
    float snapped_m[16];                /* ... this camera matrix (snap) */
    int have_snapped;
    double t, speed;
    int paused, looking, shot;
    int fly;                            /* N: free flight (no collisions) */
    float mouse_dx, mouse_dy;
    char said[1024];                    /* the last error printed (printed once) */
} viewer;

/* ------------------------------------------------------------------ messages */

static void say_error(viewer *v, const char *msg)
{
    if (!strcmp(msg, v->said))
        return;
    snprintf(v->said, sizeof v->said, "%s", msg);
    fprintf(stderr, "limen: %s\n", msg);
    fflush(stderr);
}

static limen_scene *scene(viewer *v)
{
    return limen_script_scene(v->sc);
}

/* ------------------------------------------------------------------ the camera */

static void take_pose(viewer *v)
{
    limen_node cam = limen_scene_get_camera(scene(v));
    if (cam.id && !limen_node_world_matrix(scene(v), cam, v->pose))
        v->held = 1;
}

/* The held pose onto the scene's camera (after a reload or an update that moved it). */
static void apply_pose(viewer *v)
{
    limen_node cam = limen_scene_get_camera(scene(v));
    if (!v->held || !cam.id)
        return;
    limen_node_set_parent(scene(v), cam, (limen_node){ 0 });
    limen_node_set_local_matrix(scene(v), cam, v->pose);
}

/* Rotates the pose's three axes by angle a about the unit axis u (Rodrigues). */
static void turn(float *m, const float u[3], float a)
{
    float c = cosf(a), s = sinf(a);
    for (int col = 0; col < 3; col++) {
        float *x = m + 4 * col;
        float d = u[0] * x[0] + u[1] * x[1] + u[2] * x[2];
        float cr[3] = { u[1] * x[2] - u[2] * x[1], u[2] * x[0] - u[0] * x[2],
                        u[0] * x[1] - u[1] * x[0] };
        for (int k = 0; k < 3; k++)
            x[k] = x[k] * c + cr[k] * s + u[k] * d * (1 - c);
    }
}

static void unit(float v[3])
{
    float l = sqrtf(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0)
        v[0] /= l, v[1] /= l, v[2] /= l;
}

/* Turns the held pose: yaw about the world's up, pitch about the camera's right, the
 * forward axis kept within 86 degrees of the horizon. */
static void look(viewer *v, float yaw, float pitch)
{
    static const float y_up[3] = { 0, 1, 0 };
    turn(v->pose, y_up, yaw);
    float f[3] = { -v->pose[8], -v->pose[9], -v->pose[10] }, right[3] = { v->pose[0],
                                                                          v->pose[1],
                                                                          v->pose[2] };
    unit(f);
    unit(right);
    float e = asinf(fmaxf(-1.0f, fminf(1.0f, f[1]))), lim = 1.5f;
    float e2 = fmaxf(-lim, fminf(lim, e + pitch));
    turn(v->pose, right, e2 - e);
}

/* Moves the camera by d (world units) through whatever portal the path crosses: as a person
 * who collides and slides along what it meets, or (N) flying through everything. */
static void walk(viewer *v, const float d[3])
{
    limen_scene *s = scene(v);
    limen_node cam = limen_scene_get_camera(s);
    limen_move_result res;
    apply_pose(v);
    limen_status st;
    if (v->fly) {
        st = limen_node_move(s, cam, d, &res);
    } else {
        /* a person: a capsule of radius 0.25 from the eyes 0.8 down, at the camera's scale */
        float w[16];
        limen_node_world_matrix(s, cam, w);
        float k = sqrtf(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
        limen_slide_result sr;
        st = limen_node_slide_capsule(s, cam, d, PERSON_RADIUS * k,
                                      (float[3]){ 0, -PERSON_BELOW_EYES * k, 0 }, &sr);
        res.crossed = sr.crossed;
        res.portal = sr.portal;
    }
    if (st) {
        say_error(v, limen_scene_error(s));
        return;
    }
    if (res.crossed) {
        const char *name = limen_node_get_name(s, res.portal);
        const char *to = limen_node_get_name(s, limen_portal_get_partner(s, res.portal));
        printf("crossed portal %s -> %s\n", name ? name : "?", to ? to : "?");
        fflush(stdout);
    }
    take_pose(v);
}

/* Rebuilds the camera from a pose (eye, look, up as floats) and keeps that pose for the
 * screenshot to print, so that `--eye --look --up` gives this very camera again, bit for
 * bit (the pose read back from the rebuilt camera may differ from it in the last bits).
 * (A scale that a portal pair of two sizes gave the camera is dropped: it would only move
 * the near plane.) */
static void snap(viewer *v)
{
    limen_cli_pose p;
    if (!limen_cli_pose_get(scene(v), &p) && !limen_cli_pose_apply(scene(v), &p)) {
        take_pose(v);
        v->snapped = p;
        memcpy(v->snapped_m, v->pose, sizeof v->snapped_m);
        v->have_snapped = v->held;
    }
}

static void controls(viewer *v, double dt)
{
    const Uint8 *k = SDL_GetKeyboardState(NULL);
    float fwd = (float)(k[SDL_SCANCODE_W] - k[SDL_SCANCODE_S]);
    float side = (float)(k[SDL_SCANCODE_D] - k[SDL_SCANCODE_A]);
    float rise = (float)((k[SDL_SCANCODE_E] | k[SDL_SCANCODE_SPACE]) -
                         (k[SDL_SCANCODE_Q] | k[SDL_SCANCODE_C]));
    float yaw = (float)(k[SDL_SCANCODE_LEFT] - k[SDL_SCANCODE_RIGHT]) * 1.5f * (float)dt -
                v->mouse_dx * 0.004f;
    float pitch = (float)(k[SDL_SCANCODE_UP] - k[SDL_SCANCODE_DOWN]) * 1.5f * (float)dt -
                  v->mouse_dy * 0.004f;
    v->mouse_dx = v->mouse_dy = 0;
    if (!fwd && !side && !rise && !yaw && !pitch)
        return;
    if (!v->held)
        take_pose(v);
    if (!v->held)
        return;                 /* no camera */
    if (yaw || pitch)
        look(v, yaw, pitch);
    float step = (float)(v->speed * dt) *
                 (k[SDL_SCANCODE_LSHIFT] || k[SDL_SCANCODE_RSHIFT] ? 4.0f : 1.0f);
    /* walk along the ground: the camera's forward and right without their height */
    float f[3] = { -v->pose[8], 0, -v->pose[10] }, r[3] = { v->pose[0], 0, v->pose[2] };
    if (f[0] * f[0] + f[2] * f[2] < 1e-6f)
        f[0] = -v->pose[8], f[1] = -v->pose[9], f[2] = -v->pose[10];
    unit(f);
    unit(r);
    float d[3];
    for (int i = 0; i < 3; i++)
        d[i] = step * (fwd * f[i] + side * r[i]) + (i == 1 ? step * rise : 0);
    if (fwd || side || rise)
        walk(v, d);
    else
        apply_pose(v);
    snap(v);
}

/* ------------------------------------------------------------------ the script */

static int stat_differs(const struct stat *a, const struct stat *b)
{
    return a->st_mtim.tv_sec != b->st_mtim.tv_sec || a->st_mtim.tv_nsec != b->st_mtim.tv_nsec ||
           a->st_size != b->st_size || a->st_ino != b->st_ino;
}

/* Whether the script or a mesh or texture file its scene read changed since last looked. */
static int file_changed(viewer *v)
{
    struct stat st;
    int changed = 0;
    if (!stat(v->path, &st)) {  /* (else being replaced: look again next frame) */
        changed = stat_differs(&st, &v->seen);
        v->seen = st;
    }
    for (int i = 0; i < v->nfiles; i++) {
        if (stat(v->files[i].path, &st) || !stat_differs(&st, &v->files[i].st))
            continue;
        v->files[i].st = st;
        changed = 1;
    }
    return changed;
}

/* The files the scene read (limen_scene_get_file: meshes, the files they name, textures)
 * and the modules the script required (limen_script_get_file, past the script itself), to
 * be watched from now on. */
static void watch_assets(viewer *v)
{
    v->nfiles = 0;
    for (int i = 0; v->nfiles < MAX_WATCHED; i++) {
        watched *w = &v->files[v->nfiles];
        if (limen_scene_get_file(scene(v), i, w->path, sizeof w->path))
            break;
        if (!stat(w->path, &w->st))
            v->nfiles++;
    }
    for (int i = 1; v->nfiles < MAX_WATCHED; i++) {
        watched *w = &v->files[v->nfiles];
        if (limen_script_get_file(v->sc, i, w->path, sizeof w->path))
            break;
        if (!stat(w->path, &w->st))
            v->nfiles++;
    }
}

/* Loads the script again; on failure says where and keeps the scene there is. keep: the
 * camera stays where the person stood (else the script's camera takes over). */
static void reload(viewer *v, int keep)
{
    limen_script *next = NULL;
    limen_status st = limen_script_load(v->path, &v->desc, &next);
    if (!st && limen_script_animated(next))
        st = limen_script_update(next, v->t);
    if (st) {
        v->said[0] = '\0';
        char msg[1400];
        say_error(v, limen_cli_script_error(next, st, msg, sizeof msg));
        fprintf(stderr, "limen: keeping the last good scene\n");
        limen_script_destroy(next);
        return;
    }
    if (keep && !v->held)
        take_pose(v);
    if (!keep)
        v->held = 0;
    limen_script_destroy(v->sc);
    v->sc = next;
    watch_assets(v);
    apply_pose(v);
    v->said[0] = '\0';
    printf("reloaded %s\n", v->path);
    fflush(stdout);
}

static void animate(viewer *v, double dt)
{
    if (!limen_script_animated(v->sc) || v->paused)
        return;
    v->t += dt;
    if (limen_script_update(v->sc, v->t))
        say_error(v, limen_script_error(v->sc));
    apply_pose(v);
}

/* ------------------------------------------------------------------ screenshots */

/* Writes the frame just drawn as SHOTS/NAME-NNNN.png (complete or absent) and prints the
 * pose that renders it again. */
static void screenshot(viewer *v)
{
    char path[PATH_MAX];
    const char *dir = v->shots ? v->shots : ".";
    do
        snprintf(path, sizeof path, "%s/%s-%04d.png", dir, v->name, ++v->shot);
    while (access(path, F_OK) == 0 && v->shot < 9999);
    int w, h;
    limen_renderer_get_size(v->r, &w, &h);
    unsigned char *rgb = malloc((size_t)w * (size_t)h * 3);
    /* limen_write_png writes whole or not at all (a temporary beside it, then a rename) */
    limen_status st = rgb ? limen_renderer_read_rgb(v->r, rgb) : LIMEN_ERR_NOMEM;
    bool io = !st && limen_write_png(path, w, h, rgb);
    free(rgb);
    if (st || io) {
        fprintf(stderr, "limen: screenshot %s: %s\n", path,
                io ? "cannot write it" : limen_renderer_error(v->r));
        return;
    }
    limen_cli_pose pose;
    printf("screenshot %s ", path);
    float m[16];
    limen_node cam = limen_scene_get_camera(scene(v));
    if (v->have_snapped && cam.id && !limen_node_world_matrix(scene(v), cam, m) &&
        !memcmp(m, v->snapped_m, sizeof m))
        limen_cli_pose_print(stdout, &v->snapped);
    else if (!limen_cli_pose_get(scene(v), &pose))
        limen_cli_pose_print(stdout, &pose);
    if (limen_script_animated(v->sc))
        printf(" --time %.9g", v->t);
    printf("\n");
    fflush(stdout);
}

/* ------------------------------------------------------------------ the window */

/* The viewer's framebuffer at w x h (made on first use, its storage renewed on a resize);
 * -1 where it cannot be made. */
static int frame_target(viewer *v, int w, int h)
{
    if (!v->fbo) {
#define LOAD(name) \
    if (!(*(void **)&v->gl_fn.name = SDL_GL_GetProcAddress("gl" #name))) \
        return -1;
        LOAD(GenFramebuffers) LOAD(DeleteFramebuffers) LOAD(BindFramebuffer)
        LOAD(GenRenderbuffers) LOAD(DeleteRenderbuffers) LOAD(BindRenderbuffer)
        LOAD(RenderbufferStorage) LOAD(FramebufferRenderbuffer) LOAD(CheckFramebufferStatus)
        LOAD(BlitFramebuffer)
#undef LOAD
        v->gl_fn.GenFramebuffers(1, &v->fbo);
        v->gl_fn.GenRenderbuffers(2, v->rb);
    }
    v->gl_fn.BindFramebuffer(GL_FRAMEBUFFER, v->fbo);
    v->gl_fn.BindRenderbuffer(GL_RENDERBUFFER, v->rb[0]);
    v->gl_fn.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
    v->gl_fn.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                     v->rb[0]);
    v->gl_fn.BindRenderbuffer(GL_RENDERBUFFER, v->rb[1]);
    v->gl_fn.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, w, h);
    v->gl_fn.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT,
                                     GL_RENDERBUFFER, v->rb[1]);
    GLenum status = v->gl_fn.CheckFramebufferStatus(GL_FRAMEBUFFER);
    v->gl_fn.BindRenderbuffer(GL_RENDERBUFFER, 0);
    v->gl_fn.BindFramebuffer(GL_FRAMEBUFFER, 0);
    return status == GL_FRAMEBUFFER_COMPLETE ? 0 : -1;
}

/* The frame, from the viewer's framebuffer into the window's back buffer. */
static void present(viewer *v)
{
    if (v->fbo) {
        v->gl_fn.BindFramebuffer(GL_READ_FRAMEBUFFER, v->fbo);
        v->gl_fn.BindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
        v->gl_fn.BlitFramebuffer(0, 0, v->fb_w, v->fb_h, 0, 0, v->fb_w, v->fb_h,
                                 GL_COLOR_BUFFER_BIT, GL_NEAREST);
        v->gl_fn.BindFramebuffer(GL_FRAMEBUFFER, 0);
    }
    SDL_GL_SwapWindow(v->win);
}

static void close_window(viewer *v)
{
    if (v->fbo) {
        v->gl_fn.DeleteFramebuffers(1, &v->fbo);
        v->gl_fn.DeleteRenderbuffers(2, v->rb);
    }
    if (v->gl)
        SDL_GL_DeleteContext(v->gl);
    if (v->win)
        SDL_DestroyWindow(v->win);
}

static int open_window(viewer *v, const limen_renderer_desc *rd)
{
    if (SDL_Init(SDL_INIT_VIDEO)) {
        fprintf(stderr, "limen: view: cannot open a window: %s\n", SDL_GetError());
        return -1;
    }
    SDL_GL_SetAttribute(SDL_GL_CONTEXT_PROFILE_MASK, SDL_GL_CONTEXT_PROFILE_CORE);
    SDL_GL_SetAttribute(SDL_GL_CONTEXT_MAJOR_VERSION, 3);
    SDL_GL_SetAttribute(SDL_GL_CONTEXT_MINOR_VERSION, 3);
    SDL_GL_SetAttribute(SDL_GL_DOUBLEBUFFER, 1);
    SDL_GL_SetAttribute(SDL_GL_DEPTH_SIZE, 24);
    SDL_GL_SetAttribute(SDL_GL_STENCIL_SIZE, 8);
    if (rd->msaa > 1) {
        SDL_GL_SetAttribute(SDL_GL_MULTISAMPLEBUFFERS, 1);
        SDL_GL_SetAttribute(SDL_GL_MULTISAMPLESAMPLES, rd->msaa);
    }
    int w = rd->width ? rd->width : 960, h = rd->height ? rd->height : 540;
    char title[300];
    snprintf(title, sizeof title, "limen - %s", v->name);
    v->win = SDL_CreateWindow(title, SDL_WINDOWPOS_UNDEFINED, SDL_WINDOWPOS_UNDEFINED, w, h,
                              SDL_WINDOW_OPENGL | SDL_WINDOW_RESIZABLE | SDL_WINDOW_ALLOW_HIGHDPI);
    if (!v->win || !(v->gl = SDL_GL_CreateContext(v->win))) {
        fprintf(stderr, "limen: view: cannot open an OpenGL 3.3 window: %s\n", SDL_GetError());
        return -1;
    }
    SDL_GL_MakeCurrent(v->win, v->gl);
    SDL_GL_SetSwapInterval(1);
    SDL_GL_GetDrawableSize(v->win, &v->fb_w, &v->fb_h);
    limen_renderer_desc d = *rd;
    d.backend = LIMEN_BACKEND_HOST;
    d.gl_loader = SDL_GL_GetProcAddress;
    d.width = v->fb_w;
    d.height = v->fb_h;
    d.msaa = 0;
    /* multisampled, the window's own buffer resolves the samples */
    if (rd->msaa <= 1 && frame_target(v, v->fb_w, v->fb_h)) {
        fprintf(stderr, "limen: view: cannot make a framebuffer\n");
        return -1;
    }
    d.framebuffer = v->fbo;
    limen_status st = limen_renderer_create(&d, &v->r);
    if (st) {
        fprintf(stderr, "limen: %s\n", v->r ? limen_renderer_error(v->r) : limen_status_string(st));
        return -1;
    }
    return 0;
}

static void set_title(viewer *v, double ms, const limen_frame_stats *fs)
{
    char title[400];
    snprintf(title, sizeof title, "limen - %s (%.1f ms, %d views, %.2f M samples)%s", v->name,
             ms, fs->views, (double)fs->samples * 1e-6, v->paused ? " paused" : "");
    SDL_SetWindowTitle(v->win, title);
}

/* One pass over the events; returns 0 to go on, 1 to quit. */
static int events(viewer *v, int *shot)
{
    SDL_Event e;
    while (SDL_PollEvent(&e)) {
        if (e.type == SDL_QUIT)
            return 1;
        if (e.type == SDL_KEYDOWN && !e.key.repeat) {
            switch (e.key.keysym.sym) {
            case SDLK_ESCAPE:
                return 1;
            case SDLK_F12:
                *shot = 1;
                break;
            case SDLK_F1:
                fputs(keys_help, stdout);
                fflush(stdout);
                break;
            case SDLK_n:
                v->fly = !v->fly;
                printf("%s\n", v->fly ? "flying (no collisions)" : "walking (collisions)");
                fflush(stdout);
                break;
            case SDLK_p:
                v->paused = !v->paused;
                printf("%s at t = %.3f\n", v->paused ? "paused" : "resumed", v->t);
                fflush(stdout);
                break;
            case SDLK_BACKSPACE:
                reload(v, 0);
                break;
            default:
                break;
            }
        } else if (e.type == SDL_MOUSEBUTTONDOWN && e.button.button == SDL_BUTTON_LEFT) {
            v->looking = 1;
            SDL_SetRelativeMouseMode(SDL_TRUE);
        } else if (e.type == SDL_MOUSEBUTTONUP && e.button.button == SDL_BUTTON_LEFT) {
            v->looking = 0;
            SDL_SetRelativeMouseMode(SDL_FALSE);
        } else if (e.type == SDL_MOUSEMOTION && v->looking) {
            v->mouse_dx += (float)e.motion.xrel;
            v->mouse_dy += (float)e.motion.yrel;
        }
    }
    return 0;
}

static int run(viewer *v)
{
    Uint64 freq = SDL_GetPerformanceFrequency(), last = SDL_GetPerformanceCounter();
    double title_at = 0, acc_ms = 0;
    int acc_n = 0, ready = 0;
    for (;;) {
        int shot = 0;
        if (events(v, &shot))
            return 0;
        Uint64 now = SDL_GetPerformanceCounter();
        double dt = (double)(now - last) / (double)freq;
        last = now;
        if (dt > 0.1)
            dt = 0.1;           /* a stall (a reload, a slow frame) is not a long walk */
        if (file_changed(v))
            reload(v, 1);
        animate(v, dt);
        controls(v, dt);
        int w, h;
        SDL_GL_GetDrawableSize(v->win, &w, &h);
        if ((w != v->fb_w || h != v->fb_h) && w > 0 && h > 0 &&
            (!v->fbo || !frame_target(v, w, h)) &&
            !limen_renderer_set_viewport(v->r, v->fbo, 0, 0, w, h))
            v->fb_w = w, v->fb_h = h;
        limen_frame_stats fs = { 0 };
        if (limen_render_frame(v->r, scene(v), &v->ro, &fs))
            say_error(v, limen_renderer_error(v->r));
        else if (shot)
            screenshot(v);
        if (!ready) {
            ready = 1;
            printf("view %s: %dx%d, %s; F1 for the keys\n", v->path, v->fb_w, v->fb_h,
                   limen_renderer_gl_info(v->r));
            fflush(stdout);
        }
        acc_ms += fs.ms;
        acc_n++;
        title_at += dt;
        if (title_at >= 0.25 || acc_n == 1) {
            set_title(v, acc_ms / acc_n, &fs);
            title_at = 0, acc_ms = 0, acc_n = 0;
        }
        present(v);
    }
}

int limen_cli_view(int argc, char **argv)
{
    viewer v = { .speed = 2.0 };
    /* the viewer's own options; the rest are render's */
    char **rest = calloc((size_t)argc + 1, sizeof *rest);
    int nrest = 0;
    limen_cli_pose pose = { 0 };
    limen_renderer_desc rd;
    if (!rest)
        return 1;
    for (int i = 0; i < argc; i++) {
        const char *val = i + 1 < argc ? argv[i + 1] : NULL;
        if (!strcmp(argv[i], "--shots") || !strcmp(argv[i], "--speed")) {
            bool shots = !strcmp(argv[i], "--shots");
            double sp = 0;
            if (!val || (!shots && (limen_cli_parse_double(val, &sp) || !(sp > 0)))) {
                fprintf(stderr, "limen: %s needs %s\n", argv[i],
                        shots ? "a folder" : "a positive number");
                free(rest);
                return 2;
            }
            if (shots)
                v.shots = val;
            else
                v.speed = sp;
            i++;
        } else if (!strcmp(argv[i], "-h") || !strcmp(argv[i], "--help")) {
            fputs(usage, stdout);
            fputs(keys_help, stdout);
            free(rest);
            return 0;
        } else {
            rest[nrest++] = argv[i];
        }
    }
    int rc = limen_cli_render_options(nrest, rest, &v.path, &rd, &v.ro, &v.desc, &pose);
    free(rest);
    if (rc)
        return rc;
    if (v.ro.method == LIMEN_METHOD_NAIVE) {
        fprintf(stderr, "limen: view: the naive method is for comparisons; use stencil or "
                        "texture\n");
        return 2;
    }
    const char *base = strrchr(v.path, '/');
    snprintf(v.name, sizeof v.name, "%s", base ? base + 1 : v.path);
    size_t n = strlen(v.name);
    if (n > 4 && !strcmp(v.name + n - 4, ".lua"))
        v.name[n - 4] = '\0';
    file_changed(&v);
    limen_status st = limen_script_load(v.path, &v.desc, &v.sc);
    if (!st && limen_script_animated(v.sc))
        st = limen_script_update(v.sc, 0);
    if (st) {
        char msg[1400];
        fprintf(stderr, "limen: %s\n", limen_cli_script_error(v.sc, st, msg, sizeof msg));
        limen_script_destroy(v.sc);
        return 1;
    }
    watch_assets(&v);
    if (pose.given) {
        if (limen_cli_pose_apply(scene(&v), &pose)) {
            limen_script_destroy(v.sc);
            return 1;
        }
        take_pose(&v);
    }
    rc = open_window(&v, &rd) ? 1 : run(&v);
    limen_renderer_destroy(v.r);
    close_window(&v);
    SDL_Quit();
    limen_script_destroy(v.sc);
    return rc;
}
