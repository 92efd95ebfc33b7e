/* baseline.c - the floor and the classic stencil recursion (see baseline.h). Plain OpenGL
 * 3.3 core through OSMesa's own entry points; the scene is read through limen's public API
 * only. */
#define GL_GLEXT_PROTOTYPES
#include <GL/osmesa.h>
#include <GL/gl.h>
#include <GL/glext.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "baseline.h"

enum { MAX_LIGHTS = 8, SPHERE_SEG = 48, SPHERE_RING = 24, MAX_NODES = 4096 };

typedef struct range { GLint first; GLsizei count; } range;

struct baseline {
    OSMesaContext ctx;
    unsigned char token[4 * 4 * 4];
    int w, h;
    GLuint fbo, color_rb, depth_rb, vao, vbo;
    GLuint prog, floor_prog;
    range quad, box, sphere;
    limen_plan *plan;
    limen_node nodes[MAX_NODES];
    int nnodes;
    int views;
    /* uniform locations of the classic program */
    GLint u_model, u_nmat, u_vp, u_clip, u_eye, u_albedo, u_albedo_b, u_cell, u_scale,
        u_sphere, u_quad, u_flat, u_tint, u_ambient, u_nlights, u_lpos, u_lcol;
    /* and of the floor's */
    GLint f_mvp, f_model, f_normal, f_light, f_albedo, f_ambient;
};

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

/* ------------------------------------------------------------------ matrices (column-major) */

static void mat_mul(const float a[16], const float b[16], float out[16])
{
    float t[16];
    for (int c = 0; c < 4; c++)
        for (int r = 0; r < 4; r++) {
            float acc = 0;
            for (int k = 0; k < 4; k++)
                acc += a[k * 4 + r] * b[c * 4 + k];
            t[c * 4 + r] = acc;
        }
    memcpy(out, t, sizeof t);
}

/* The inverse transpose of m's upper 3x3 (normals), as a column-major mat3. */
static void normal_matrix(const float m[16], float out[9])
{
    float a = m[0], b = m[4], c = m[8], d = m[1], e = m[5], f = m[9], g = m[2], h = m[6],
          i = m[10];
    float A = e * i - f * h, B = -(d * i - f * g), C = d * h - e * g;
    float D = -(b * i - c * h), E = a * i - c * g, F = -(a * h - b * g);
    float G = b * f - c * e, H = -(a * f - c * d), I = a * e - b * d;
    float det = a * A + b * B + c * C;
    float k = det != 0 ? 1.0f / det : 0.0f;
    /* (M^-1)^T = cofactors / det; element (r, c) goes to out[c * 3 + r] */
    float cof[3][3] = { { A, B, C }, { D, E, F }, { G, H, I } };
    for (int r = 0; r < 3; r++)
        for (int cc = 0; cc < 3; cc++)
            out[cc * 3 + r] = cof[r][cc] * k;
}

/* ------------------------------------------------------------------ GL set-up */

static GLuint shader(GLenum type, const char *src, char *err, size_t errsize)
{
    GLuint sh = glCreateShader(type);
    glShaderSource(sh, 1, &src, NULL);
    glCompileShader(sh);
    GLint ok = 0;
    glGetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[400] = "";
        glGetShaderInfoLog(sh, sizeof log, NULL, log);
        snprintf(err, errsize, "baseline shader: %s", log);
        glDeleteShader(sh);
        return 0;
    }
    return sh;
}

static GLuint program(const char *vs, const char *fs, char *err, size_t errsize)
{
    GLuint v = shader(GL_VERTEX_SHADER, vs, err, errsize);
    GLuint f = v ? shader(GL_FRAGMENT_SHADER, fs, err, errsize) : 0;
    if (!f)
        return 0;
    GLuint p = glCreateProgram();
    glAttachShader(p, v);
    glAttachShader(p, f);
    glLinkProgram(p);
    glDeleteShader(v);
    glDeleteShader(f);
    GLint ok = 0;
    glGetProgramiv(p, GL_LINK_STATUS, &ok);
    if (!ok) {
        snprintf(err, errsize, "baseline program does not link");
        return 0;
    }
    return p;
}

/* The floor: the wall's world position per fragment, one light, one normal. */
static const char *floor_vs =
    "#version 330 core\n"
    "layout(location = 0) in vec3 pos;\n"
    "uniform mat4 mvp, model;\n"
    "out vec3 p;\n"
    "void main() { p = (model * vec4(pos, 1.0)).xyz; gl_Position = mvp * vec4(pos, 1.0); }\n";
static const char *floor_fs =
    "#version 330 core\n"
    "in vec3 p;\n"
    "uniform vec3 n, light, albedo;\n"
    "uniform float ambient;\n"
    "out vec4 color;\n"
    "void main() {\n"
    "    float d = max(0.0, dot(n, normalize(light - p)));\n"
    "    color = vec4(albedo * (ambient + (1.0 - ambient) * d), 1.0);\n"
    "}\n";

/* The classic renderer's one shader for everything, as such renderers have it: uniforms
 * choose flat or lit, checker or not, sphere normals or the mesh's. */
static const char *classic_vs =
    "#version 330 core\n"
    "layout(location = 0) in vec3 pos;\n"
    "layout(location = 1) in vec3 nrm;\n"
    "uniform mat4 model, view_proj;\n"
    "uniform vec4 clip;\n"
    "out vec3 world, local, normal;\n"
    "void main() {\n"
    "    vec4 w = model * vec4(pos, 1.0);\n"
    "    world = w.xyz; local = pos; normal = nrm;\n"
    "    gl_ClipDistance[0] = dot(clip, w);\n"
    "    gl_Position = view_proj * w;\n"
    "}\n";
static const char *classic_fs =
    "#version 330 core\n"
    "in vec3 world, local, normal;\n"
    "uniform mat3 nmat;\n"
    "uniform vec3 eye, albedo, albedo_b, scale, tint;\n"
    "uniform float cell, ambient;\n"
    "uniform int sphere, quad, flat_colour, nlights;\n"
    "uniform vec3 lpos[8], lcol[8];\n"
    "out vec4 color;\n"
    "void main() {\n"
    "    if (flat_colour != 0) { color = vec4(albedo * tint, 1.0); return; }\n"
    "    vec3 n = normalize(nmat * (sphere != 0 ? local : normal));\n"
    "    if (dot(n, eye - world) < 0.0) n = -n;\n"
    "    vec3 a = albedo;\n"
    "    if (cell > 0.0) {\n"
    "        vec3 q = floor(local * scale / cell);\n"
    "        float s = q.x + q.y + (quad != 0 ? 0.0 : q.z);\n"
    "        if (mod(s, 2.0) > 0.5) a = albedo_b;\n"
    "    }\n"
    "    vec3 sum = vec3(0.0);\n"
    "    for (int i = 0; i < nlights; i++)\n"
    "        sum += lcol[i] * max(0.0, dot(n, normalize(lpos[i] - world)));\n"
    "    color = vec4(clamp(a * (ambient + (1.0 - ambient) * sum), 0.0, 1.0) * tint, 1.0);\n"
    "}\n";

typedef struct vtx { float p[3], n[3]; } vtx;

/* Triangles (as lists) of the unit quad, the unit box and the unit sphere. */
static vtx *meshes(baseline *b, int *count)
{
    int nq = 6, nb = 36, ns = SPHERE_SEG * SPHERE_RING * 6;
    vtx *v = malloc(sizeof *v * (size_t)(nq + nb + ns));
    if (!v)
        return NULL;
    int k = 0;
    static const float qx[6] = { -0.5f, 0.5f, 0.5f, -0.5f, 0.5f, -0.5f };
    static const float qy[6] = { -0.5f, -0.5f, 0.5f, -0.5f, 0.5f, 0.5f };
    b->quad.first = k;
    for (int i = 0; i < 6; i++)
        v[k++] = (vtx){ { qx[i], qy[i], 0 }, { 0, 0, 1 } };
    b->quad.count = 6;
    /* the box: each face the quad turned to its normal (axis a, sign s) */
    b->box.first = k;
    for (int a = 0; a < 3; a++)
        for (int s = -1; s <= 1; s += 2) {
            int u = (a + 1) % 3, w = (a + 2) % 3;
            for (int i = 0; i < 6; i++) {
                vtx t = { { 0 }, { 0 } };
                t.p[a] = 0.5f * (float)s;
                /* counter-clockwise seen from outside: swap the in-plane axes for s < 0 */
                t.p[s > 0 ? u : w] = qx[i];
                t.p[s > 0 ? w : u] = qy[i];
                t.n[a] = (float)s;
                v[k++] = t;
            }
        }
    b->box.count = 36;
    b->sphere.first = k;
    for (int j = 0; j < SPHERE_RING; j++)
        for (int i = 0; i < SPHERE_SEG; i++) {
            float p[4][3];
            for (int c = 0; c < 4; c++) {
                int ii = i + (c == 1 || c == 2), jj = j + (c >= 2);
                float th = (float)M_PI * (float)jj / SPHERE_RING;
                float ph = 2.0f * (float)M_PI * (float)ii / SPHERE_SEG;
                p[c][0] = sinf(th) * cosf(ph);
                p[c][1] = cosf(th);
                p[c][2] = -sinf(th) * sinf(ph);
            }
            static const int tri[6] = { 0, 3, 2, 0, 2, 1 };
            for (int t = 0; t < 6; t++) {
                const float *q = p[tri[t]];
                v[k++] = (vtx){ { q[0], q[1], q[2] }, { q[0], q[1], q[2] } };
            }
        }
    b->sphere.count = k - b->sphere.first;
    *count = k;
    return v;
}

baseline *baseline_create(int width, int height, char *err, size_t errsize)
{
    baseline *b = calloc(1, sizeof *b);
    if (!b) {
        snprintf(err, errsize, "out of memory");
        return NULL;
    }
    b->w = width;
    b->h = height;
    const int attribs[] = { OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 0,
                            OSMESA_STENCIL_BITS, 0, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                            OSMESA_CONTEXT_MAJOR_VERSION, 3, OSMESA_CONTEXT_MINOR_VERSION, 3,
                            0 };
    b->ctx = OSMesaCreateContextAttribs(attribs, NULL);
    if (!b->ctx || !OSMesaMakeCurrent(b->ctx, b->token, GL_UNSIGNED_BYTE, 4, 4)) {
        snprintf(err, errsize, "baseline: no OSMesa 3.3 core context");
        baseline_destroy(b);
        return NULL;
    }
    glGenRenderbuffers(1, &b->color_rb);
    glBindRenderbuffer(GL_RENDERBUFFER, b->color_rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    glGenRenderbuffers(1, &b->depth_rb);
    glBindRenderbuffer(GL_RENDERBUFFER, b->depth_rb);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH24_STENCIL8, width, height);
    glGenFramebuffers(1, &b->fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, b->fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                              b->color_rb);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                              b->depth_rb);
    if (glCheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        snprintf(err, errsize, "baseline: framebuffer incomplete");
        baseline_destroy(b);
        return NULL;
    }
    b->prog = program(classic_vs, classic_fs, err, errsize);
    b->floor_prog = b->prog ? program(floor_vs, floor_fs, err, errsize) : 0;
    int nv = 0;
    vtx *v = b->floor_prog ? meshes(b, &nv) : NULL;
    if (!v || limen_plan_create(&b->plan)) {
        if (b->floor_prog)
            snprintf(err, errsize, "out of memory");
        free(v);
        baseline_destroy(b);
        return NULL;
    }
    glGenVertexArrays(1, &b->vao);
    glBindVertexArray(b->vao);
    glGenBuffers(1, &b->vbo);
    glBindBuffer(GL_ARRAY_BUFFER, b->vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof *v * (size_t)nv), v, GL_STATIC_DRAW);
    free(v);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, sizeof(vtx), (void *)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, sizeof(vtx), (void *)(3 * sizeof(float)));
#define U(f, n) b->f = glGetUniformLocation(b->prog, n)
    U(u_model, "model"); U(u_nmat, "nmat"); U(u_vp, "view_proj"); U(u_clip, "clip");
    U(u_eye, "eye"); U(u_albedo, "albedo"); U(u_albedo_b, "albedo_b"); U(u_cell, "cell");
    U(u_scale, "scale"); U(u_sphere, "sphere"); U(u_quad, "quad"); U(u_flat, "flat_colour");
    U(u_tint, "tint"); U(u_ambient, "ambient"); U(u_nlights, "nlights"); U(u_lpos, "lpos");
    U(u_lcol, "lcol");
#undef U
#define F(f, n) b->f = glGetUniformLocation(b->floor_prog, n)
    F(f_mvp, "mvp"); F(f_model, "model"); F(f_normal, "n"); F(f_light, "light");
    F(f_albedo, "albedo"); F(f_ambient, "ambient");
#undef F
    return b;
}

void baseline_destroy(baseline *b)
{
    if (!b)
        return;
    if (b->ctx) {
        if (OSMesaMakeCurrent(b->ctx, b->token, GL_UNSIGNED_BYTE, 4, 4)) {
            glDeleteProgram(b->prog);
            glDeleteProgram(b->floor_prog);
            glDeleteBuffers(1, &b->vbo);
            glDeleteVertexArrays(1, &b->vao);
            glDeleteFramebuffers(1, &b->fbo);
            glDeleteRenderbuffers(1, &b->color_rb);
            glDeleteRenderbuffers(1, &b->depth_rb);
        }
        OSMesaMakeCurrent(NULL, NULL, GL_UNSIGNED_BYTE, 0, 0);
        OSMesaDestroyContext(b->ctx);
    }
    limen_plan_destroy(b->plan);
    free(b);
}

static int begin(baseline *b, char *err, size_t errsize)
{
    if (!OSMesaMakeCurrent(b->ctx, b->token, GL_UNSIGNED_BYTE, 4, 4)) {
        snprintf(err, errsize, "baseline: cannot make the context current");
        return -1;
    }
    glBindFramebuffer(GL_FRAMEBUFFER, b->fbo);
    glViewport(0, 0, b->w, b->h);
    glBindVertexArray(b->vao);
    return 0;
}

static double finish(double t0, char *err, size_t errsize)
{
    glFinish();
    double ms = now_ms() - t0;
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        snprintf(err, errsize, "baseline: OpenGL error 0x%x", e);
        return -1;
    }
    return ms;
}

/* ------------------------------------------------------------------ the floor */

double baseline_floor_frame(baseline *b, limen_scene *s, char *err, size_t errsize)
{
    if (begin(b, err, errsize))
        return -1;
    double t0 = now_ms();
    b->nnodes = limen_scene_nodes(s, b->nodes, MAX_NODES);
    limen_node wall = { 0 }, light = { 0 };
    for (int i = 0; i < b->nnodes && i < MAX_NODES; i++) {
        limen_node_kind k = limen_node_get_kind(s, b->nodes[i]);
        if (k == LIMEN_NODE_QUAD && !wall.id)
            wall = b->nodes[i];
        if (k == LIMEN_NODE_LIGHT && !light.id)
            light = b->nodes[i];
    }
    float view[16], proj[16], world[16], lw[16], dims[3], albedo[3];
    if (!wall.id || !light.id ||
        limen_camera_matrices(s, (float)b->w / (float)b->h, LIMEN_DEPTH_NO, view, proj) ||
        limen_node_world_matrix(s, wall, world) || limen_node_world_matrix(s, light, lw) ||
        limen_node_get_dims(s, wall, dims) || limen_node_get_color(s, wall, albedo)) {
        snprintf(err, errsize, "floor: the scene needs a camera, a quad and a light");
        return -1;
    }
    float model[16], mvp[16];
    memcpy(model, world, sizeof model);
    for (int r = 0; r < 4; r++) {
        model[0 + r] *= dims[0];
        model[4 + r] *= dims[1];
    }
    mat_mul(view, model, mvp);
    mat_mul(proj, mvp, mvp);
    float n[3] = { world[8], world[9], world[10] };
    float len = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int i = 0; i < 3; i++)
        n[i] /= len;
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_STENCIL_TEST);
    glClearColor(0, 0, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glUseProgram(b->floor_prog);
    glUniformMatrix4fv(b->f_mvp, 1, GL_FALSE, mvp);
    glUniformMatrix4fv(b->f_model, 1, GL_FALSE, model);
    glUniform3fv(b->f_normal, 1, n);
    glUniform3fv(b->f_light, 1, lw + 12);
    glUniform3fv(b->f_albedo, 1, albedo);
    glUniform1f(b->f_ambient, limen_scene_get_ambient(s));
    glDrawArrays(GL_TRIANGLES, b->quad.first, b->quad.count);
    return finish(t0, err, errsize);
}

/* ------------------------------------------------------------------ the classic recursion */

/* Draws node n (any kind but lights, cameras and groups) with the bound view. */
static void draw_shape(baseline *b, limen_scene *s, limen_node n, const float *albedo,
                       int flat)
{
    limen_node_kind k = limen_node_get_kind(s, n);
    float world[16], dims[3], a[3], bb[3], cell = 0;
    limen_node_world_matrix(s, n, world);
    limen_node_get_dims(s, n, dims);
    limen_node_get_checker(s, n, a, bb, &cell);
    const range *rg = &b->box;
    float sc[3] = { dims[0], dims[1], dims[2] };
    int surface = k == LIMEN_NODE_MIRROR || k == LIMEN_NODE_PORTAL;
    if (k == LIMEN_NODE_QUAD || surface) {
        rg = &b->quad;
        sc[2] = 1;
    } else if (k == LIMEN_NODE_SPHERE) {
        rg = &b->sphere;
        sc[0] = sc[1] = sc[2] = dims[0];
    }
    float model[16], nmat[9];
    memcpy(model, world, sizeof model);
    for (int c = 0; c < 3; c++)
        for (int r = 0; r < 4; r++)
            model[c * 4 + r] *= sc[c];
    normal_matrix(model, nmat);
    glUniformMatrix4fv(b->u_model, 1, GL_FALSE, model);
    glUniformMatrix3fv(b->u_nmat, 1, GL_FALSE, nmat);
    glUniform3fv(b->u_albedo, 1, albedo ? albedo : a);
    glUniform3fv(b->u_albedo_b, 1, bb);
    glUniform1f(b->u_cell, flat || surface ? 0.0f : cell);
    glUniform3fv(b->u_scale, 1, sc);
    glUniform1i(b->u_sphere, k == LIMEN_NODE_SPHERE);
    glUniform1i(b->u_quad, k == LIMEN_NODE_QUAD);
    glUniform1i(b->u_flat, flat);
    /* surfaces are not cut by the near plane (a camera closer than it still sees through) */
    if (surface)
        glEnable(GL_DEPTH_CLAMP);
    else
        glDisable(GL_DEPTH_CLAMP);
    if (k == LIMEN_NODE_BOX || k == LIMEN_NODE_SPHERE)
        glEnable(GL_CULL_FACE);
    else
        glDisable(GL_CULL_FACE);
    glDrawArrays(GL_TRIANGLES, rg->first, rg->count);
}

static void use_view(baseline *b, const limen_view *v)
{
    float vp[16];
    mat_mul(v->proj, v->view, vp);
    glUniformMatrix4fv(b->u_vp, 1, GL_FALSE, vp);
    glUniform3fv(b->u_eye, 1, v->eye);
    glUniform3fv(b->u_tint, 1, v->tint);
    static const float keep[4] = { 0, 0, 0, 1 };
    if (v->clip == LIMEN_CLIP_PLANE && v->depth > 0) {
        glUniform4fv(b->u_clip, 1, v->clip_plane);
        glEnable(GL_CLIP_DISTANCE0);
    } else {
        glUniform4fv(b->u_clip, 1, keep);
        glDisable(GL_CLIP_DISTANCE0);
    }
    glFrontFace(v->front_face_cw ? GL_CW : GL_CCW);
}

static int is_thing(limen_node_kind k)
{
    return k == LIMEN_NODE_BOX || k == LIMEN_NODE_SPHERE || k == LIMEN_NODE_QUAD;
}

/* View vi on the pixels whose stencil is `level`: first every surface it recurses into
 * (marked by an increment, its view drawn, unmarked), then a full-screen depth clear, the
 * recursing surfaces into depth, and the whole scene. */
static void classic_view(baseline *b, limen_scene *s, int vi, int level, const float bg[3])
{
    const limen_view *v = limen_plan_view(b->plan, vi);
    const limen_view_surface *vs;
    int n = limen_plan_view_surfaces(b->plan, vi, &vs);
    b->views++;
    use_view(b, v);
    for (int k = 0; k < n; k++) {
        if (vs[k].state != LIMEN_SURFACE_RECURSE)
            continue;
        const limen_view *c = limen_plan_view(b->plan, vs[k].child);
        float cbg[3] = { bg[0] * c->tint[0], bg[1] * c->tint[1], bg[2] * c->tint[2] };
        float white[3] = { 1, 1, 1 };
        /* mark, painting the nested view's background */
        glDisable(GL_DEPTH_TEST);
        glDepthMask(GL_FALSE);
        glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
        glStencilFunc(GL_EQUAL, level, 0xFF);
        glStencilOp(GL_KEEP, GL_KEEP, GL_INCR);
        glUniform3fv(b->u_tint, 1, white);
        draw_shape(b, s, vs[k].node, cbg, 1);
        classic_view(b, s, vs[k].child, level + 1, bg);
        /* unmark */
        use_view(b, v);
        glDisable(GL_DEPTH_TEST);
        glDepthMask(GL_FALSE);
        glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
        glStencilFunc(GL_EQUAL, level + 1, 0xFF);
        glStencilOp(GL_KEEP, GL_KEEP, GL_DECR);
        draw_shape(b, s, vs[k].node, bg, 1);
    }
    /* the full-screen depth clear, then the recursing surfaces into depth */
    glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
    glStencilFunc(GL_EQUAL, level, 0xFF);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glClear(GL_DEPTH_BUFFER_BIT);
    glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
    for (int k = 0; k < n; k++)
        if (vs[k].state == LIMEN_SURFACE_RECURSE)
            draw_shape(b, s, vs[k].node, bg, 1);
    /* the whole scene: every thing, and the surfaces that end here */
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    for (int i = 0; i < b->nnodes && i < MAX_NODES; i++)
        if (is_thing(limen_node_get_kind(s, b->nodes[i])) &&
            limen_node_get_visible(s, b->nodes[i]))
            draw_shape(b, s, b->nodes[i], NULL, 0);
    for (int k = 0; k < n; k++) {
        float back[3], fill[3];
        limen_surface_get(s, vs[k].node, NULL, back, fill, NULL);
        if (vs[k].state == LIMEN_SURFACE_FILL)
            draw_shape(b, s, vs[k].node, fill, 1);
        else if (vs[k].state == LIMEN_SURFACE_BACK)
            draw_shape(b, s, vs[k].node, back, 0);
    }
}

double baseline_classic_frame(baseline *b, limen_scene *s, int max_depth, char *err,
                              size_t errsize)
{
    if (begin(b, err, errsize))
        return -1;
    double t0 = now_ms();
    limen_plan_desc pd = { .width = b->w, .height = b->h, .range = LIMEN_DEPTH_NO,
                           .limits = { .clip = LIMEN_CLIP_OBLIQUE,
                                       .depth_rule = LIMEN_DEPTH_RULE_CAP, .depth = max_depth,
                                       .budget = { INT64_MAX, INT64_MAX } },
                           .cull = LIMEN_CULL_FRUSTUM };
    if (limen_plan_build(b->plan, s, &pd)) {
        snprintf(err, errsize, "classic: %s", limen_scene_error(s));
        return -1;
    }
    b->nnodes = limen_scene_nodes(s, b->nodes, MAX_NODES);
    float lpos[MAX_LIGHTS][3], lcol[MAX_LIGHTS][3];
    int nl = 0;
    for (int i = 0; i < b->nnodes && i < MAX_NODES; i++) {
        limen_node_kind k = limen_node_get_kind(s, b->nodes[i]);
        if (k == LIMEN_NODE_CYLINDER) {
            snprintf(err, errsize, "classic: cylinders are not drawn by this baseline");
            return -1;
        }
        float w[16];
        if (k == LIMEN_NODE_LIGHT && nl < MAX_LIGHTS && limen_node_get_visible(s, b->nodes[i]) &&
            !limen_node_world_matrix(s, b->nodes[i], w)) {
            memcpy(lpos[nl], w + 12, sizeof lpos[nl]);
            limen_node_get_color(s, b->nodes[i], lcol[nl]);
            nl++;
        }
    }
    float bg[3];
    limen_scene_get_background(s, bg);
    glClearColor(bg[0], bg[1], bg[2], 1);
    glClearDepth(1.0);
    glClearStencil(0);
    glDepthMask(GL_TRUE);
    glStencilMask(0xFF);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    glEnable(GL_STENCIL_TEST);
    glCullFace(GL_BACK);
    glUseProgram(b->prog);
    glUniform1f(b->u_ambient, limen_scene_get_ambient(s));
    glUniform1i(b->u_nlights, nl);
    if (nl) {
        glUniform3fv(b->u_lpos, nl, &lpos[0][0]);
        glUniform3fv(b->u_lcol, nl, &lcol[0][0]);
    }
    b->views = 0;
    classic_view(b, s, 0, 0, bg);
    glDisable(GL_STENCIL_TEST);
    return finish(t0, err, errsize);
}

void baseline_read_rgb(baseline *b, unsigned char *rgb)
{
    if (!OSMesaMakeCurrent(b->ctx, b->token, GL_UNSIGNED_BYTE, 4, 4))
        return;
    glBindFramebuffer(GL_READ_FRAMEBUFFER, b->fbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    size_t row = (size_t)b->w * 3;
    for (int y = 0; y < b->h; y++)
        glReadPixels(0, b->h - 1 - y, b->w, 1, GL_RGB, GL_UNSIGNED_BYTE, rgb + (size_t)y * row);
}

int baseline_views(const baseline *b)
{
    return b->views;
}
