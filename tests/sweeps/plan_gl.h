/* plan_gl.h - draws a limen plan with OpenGL of its own, with any view's projection and clip
 * method replaced: how the sweeps measure a method the library would not choose (the
 * oblique projection forced where the planner falls back to the user clip plane).
 *
 * The drawing is plan_game.h's game (the stencil method written out over the plan, as
 * examples/own_renderer.c drew it before the draw list), through its hooks: the replaced
 * projections and clip methods, and optionally the surfaces' flat passes from their polygon
 * clipped on the CPU in double (pgl_surface_poly), the remedy the approach sweep tests for
 * the GPU's float clipping of a surface nearly touching the eye.
 * OpenGL depth (NO), a depth24/stencil8 buffer, any size. Include it in one test program only.
 */
#ifndef LIMEN_PLAN_GL_H
#define LIMEN_PLAN_GL_H

#include "plan_game.h"
#include "sweep.h"

typedef struct pgl {
    game *game;
    int cpu_surfaces;           /* 1: flat passes from the CPU-clipped polygon */
    GLuint poly_vao, poly_vbo;
} pgl;

static void pgl_destroy(pgl *g)
{
    if (!g)
        return;
    if (g->game && !make_current(g->game)) {
        glDeleteBuffers(1, &g->poly_vbo);
        glDeleteVertexArrays(1, &g->poly_vao);
    }
    if (g->game)
        game_destroy(g->game);
    free(g);
}

static pgl *pgl_create(int w, int h)
{
    pgl *g = calloc(1, sizeof *g);
    if (!g)
        return NULL;
    g->game = game_create(w, h);
    if (!g->game) {
        pgl_destroy(g);
        return NULL;
    }
    glGenVertexArrays(1, &g->poly_vao);
    glBindVertexArray(g->poly_vao);
    glGenBuffers(1, &g->poly_vbo);
    glBindBuffer(GL_ARRAY_BUFFER, g->poly_vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof(float) * 6 * 64), NULL, GL_DYNAMIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void *)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void *)(3 * sizeof(float)));
    glBindVertexArray(g->game->vao);
    return g;
}

/* Draws polygon p (n clip-space vertices) as a fan in NDC with w = 1: the GPU neither clips
 * nor divides. */
static void pgl_draw_ndc(pgl *g, double p[][4], int n, double z_fixed, int use_fixed)
{
    if (n < 3)
        return;
    float buf[6 * 32];
    for (int i = 0; i < n; i++) {
        buf[6 * i + 0] = (float)(p[i][0] / p[i][3]);
        buf[6 * i + 1] = (float)(p[i][1] / p[i][3]);
        buf[6 * i + 2] = (float)(use_fixed ? z_fixed : p[i][2] / p[i][3]);
        buf[6 * i + 3] = buf[6 * i + 4] = 0, buf[6 * i + 5] = 1;
    }
    glBindBuffer(GL_ARRAY_BUFFER, g->poly_vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)(sizeof(float) * 6 * (size_t)n), buf);
    glDrawArrays(GL_TRIANGLE_FAN, 0, n);
}

/* The game's flat_surface hook: a surface's flat pass from its polygon clipped in double: to
 * the view's clip plane (nested views), to the four sides of the frustum (so that the
 * projection is bounded), and split at the near and far planes into the part whose depth
 * the projection gives and the parts that depth clamping would put on the near or the far
 * plane. */
static void pgl_surface_poly(game *gm, const limen_view *v, const item *it, const float albedo[3])
{
    pgl *g = gm->hook_data;
    const float *proj = gm->proj ? gm->proj[v->id] : v->proj;
    limen_clip_method clip = gm->clip ? gm->clip[v->id] : v->clip;
    double pv[16], P[16], V[16], M[16];
    for (int i = 0; i < 16; i++)
        P[i] = proj[i], V[i] = v->view[i], M[i] = it->model[i];
    limen__d_mul(P, V, pv);
    double a[32][4], b[32][4];
    const double local[4][2] = { { -0.5, -0.5 }, { 0.5, -0.5 }, { 0.5, 0.5 }, { -0.5, 0.5 } };
    int n = 4;
    for (int i = 0; i < 4; i++) {
        double w[4];
        for (int r = 0; r < 4; r++)
            w[r] = M[r] * local[i][0] + M[4 + r] * local[i][1] + M[12 + r];
        for (int r = 0; r < 4; r++)
            a[i][r] = pv[r] * w[0] + pv[4 + r] * w[1] + pv[8 + r] * w[2] + pv[12 + r] * w[3];
    }
    if (v->depth > 0 && clip == LIMEN_CLIP_PLANE) {
        /* the world clip plane in clip space: C_clip = (PV)^-T C */
        double inv[16], c[4];
        if (sweep_inv4(pv, inv)) {
            for (int j = 0; j < 4; j++)
                c[j] = inv[j * 4] * v->clip_plane[0] + inv[j * 4 + 1] * v->clip_plane[1] +
                       inv[j * 4 + 2] * v->clip_plane[2] + inv[j * 4 + 3] * v->clip_plane[3];
            n = limen__d_clip4(a, n, c, b, 30);
            memcpy(a, b, sizeof(double) * 4 * (size_t)n);
        }
    }
    static const double sides[4][4] = { { -1, 0, 0, 1 }, { 1, 0, 0, 1 }, { 0, -1, 0, 1 }, { 0, 1, 0, 1 } };
    for (int k = 0; k < 4 && n >= 3; k++) {
        n = limen__d_clip4(a, n, sides[k], b, 30);
        memcpy(a, b, sizeof(double) * 4 * (size_t)n);
    }
    if (n < 3)
        return;
    /* vertices at the apex (w = 0) cannot be divided; they are a point, drop them */
    int m = 0;
    for (int i = 0; i < n; i++)
        if (a[i][3] > 0)
            memcpy(b[m++], a[i], sizeof(double) * 4);
    n = m;
    memcpy(a, b, sizeof(double) * 4 * (size_t)n);
    static const float identity[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
    glUniformMatrix4fv(gm->u.model, 1, GL_FALSE, identity);
    glUniformMatrix4fv(gm->u.view_proj, 1, GL_FALSE, identity);
    glUniform3fv(gm->u.albedo, 1, albedo);
    glUniform1f(gm->u.cell, 0.0f);
    glUniform1i(gm->u.shape, 0);
    glUniform1i(gm->u.flat, 1);
    glDisable(GL_CLIP_DISTANCE0);
    glDisable(GL_CULL_FACE);
    glEnable(GL_DEPTH_CLAMP);
    glBindVertexArray(g->poly_vao);
    static const double nearp[4] = { 0, 0, 1, 1 }, nearn[4] = { 0, 0, -1, -1 };
    static const double farp[4] = { 0, 0, -1, 1 }, farn[4] = { 0, 0, 1, -1 };
    double c[32][4], d[32][4];
    int k = limen__d_clip4(a, n, nearn, c, 30); /* in front of the near plane: depth -1 */
    pgl_draw_ndc(g, c, k, -1.0, 1);
    k = limen__d_clip4(a, n, farn, c, 30);      /* beyond the far plane: depth 1 */
    pgl_draw_ndc(g, c, k, 1.0, 1);
    k = limen__d_clip4(a, n, nearp, c, 30);     /* between: the projection's depth */
    k = limen__d_clip4(c, k, farp, d, 30);
    pgl_draw_ndc(g, d, k, 0, 0);
    glBindVertexArray(gm->vao);
    use_view(gm, v);
}

/* Draws plan p (planned for this size, LIMEN_DEPTH_NO) of scene s into rgb (w*h*3, top row
 * first). proj[i] and clip[i], where not NULL, replace view i's projection and clip method. */
static int pgl_draw(pgl *g, limen_scene *s, const limen_plan *p, const float (*proj)[16],
                    const limen_clip_method *clip, unsigned char *rgb)
{
    game *gm = g->game;
    gm->proj = proj, gm->clip = clip;
    gm->flat_surface = g->cpu_surfaces ? pgl_surface_poly : NULL;
    gm->hook_data = g;
    int rc = game_draw(gm, s, p, LIMEN_DEPTH_NO, rgb);
    gm->proj = NULL, gm->clip = NULL, gm->flat_surface = NULL;
    return rc;
}

#endif
