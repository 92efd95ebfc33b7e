/* walk.c - a small game on SDL2 that lets limen draw into its own window.
 *
 * The game owns the window and the OpenGL context (SDL); limen owns nothing but its scene
 * and a renderer created with LIMEN_BACKEND_HOST, which draws the planned view tree (mirror
 * and portals included) into the window's framebuffer and gives the GL state back, so that
 * the game draws on top with its own GL (here a crosshair). The scene is built in C, and
 * the player walks as a body of a person's size (limen_node_slide_capsule: a capsule from
 * the eyes down) that stops at walls and shapes, slides along them, and passes through a
 * portal exactly as any object would.
 *
 *     make examples && build/examples/walk
 *     W A S D walk, drag the mouse or use the arrows to look, Escape quits.
 *     build/examples/walk --frames 60 --autopilot --shot walk.png   (walks on its own)
 */
#include <SDL.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "limen.h"

typedef struct world {
    limen_scene *s;
    limen_node cam;
} world;

static limen_node add(limen_scene *s, limen_node_kind kind, const char *name, float x, float y,
                      float z)
{
    limen_node n;
    limen_node_create(s, kind, name, &n);
    limen_node_set_position(s, n, (float[3]){ x, y, z });
    return n;
}

/* A room with a mirror on its north wall and a portal pair on its west and east walls. */
static int build(world *w)
{
    if (limen_scene_create(NULL, &w->s))
        return -1;
    limen_scene *s = w->s;
    limen_scene_set_background(s, (float[3]){ 0.1f, 0.1f, 0.12f });
    limen_scene_set_ambient(s, 0.3f);
    add(s, LIMEN_NODE_LIGHT, "light", 0, 2.8f, 1);

    limen_node floor = add(s, LIMEN_NODE_QUAD, "floor", 0, 0, 0);
    limen_node_set_facing(s, floor, (float[3]){ 0, 1, 0 }, NULL);
    limen_node_set_dims(s, floor, (float[3]){ 8, 8, 0 });
    limen_node_set_checker(s, floor, (float[3]){ 0.8f, 0.8f, 0.8f },
                           (float[3]){ 0.3f, 0.3f, 0.3f }, 1);
    static const struct { const char *name; float x, z, nx, nz, c[3]; } walls[] = {
        { "west wall", -4, 0, 1, 0, { 0.7f, 0.7f, 0.75f } },
        { "east wall", 4, 0, -1, 0, { 0.75f, 0.7f, 0.7f } },
        { "north wall", 0, -4, 0, 1, { 0.6f, 0.65f, 0.6f } },
    };
    for (int i = 0; i < 3; i++) {
        limen_node wall = add(s, LIMEN_NODE_QUAD, walls[i].name, walls[i].x, 1.5f, walls[i].z);
        limen_node_set_facing(s, wall, (float[3]){ walls[i].nx, 0, walls[i].nz }, NULL);
        limen_node_set_dims(s, wall, (float[3]){ 8, 3, 0 });
        limen_node_set_color(s, wall, walls[i].c);
    }
    limen_node mirror = add(s, LIMEN_NODE_MIRROR, "mirror", 0, 1.5f, -3.99f);
    limen_node_set_dims(s, mirror, (float[3]){ 3, 2, 0 });
    limen_node blue = add(s, LIMEN_NODE_PORTAL, "blue", -3.99f, 1.1f, 0);
    limen_node orange = add(s, LIMEN_NODE_PORTAL, "orange", 3.99f, 1.1f, 0);
    limen_node_set_facing(s, blue, (float[3]){ 1, 0, 0 }, NULL);
    limen_node_set_facing(s, orange, (float[3]){ -1, 0, 0 }, NULL);
    limen_node_set_dims(s, blue, (float[3]){ 1.2f, 2, 0 });
    limen_node_set_dims(s, orange, (float[3]){ 1.2f, 2, 0 });
    limen_surface_set_fill(s, blue, (float[3]){ 0.1f, 0.3f, 1 });
    limen_surface_set_fill(s, orange, (float[3]){ 1, 0.5f, 0.1f });
    limen_portal_link(s, blue, orange);

    limen_node ball = add(s, LIMEN_NODE_SPHERE, "ball", 0, 0.5f, -2);
    limen_node_set_dims(s, ball, (float[3]){ 0.5f, 0, 0 });
    limen_node_set_color(s, ball, (float[3]){ 0.9f, 0.1f, 0.1f });
    limen_node crate = add(s, LIMEN_NODE_BOX, "crate", 2.5f, 0.4f, -1);
    limen_node_set_dims(s, crate, (float[3]){ 0.8f, 0.8f, 0.8f });
    limen_node_set_color(s, crate, (float[3]){ 0.1f, 0.8f, 0.3f });

    /* the player: a camera in front of the blue portal, looking into it */
    w->cam = add(s, LIMEN_NODE_CAMERA, "player", 0, 0, 0);
    limen_node_look_at(s, w->cam, (float[3]){ -1.5f, 1.4f, 0.2f }, (float[3]){ -4, 1.3f, 0 },
                       (float[3]){ 0, 1, 0 });
    limen_scene_set_camera(s, w->cam);
    return strcmp(limen_scene_error(s), "") ? -1 : 0;
}

/* Turns the camera about the world's up by yaw and about its own right by pitch. */
static void look(world *w, float yaw, float pitch)
{
    float m[16], eye[3], f[3];
    limen_node_world_matrix(w->s, w->cam, m);
    for (int k = 0; k < 3; k++)
        eye[k] = m[12 + k], f[k] = -m[8 + k];
    float len = sqrtf(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]);
    float e = asinf(fmaxf(-1, fminf(1, f[1] / len))) + pitch;
    float a = atan2f(f[0], -f[2]) - yaw;
    e = fmaxf(-1.5f, fminf(1.5f, e));
    float target[3] = { eye[0] + sinf(a) * cosf(e), eye[1] + sinf(e), eye[2] - cosf(a) * cosf(e) };
    limen_node_look_at(w->s, w->cam, eye, target, (float[3]){ 0, 1, 0 });
}

/* Walks along the ground as a person: a capsule of radius 0.25 from the eyes 0.8 down,
 * which collides and slides, and passes through any portal on the way. */
static void walk(world *w, float fwd, float side)
{
    float m[16];
    limen_node_world_matrix(w->s, w->cam, m);
    float f[3] = { -m[8], 0, -m[10] }, r[3] = { m[0], 0, m[2] };
    float fl = sqrtf(f[0] * f[0] + f[2] * f[2]), rl = sqrtf(r[0] * r[0] + r[2] * r[2]);
    float d[3] = { fwd * f[0] / fl + side * r[0] / rl, 0, fwd * f[2] / fl + side * r[2] / rl };
    limen_slide_result res;
    if (!limen_node_slide_capsule(w->s, w->cam, d, 0.25f, (float[3]){ 0, -0.8f, 0 }, &res) &&
        res.crossed) {
        printf("crossed portal %s\n", limen_node_get_name(w->s, res.portal));
        fflush(stdout);
    }
}

/* The game's own drawing after limen's: a crosshair, two scissored clears. */
typedef struct game_gl {
    void (*Enable)(unsigned), (*Disable)(unsigned);
    void (*Scissor)(int, int, int, int), (*ClearColor)(float, float, float, float);
    void (*Clear)(unsigned);
} game_gl;

/* dst: the address of a function pointer */
static void load_gl(void *dst, const char *name)
{
    void *p = SDL_GL_GetProcAddress(name);
    memcpy(dst, &p, sizeof p);
}

static void crosshair(const game_gl *gl, int w, int h)
{
    const unsigned scissor_test = 0x0C11, color_buffer_bit = 0x4000;
    gl->Enable(scissor_test);
    gl->ClearColor(1, 1, 1, 1);
    gl->Scissor(w / 2 - 8, h / 2 - 1, 16, 2);
    gl->Clear(color_buffer_bit);
    gl->Scissor(w / 2 - 1, h / 2 - 8, 2, 16);
    gl->Clear(color_buffer_bit);
    gl->Disable(scissor_test);
}

int main(int argc, char **argv)
{
    long frames = -1;
    int autopilot = 0;
    const char *shot = NULL;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--frames") && i + 1 < argc)
            frames = atol(argv[++i]);
        else if (!strcmp(argv[i], "--shot") && i + 1 < argc)
            shot = argv[++i];
        else if (!strcmp(argv[i], "--autopilot"))
            autopilot = 1;
        else {
            fprintf(stderr, "usage: walk [--frames N] [--autopilot] [--shot OUT.png]\n");
            return 2;
        }
    }
    world w;
    if (build(&w)) {
        fprintf(stderr, "walk: %s\n", limen_scene_error(w.s));
        return 1;
    }
    /* 1. the game's window and context: OpenGL 3.3 core, with depth and stencil */
    if (SDL_Init(SDL_INIT_VIDEO)) {
        fprintf(stderr, "walk: %s\n", SDL_GetError());
        return 1;
    }
    SDL_GL_SetAttribute(SDL_GL_CONTEXT_PROFILE_MASK, SDL_GL_CONTEXT_PROFILE_CORE);
    SDL_GL_SetAttribute(SDL_GL_CONTEXT_MAJOR_VERSION, 3);
    SDL_GL_SetAttribute(SDL_GL_CONTEXT_MINOR_VERSION, 3);
    SDL_GL_SetAttribute(SDL_GL_DEPTH_SIZE, 24);
    SDL_GL_SetAttribute(SDL_GL_STENCIL_SIZE, 8);
    SDL_Window *win = SDL_CreateWindow("walk - limen in a game's window", SDL_WINDOWPOS_UNDEFINED,
                                       SDL_WINDOWPOS_UNDEFINED, 640, 400, SDL_WINDOW_OPENGL);
    SDL_GLContext ctx = win ? SDL_GL_CreateContext(win) : NULL;
    if (!ctx) {
        fprintf(stderr, "walk: %s\n", SDL_GetError());
        return 1;
    }
    SDL_GL_SetSwapInterval(1);
    game_gl gl;
    load_gl(&gl.Enable, "glEnable");
    load_gl(&gl.Disable, "glDisable");
    load_gl(&gl.Scissor, "glScissor");
    load_gl(&gl.ClearColor, "glClearColor");
    load_gl(&gl.Clear, "glClear");

    /* 2. limen draws into it: the host backend, the window's own framebuffer (0) */
    int fw, fh;
    SDL_GL_GetDrawableSize(win, &fw, &fh);
    limen_renderer *r = NULL;
    limen_renderer_desc desc = { .backend = LIMEN_BACKEND_HOST, .width = fw, .height = fh,
                                 .gl_loader = SDL_GL_GetProcAddress, .framebuffer = 0 };
    if (limen_renderer_create(&desc, &r)) {
        fprintf(stderr, "walk: %s\n", limen_renderer_error(r));
        return 1;
    }

    /* 3. the game loop */
    int rc = 0, dragging = 0;
    for (long f = 0; frames < 0 || f < frames; f++) {
        SDL_Event e;
        float yaw = 0, pitch = 0;
        int quit = 0;
        while (SDL_PollEvent(&e)) {
            if (e.type == SDL_QUIT || (e.type == SDL_KEYDOWN && e.key.keysym.sym == SDLK_ESCAPE))
                quit = 1;
            else if (e.type == SDL_MOUSEBUTTONDOWN || e.type == SDL_MOUSEBUTTONUP)
                dragging = e.type == SDL_MOUSEBUTTONDOWN;
            else if (e.type == SDL_MOUSEMOTION && dragging)
                yaw += 0.004f * (float)e.motion.xrel, pitch -= 0.004f * (float)e.motion.yrel;
        }
        if (quit)
            break;
        const Uint8 *k = SDL_GetKeyboardState(NULL);
        const float step = 1.0f / 30;      /* a fixed step per frame: 2 units a second at 60 */
        yaw += 0.05f * (float)(k[SDL_SCANCODE_RIGHT] - k[SDL_SCANCODE_LEFT]);
        pitch += 0.05f * (float)(k[SDL_SCANCODE_UP] - k[SDL_SCANCODE_DOWN]);
        if (yaw || pitch)
            look(&w, yaw, pitch);
        float fwd = (float)(k[SDL_SCANCODE_W] - k[SDL_SCANCODE_S]) + (float)autopilot;
        float side = (float)(k[SDL_SCANCODE_D] - k[SDL_SCANCODE_A]);
        if (fwd || side)
            walk(&w, fwd * step, side * step);

        limen_frame_stats stats;
        if (limen_render_frame(r, w.s, NULL, &stats)) {
            fprintf(stderr, "walk: %s\n", limen_renderer_error(r));
            rc = 1;
            break;
        }
        if (shot && f + 1 == frames && limen_renderer_write_png(r, shot)) {
            fprintf(stderr, "walk: %s\n", limen_renderer_error(r));
            rc = 1;
        }
        crosshair(&gl, fw, fh);         /* the game's GL state is its own again */
        SDL_GL_SwapWindow(win);
    }
    limen_renderer_destroy(r);
    limen_scene_destroy(w.s);
    SDL_GL_DeleteContext(ctx);
    SDL_DestroyWindow(win);
    SDL_Quit();
    return rc;
}
