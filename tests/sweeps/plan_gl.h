/* plan_gl.h - draws a limen plan with OpenGL of its own, with any view's projection and clip
 * method replaced: how the sweeps measure a method the library would not choose (the
 * oblique projection forced where the planner falls back to the user clip plane).
 *
 * It is tests/test_example_game.c's renderer (the stencil method, the engine-agnostic way
 * of drawing limen's view tree; that test keeps it within 0.5% of limen's own frames), cut
 * down to what the sweeps need: OpenGL depth (NO), a depth24/stencil8 buffer, any size.
 * Include it in one test program only.
 */
#ifndef LIMEN_PLAN_GL_H
#define LIMEN_PLAN_GL_H

#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>
#include <GL/osmesa.h>

#include "sweep.h"

#define PGL_SEGMENTS 96
#define PGL_MAX_ITEMS 256
#define PGL_MAX_LIGHTS 8

typedef struct pgl_mesh { GLsizei first, count; } pgl_mesh;
enum { PGL_QUAD, PGL_BOX, PGL_SPHERE, PGL_CYLINDER, PGL_NMESH };

typedef struct pgl_item {
    limen_node node;
    limen_node_kind kind;
    int mesh, shape;
    float model[16], scale[3], color[3], color_b[3], cell, back[3], fill[3];
} pgl_item;

typedef struct pgl {
    int w, h;
    OSMesaContext ctx;
    unsigned char token[64];
    GLuint fbo, color_rb, depth_rb, prog, vao, vbo, ibo;
    struct {
        GLint model, view_proj, clip_plane, scale, eye, albedo, albedo_b, cell, tint, ambient,
            shape, flat, nlights, light_pos, light_col;
    } u;
    pgl_mesh meshes[PGL_NMESH];
    pgl_item items[PGL_MAX_ITEMS];
    int nitems;
    float background[3];
    /* the frame being drawn */
    const limen_plan *plan;
    const float (*proj)[16];
    const limen_clip_method *clip;
    /* 1: draw the flat passes of mirrors and portals (mark, seal, fill) from their polygon
     * clipped on the CPU in double (pgl_surface_poly) instead of their quad: the remedy the
     * approach sweep tests for the GPU's float clipping of a surface nearly touching the eye */
    int cpu_surfaces;
    GLuint poly_vao, poly_vbo;
} pgl;

static void pgl_mul(const float a[16], const float b[16], float c[16])
{
    for (int j = 0; j < 4; j++)
        for (int i = 0; i < 4; i++)
            c[j * 4 + i] = a[i] * b[j * 4] + a[4 + i] * b[j * 4 + 1] + a[8 + i] * b[j * 4 + 2] +
                           a[12 + i] * b[j * 4 + 3];
}

static int pgl_current(pgl *g)
{
    return OSMesaMakeCurrent(g->ctx, g->token, GL_UNSIGNED_BYTE, 4, 4) ? 0 : -1;
}

static const char *pgl_vs =
    "#version 330 core\n"
    "layout(location = 0) in vec3 a_pos;\n"
    "layout(location = 1) in vec3 a_nrm;\n"
    "uniform mat4 u_model, u_view_proj;\n"
    "uniform vec3 u_scale;\n"
    "uniform vec4 u_clip_plane;\n"
    "uniform int u_shape;\n"
    "out vec3 v_world, v_local, v_normal;\n"
    "void main() {\n"
    "    vec4 w = u_model * vec4(a_pos, 1.0);\n"
    "    v_world = w.xyz; v_local = a_pos * u_scale;\n"
    "    vec3 n = a_nrm;\n"
    "    if (u_shape == 1) n = a_pos;\n"
    "    else if (u_shape == 2 && abs(a_nrm.y) < 0.5) n = vec3(a_pos.x, 0.0, a_pos.z);\n"
    "    v_normal = transpose(inverse(mat3(u_model))) * n;\n"
    "    gl_ClipDistance[0] = dot(u_clip_plane, w);\n"
    "    gl_Position = u_view_proj * w;\n"
    "}\n";

static const char *pgl_fs =
    "#version 330 core\n"
    "in vec3 v_world, v_local, v_normal;\n"
    "uniform vec3 u_eye, u_albedo, u_albedo_b, u_tint;\n"
    "uniform float u_cell, u_ambient;\n"
    "uniform int u_flat, u_nlights;\n"
    "uniform vec3 u_light_pos[8], u_light_col[8];\n"
    "out vec4 o_color;\n"
    "void main() {\n"
    "    if (u_flat != 0) { o_color = vec4(u_albedo * u_tint, 1.0); return; }\n"
    "    vec3 n = normalize(v_normal);\n"
    "    if (dot(n, u_eye - v_world) < 0.0) n = -n;\n"
    "    vec3 albedo = u_albedo;\n"
    "    if (u_cell > 0.0) {\n"
    "        vec3 c = floor(v_local / u_cell);\n"
    "        float k = c.x + c.y + c.z;\n"
    "        if (k - 2.0 * floor(k * 0.5) > 0.5) albedo = u_albedo_b;\n"
    "    }\n"
    "    vec3 light = vec3(0.0);\n"
    "    for (int i = 0; i < u_nlights; i++)\n"
    "        light += u_light_col[i] * max(0.0, dot(n, normalize(u_light_pos[i] - v_world)));\n"
    "    vec3 c = clamp(albedo * (u_ambient + (1.0 - u_ambient) * light), 0.0, 1.0);\n"
    "    o_color = vec4(c * u_tint, 1.0);\n"
    "}\n";

static int pgl_program(pgl *g)
{
    const char *src[2] = { pgl_vs, pgl_fs };
    const GLenum type[2] = { GL_VERTEX_SHADER, GL_FRAGMENT_SHADER };
    GLint ok = 0;
    g->prog = glCreateProgram();
    for (int i = 0; i < 2; i++) {
        GLuint sh = glCreateShader(type[i]);
        glShaderSource(sh, 1, &src[i], NULL);
        glCompileShader(sh);
        glAttachShader(g->prog, sh);
        glDeleteShader(sh);
    }
    glLinkProgram(g->prog);
    glGetProgramiv(g->prog, GL_LINK_STATUS, &ok);
#define PGL_U(field, name) g->u.field = glGetUniformLocation(g->prog, name)
    PGL_U(model, "u_model"); PGL_U(view_proj, "u_view_proj");
    PGL_U(clip_plane, "u_clip_plane"); PGL_U(scale, "u_scale"); PGL_U(eye, "u_eye");
    PGL_U(albedo, "u_albedo"); PGL_U(albedo_b, "u_albedo_b"); PGL_U(cell, "u_cell");
    PGL_U(tint, "u_tint"); PGL_U(ambient, "u_ambient"); PGL_U(shape, "u_shape");
    PGL_U(flat, "u_flat"); PGL_U(nlights, "u_nlights"); PGL_U(light_pos, "u_light_pos");
    PGL_U(light_col, "u_light_col");
#undef PGL_U
    return ok ? 0 : -1;
}

#define PGL_MAX_VERTS (28 + (PGL_SEGMENTS + 1) * (PGL_SEGMENTS / 2 + 7))
#define PGL_MAX_INDEX (42 + 6 * PGL_SEGMENTS * (PGL_SEGMENTS / 2 + 3))
typedef struct pgl_builder { float v[6 * PGL_MAX_VERTS]; GLuint idx[PGL_MAX_INDEX]; GLuint nv, ni; } pgl_builder;

static GLuint pgl_vtx(pgl_builder *b, float x, float y, float z, float nx, float ny, float nz)
{
    float *p = b->v + 6 * b->nv;
    p[0] = x, p[1] = y, p[2] = z, p[3] = nx, p[4] = ny, p[5] = nz;
    return b->nv++;
}

static void pgl_tri(pgl_builder *b, GLuint i0, GLuint i1, GLuint i2)
{
    b->idx[b->ni++] = i0, b->idx[b->ni++] = i1, b->idx[b->ni++] = i2;
}

static void pgl_face(pgl_builder *b, int axis, int sgn, float dist)
{
    static const float uv[4][2] = { { -1, -1 }, { 1, -1 }, { 1, 1 }, { -1, 1 } };
    int u = (axis + 1) % 3, v = (axis + 2) % 3;
    GLuint id[4];
    for (int k = 0; k < 4; k++) {
        float p[3], n[3] = { 0, 0, 0 };
        n[axis] = (float)sgn;
        p[axis] = dist, p[u] = 0.5f * uv[k][0], p[v] = 0.5f * uv[k][1] * (float)sgn;
        id[k] = pgl_vtx(b, p[0], p[1], p[2], n[0], n[1], n[2]);
    }
    pgl_tri(b, id[0], id[1], id[2]);
    pgl_tri(b, id[0], id[2], id[3]);
}

static void pgl_lathe(pgl_builder *b, int rings, const float (*ring)[4])
{
    GLuint base = b->nv;
    for (int i = 0; i < rings; i++)
        for (int j = 0; j <= PGL_SEGMENTS; j++) {
            double th = 2.0 * M_PI * j / PGL_SEGMENTS;
            float c = (float)cos(th), s = (float)-sin(th);
            const float *r = ring[i];
            pgl_vtx(b, r[0] * c, r[1], r[0] * s, r[2] * c, r[3], r[2] * s);
        }
    for (int i = 0; i + 1 < rings; i++)
        for (int j = 0; j < PGL_SEGMENTS; j++) {
            GLuint a = base + (GLuint)(i * (PGL_SEGMENTS + 1) + j), c = a + PGL_SEGMENTS + 1;
            pgl_tri(b, a, c, c + 1);
            pgl_tri(b, a, c + 1, a + 1);
        }
}

static int pgl_meshes(pgl *g)
{
    pgl_builder *b = calloc(1, sizeof *b);
    if (!b)
        return -1;
    g->meshes[PGL_QUAD].first = (GLsizei)b->ni;
    pgl_face(b, 2, 1, 0.0f);
    g->meshes[PGL_BOX].first = (GLsizei)b->ni;
    for (int axis = 0; axis < 3; axis++)
        for (int sgn = -1; sgn <= 1; sgn += 2)
            pgl_face(b, axis, sgn, 0.5f * (float)sgn);
    g->meshes[PGL_SPHERE].first = (GLsizei)b->ni;
    float sphere[PGL_SEGMENTS / 2 + 1][4];
    for (int i = 0; i <= PGL_SEGMENTS / 2; i++) {
        double phi = M_PI * i / (PGL_SEGMENTS / 2);
        float r = (float)sin(phi), y = (float)cos(phi);
        sphere[i][0] = sphere[i][2] = r, sphere[i][1] = sphere[i][3] = y;
    }
    pgl_lathe(b, PGL_SEGMENTS / 2 + 1, sphere);
    g->meshes[PGL_CYLINDER].first = (GLsizei)b->ni;
    static const float top[2][4] = { { 0, 1, 0, 1 }, { 1, 1, 0, 1 } };
    static const float side[2][4] = { { 1, 1, 1, 0 }, { 1, 0, 1, 0 } };
    static const float bottom[2][4] = { { 1, 0, 0, -1 }, { 0, 0, 0, -1 } };
    pgl_lathe(b, 2, top);
    pgl_lathe(b, 2, side);
    pgl_lathe(b, 2, bottom);
    for (int m = 0; m < PGL_NMESH; m++)
        g->meshes[m].count = (m + 1 < PGL_NMESH ? g->meshes[m + 1].first : (GLsizei)b->ni) -
                             g->meshes[m].first;
    glGenVertexArrays(1, &g->vao);
    glBindVertexArray(g->vao);
    glGenBuffers(1, &g->vbo);
    glBindBuffer(GL_ARRAY_BUFFER, g->vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof(float) * 6 * b->nv), b->v, GL_STATIC_DRAW);
    glGenBuffers(1, &g->ibo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, g->ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(sizeof(GLuint) * b->ni), b->idx,
                 GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void *)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), (void *)(3 * sizeof(float)));
    free(b);
    return 0;
}

static void pgl_destroy(pgl *g)
{
    if (!g)
        return;
    if (g->ctx && !pgl_current(g)) {
        glDeleteProgram(g->prog);
        glDeleteBuffers(1, &g->vbo);
        glDeleteBuffers(1, &g->ibo);
        glDeleteVertexArrays(1, &g->vao);
        glDeleteBuffers(1, &g->poly_vbo);
        glDeleteVertexArrays(1, &g->poly_vao);
        glDeleteFramebuffers(1, &g->fbo);
        glDeleteRenderbuffers(1, &g->color_rb);
        glDeleteRenderbuffers(1, &g->depth_rb);
        OSMesaMakeCurrent(NULL, NULL, GL_UNSIGNED_BYTE, 0, 0);
    }
    if (g->ctx)
        OSMesaDestroyContext(g->ctx);
    free(g);
}

static pgl *pgl_create(int w, int h)
{
    pgl *g = calloc(1, sizeof *g);
    if (!g)
        return NULL;
    g->w = w, g->h = h;
    const int attribs[] = { OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 0, OSMESA_STENCIL_BITS,
                            0, OSMESA_PROFILE, OSMESA_CORE_PROFILE, OSMESA_CONTEXT_MAJOR_VERSION,
                            3, OSMESA_CONTEXT_MINOR_VERSION, 3, 0 };
    g->ctx = OSMesaCreateContextAttribs(attribs, NULL);
    if (!g->ctx || pgl_current(g) || pgl_program(g) || pgl_meshes(g)) {
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
    glBindVertexArray(g->vao);
    glGenRenderbuffers(1, &g->color_rb);
    glBindRenderbuffer(GL_RENDERBUFFER, g->color_rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, w, h);
    glGenRenderbuffers(1, &g->depth_rb);
    glBindRenderbuffer(GL_RENDERBUFFER, g->depth_rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, w, h);
    glGenFramebuffers(1, &g->fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, g->color_rb);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                              g->depth_rb);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        pgl_destroy(g);
        return NULL;
    }
    return g;
}

static int pgl_read_node(limen_scene *s, limen_node n, pgl_item *it)
{
    memset(it, 0, sizeof *it);
    it->node = n;
    it->kind = limen_node_get_kind(s, n);
    float d[3], world[16];
    limen_node_get_dims(s, n, d);
    switch (it->kind) {
    case LIMEN_NODE_BOX: it->mesh = PGL_BOX; memcpy(it->scale, d, sizeof d); break;
    case LIMEN_NODE_SPHERE:
        it->mesh = PGL_SPHERE, it->shape = 1;
        it->scale[0] = it->scale[1] = it->scale[2] = d[0];
        break;
    case LIMEN_NODE_CYLINDER:
        it->mesh = PGL_CYLINDER, it->shape = 2;
        it->scale[0] = it->scale[2] = d[0], it->scale[1] = d[1];
        break;
    case LIMEN_NODE_QUAD: case LIMEN_NODE_MIRROR: case LIMEN_NODE_PORTAL:
        it->mesh = PGL_QUAD, it->scale[0] = d[0], it->scale[1] = d[1], it->scale[2] = 1;
        break;
    default:
        return 0;
    }
    limen_node_world_matrix(s, n, world);
    memcpy(it->model, world, sizeof world);
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 3; r++)
            it->model[c * 4 + r] *= it->scale[c];
    limen_node_get_checker(s, n, it->color, it->color_b, &it->cell);
    if (it->kind == LIMEN_NODE_MIRROR || it->kind == LIMEN_NODE_PORTAL)
        limen_surface_get(s, n, NULL, it->back, it->fill, NULL);
    return 1;
}

static void pgl_read_scene(pgl *g, limen_scene *s)
{
    limen_node nodes[PGL_MAX_ITEMS];
    int n = limen_scene_nodes(s, nodes, PGL_MAX_ITEMS);
    float lp[PGL_MAX_LIGHTS][3], lc[PGL_MAX_LIGHTS][3];
    int nl = 0;
    g->nitems = 0;
    for (int i = 0; i < n && i < PGL_MAX_ITEMS; i++) {
        if (!limen_node_get_visible(s, nodes[i]))
            continue;
        if (limen_node_get_kind(s, nodes[i]) == LIMEN_NODE_LIGHT && nl < PGL_MAX_LIGHTS) {
            float m[16];
            limen_node_world_matrix(s, nodes[i], m);
            memcpy(lp[nl], m + 12, sizeof lp[0]);
            limen_node_get_color(s, nodes[i], lc[nl++]);
        } else if (pgl_read_node(s, nodes[i], &g->items[g->nitems])) {
            g->nitems++;
        }
    }
    limen_scene_get_background(s, g->background);
    glUniform1f(g->u.ambient, limen_scene_get_ambient(s));
    glUniform1i(g->u.nlights, nl);
    if (nl) {
        glUniform3fv(g->u.light_pos, nl, &lp[0][0]);
        glUniform3fv(g->u.light_col, nl, &lc[0][0]);
    }
}

static int pgl_is_surface(const pgl_item *it)
{
    return it->kind == LIMEN_NODE_MIRROR || it->kind == LIMEN_NODE_PORTAL;
}

static void pgl_set(GLenum cap, int on)
{
    if (on)
        glEnable(cap);
    else
        glDisable(cap);
}

static void pgl_use_view(pgl *g, const limen_view *v)
{
    float vp[16];
    const float *proj = g->proj ? g->proj[v->id] : v->proj;
    limen_clip_method clip = g->clip ? g->clip[v->id] : v->clip;
    pgl_mul(proj, v->view, vp);
    glUniformMatrix4fv(g->u.view_proj, 1, GL_FALSE, vp);
    glUniform3fv(g->u.eye, 1, v->eye);
    static const float no_clip[4] = { 0, 0, 0, 1 };
    int plane = clip == LIMEN_CLIP_PLANE;
    pgl_set(GL_CLIP_DISTANCE0, plane);
    glUniform4fv(g->u.clip_plane, 1, plane ? v->clip_plane : no_clip);
    glFrontFace(v->front_face_cw ? GL_CW : GL_CCW);
    glUniform3fv(g->u.tint, 1, v->tint);
}

static void pgl_draw_item(pgl *g, const pgl_item *it, int flat, const float albedo[3])
{
    glUniformMatrix4fv(g->u.model, 1, GL_FALSE, it->model);
    glUniform3fv(g->u.scale, 1, it->scale);
    glUniform3fv(g->u.albedo, 1, albedo);
    glUniform3fv(g->u.albedo_b, 1, it->color_b);
    glUniform1f(g->u.cell, flat || pgl_is_surface(it) ? 0.0f : it->cell);
    glUniform1i(g->u.shape, it->shape);
    glUniform1i(g->u.flat, flat);
    pgl_set(GL_DEPTH_CLAMP, pgl_is_surface(it));
    pgl_set(GL_CULL_FACE, it->mesh != PGL_QUAD);
    const pgl_mesh *m = &g->meshes[it->mesh];
    glDrawElements(GL_TRIANGLES, m->count, GL_UNSIGNED_INT, (void *)(sizeof(GLuint) * (size_t)m->first));
}

static void pgl_far_plane(pgl *g, const limen_view *v, const float rgb[3])
{
    static const float identity[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
    pgl_item far = { .mesh = PGL_QUAD, .kind = LIMEN_NODE_MIRROR, .scale = { 1, 1, 1 },
                     .model = { 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1, 0, 0, 0, 1, 1 } };
    glUniformMatrix4fv(g->u.view_proj, 1, GL_FALSE, identity);
    glUniform3fv(g->u.tint, 1, v->tint);
    /* llvmpipe applies gl_ClipDistance[0] even with GL_CLIP_DISTANCE0 disabled: give the
     * far rectangle a clip plane it cannot fail, or a nested view cut by a user clip plane
     * loses its background */
    static const float no_clip[4] = { 0, 0, 0, 1 };
    glUniform4fv(g->u.clip_plane, 1, no_clip);
    glDisable(GL_CLIP_DISTANCE0);
    pgl_draw_item(g, &far, 1, rgb);
}

static const pgl_item *pgl_find(const pgl *g, limen_node n)
{
    for (int i = 0; i < g->nitems; i++)
        if (g->items[i].node.id == n.id)
            return &g->items[i];
    return NULL;
}


/* Keeps the part of polygon in (n vertices of 4 doubles) where plane . v >= 0. */
static int pgl_clip4(double in[][4], int n, const double plane[4], double out[][4])
{
    int m = 0;
    for (int i = 0; i < n && m < 30; i++) {
        const double *a = in[i], *b = in[(i + 1) % n];
        double da = 0, db = 0;
        for (int k = 0; k < 4; k++)
            da += plane[k] * a[k], db += plane[k] * b[k];
        if (da >= 0)
            memcpy(out[m++], a, sizeof(double) * 4);
        if ((da >= 0) != (db >= 0)) {
            double t = da / (da - db);
            for (int k = 0; k < 4; k++)
                out[m][k] = a[k] + t * (b[k] - a[k]);
            m++;
        }
    }
    return m;
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

/* A surface's flat pass from its polygon clipped in double: to the view's clip plane (nested
 * views), to the four sides of the frustum (so that the projection is bounded), and split at
 * the near and far planes into the part whose depth the projection gives and the parts that
 * depth clamping would put on the near or the far plane. */
static void pgl_surface_poly(pgl *g, const limen_view *v, const pgl_item *it, const float albedo[3])
{
    const float *proj = g->proj ? g->proj[v->id] : v->proj;
    limen_clip_method clip = g->clip ? g->clip[v->id] : v->clip;
    double pv[16], P[16], V[16], M[16];
    for (int i = 0; i < 16; i++)
        P[i] = proj[i], V[i] = v->view[i], M[i] = it->model[i];
    sweep_mul4(P, V, pv);
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
            n = pgl_clip4(a, n, c, b);
            memcpy(a, b, sizeof(double) * 4 * (size_t)n);
        }
    }
    static const double sides[4][4] = { { -1, 0, 0, 1 }, { 1, 0, 0, 1 }, { 0, -1, 0, 1 }, { 0, 1, 0, 1 } };
    for (int k = 0; k < 4 && n >= 3; k++) {
        n = pgl_clip4(a, n, sides[k], b);
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
    glUniformMatrix4fv(g->u.model, 1, GL_FALSE, (const float[16]){ 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 });
    glUniformMatrix4fv(g->u.view_proj, 1, GL_FALSE, (const float[16]){ 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 });
    glUniform3fv(g->u.albedo, 1, albedo);
    glUniform1f(g->u.cell, 0.0f);
    glUniform1i(g->u.shape, 0);
    glUniform1i(g->u.flat, 1);
    glDisable(GL_CLIP_DISTANCE0);
    glDisable(GL_CULL_FACE);
    glEnable(GL_DEPTH_CLAMP);
    glBindVertexArray(g->poly_vao);
    static const double nearp[4] = { 0, 0, 1, 1 }, nearn[4] = { 0, 0, -1, -1 };
    static const double farp[4] = { 0, 0, -1, 1 }, farn[4] = { 0, 0, 1, -1 };
    double c[32][4], d[32][4];
    int k = pgl_clip4(a, n, nearn, c);          /* in front of the near plane: depth -1 */
    pgl_draw_ndc(g, c, k, -1.0, 1);
    k = pgl_clip4(a, n, farn, c);               /* beyond the far plane: depth 1 */
    pgl_draw_ndc(g, c, k, 1.0, 1);
    k = pgl_clip4(a, n, nearp, c);              /* between: the projection's depth */
    k = pgl_clip4(c, k, farp, d);
    pgl_draw_ndc(g, d, k, 0, 0);
    glBindVertexArray(g->vao);
    pgl_use_view(g, v);
}

static void pgl_flat_surface(pgl *g, const limen_view *v, const pgl_item *it, const float albedo[3])
{
    if (g->cpu_surfaces)
        pgl_surface_poly(g, v, it, albedo);
    else
        pgl_draw_item(g, it, 1, albedo);
}

static void pgl_view(pgl *g, int index)
{
    const limen_view *v = limen_plan_view(g->plan, index);
    const int st = v->stencil;
    glScissor(v->scissor[0], v->scissor[1], v->scissor[2], v->scissor[3]);
    glStencilFunc(GL_EQUAL, st, 0xFF);
    glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    if (v->depth > 0) {
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        glDepthFunc(GL_ALWAYS);
        pgl_far_plane(g, v, g->background);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glDepthFunc(GL_LESS);
    }
    pgl_use_view(g, v);
    for (int i = 0; i < g->nitems; i++)
        if (!pgl_is_surface(&g->items[i]))
            pgl_draw_item(g, &g->items[i], 0, g->items[i].color);
    if (v->depth > 0) {
        glDepthFunc(GL_EQUAL);
        pgl_far_plane(g, v, g->background);
        glDepthFunc(GL_LESS);
        pgl_use_view(g, v);
    }
    const limen_view_surface *surf;
    int n = limen_plan_view_surfaces(g->plan, index, &surf);
    for (int k = 0; k < n; k++) {
        const pgl_item *it = pgl_find(g, surf[k].node);
        if (!it)
            continue;
        if (surf[k].state == LIMEN_SURFACE_BACK) {
            pgl_draw_item(g, it, 0, it->back);
            continue;
        }
        if (surf[k].state == LIMEN_SURFACE_FILL) {
            pgl_flat_surface(g, v, it, it->fill);
            continue;
        }
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        glDepthMask(GL_FALSE);
        glStencilOp(GL_KEEP, GL_KEEP, GL_INCR);
        pgl_flat_surface(g, v, it, it->fill);
        glDepthMask(GL_TRUE);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        pgl_view(g, surf[k].child);
        glScissor(v->scissor[0], v->scissor[1], v->scissor[2], v->scissor[3]);
        pgl_use_view(g, v);
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        glStencilFunc(GL_EQUAL, st + 1, 0xFF);
        glStencilOp(GL_KEEP, GL_KEEP, GL_DECR);
        glDepthFunc(GL_ALWAYS);
        pgl_flat_surface(g, v, it, it->fill);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glDepthFunc(GL_LESS);
        glStencilFunc(GL_EQUAL, st, 0xFF);
        glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    }
}

/* Draws plan p (planned for this size, LIMEN_DEPTH_NO) of scene s into rgb (w*h*3, top row
 * first). proj[i] and clip[i], where not NULL, replace view i's projection and clip method. */
static int pgl_draw(pgl *g, limen_scene *s, const limen_plan *p, const float (*proj)[16],
                    const limen_clip_method *clip, unsigned char *rgb)
{
    if (pgl_current(g))
        return -1;
    g->plan = p, g->proj = proj, g->clip = clip;
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo);
    glViewport(0, 0, g->w, g->h);
    glUseProgram(g->prog);
    glBindVertexArray(g->vao);
    pgl_read_scene(g, s);
    glDisable(GL_SCISSOR_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glDepthMask(GL_TRUE);
    glStencilMask(0xFF);
    glClearColor(g->background[0], g->background[1], g->background[2], 1.0f);
    glClearDepth(1.0);
    glClearStencil(0);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glEnable(GL_STENCIL_TEST);
    glEnable(GL_SCISSOR_TEST);
    glCullFace(GL_BACK);
    pgl_view(g, 0);
    glDisable(GL_SCISSOR_TEST);
    glDisable(GL_STENCIL_TEST);
    glFrontFace(GL_CCW);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    for (int y = 0; y < g->h; y++)
        glReadPixels(0, g->h - 1 - y, g->w, 1, GL_RGB, GL_UNSIGNED_BYTE, rgb + 3 * (size_t)g->w * y);
    return glGetError() == GL_NO_ERROR ? 0 : -1;
}

#endif
