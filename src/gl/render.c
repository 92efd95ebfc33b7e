/* render.c - the OpenGL renderer: context, shaders, meshes, framebuffers, and drawing the
 * scene for a view. Shading follows DESIGN.md exactly so that the ray tracer can match it
 * pixel for pixel. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/internal.h"
#include "gl/glapi.h"
#include "gl/mesh.h"

/* A silhouette may stray this far (pixels) from the true curved shape. */
#define LOD_TOLERANCE_PX 0.2f

typedef struct uniforms {
    GLint model, normal_mat, view_proj, eye, clip_plane, albedo, albedo_b, cell, scale,
        shape, quad, ambient, nlights, light_pos, light_col;
} uniforms;

struct limen_renderer {
    const limen__ctx_ops *ops;
    limen__ctx *ctx;
    limen__gl gl;
    int width, height, msaa;
    limen_depth_range range;
    bool has_fragment_stats;
    char err[LIMEN__ERR_MAX];
    char info[256];

    GLuint prog, vao, vbo, ibo;
    uniforms u;
    limen__meshes meshes;

    GLuint fbo, color_rb, depth_rb;         /* what views draw into (multisampled if msaa) */
    GLuint resolve_fbo, resolve_rb;         /* single-sampled copy when msaa */
    GLuint q_samples, q_fragments;

    unsigned char *rgba;                    /* read-back buffer */
    bool have_frame;
};

/* One view as the renderer draws it. */
typedef struct rview {
    mat4 view, proj, view_proj;
    vec3 eye;                   /* world-space eye (for two-sided lighting) */
    vec4 clip;                  /* world-space plane; gl_ClipDistance when enabled */
    bool clip_on;
    float px_scale;             /* proj[1][1] * height / 2: pixels per unit at distance 1 */
} rview;

#define GL(fn) r->gl.fn

static limen_status rfail(limen_renderer *r, limen_status st, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

static limen_status rfail(limen_renderer *r, limen_status st, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    limen__vformat(r->err, sizeof r->err, fmt, ap);
    va_end(ap);
    return st;
}

/* ------------------------------------------------------------------ GL loading */

const char *limen__gl_load(limen__gl *gl, limen__getproc getproc)
{
#define LOAD_REQ(ret, name, args)                                                        \
    gl->name = (ret(APIENTRY *) args)getproc("gl" #name);                                \
    if (!gl->name)                                                                       \
        return "gl" #name;
#define LOAD_OPT(ret, name, args) gl->name = (ret(APIENTRY *) args)getproc("gl" #name);
    LIMEN_GL_REQUIRED(LOAD_REQ)
    LIMEN_GL_OPTIONAL(LOAD_OPT)
#undef LOAD_REQ
#undef LOAD_OPT
    return NULL;
}

/* ------------------------------------------------------------------ shaders */

static const char *vs_src =
    "#version 330 core\n"
    "layout(location = 0) in vec3 a_pos;\n"
    "layout(location = 1) in vec3 a_nrm;\n"
    "uniform mat4 u_model, u_view_proj;\n"
    "uniform vec4 u_clip_plane;\n"
    "out vec3 v_world, v_local, v_nrm;\n"
    "void main() {\n"
    "    vec4 w = u_model * vec4(a_pos, 1.0);\n"
    "    v_world = w.xyz; v_local = a_pos; v_nrm = a_nrm;\n"
    "    gl_ClipDistance[0] = dot(u_clip_plane, w);\n"
    "    gl_Position = u_view_proj * w;\n"
    "}\n";

/* The normal comes from the true shape where it is curved (sphere, cylinder side), so
 * shading does not depend on the tessellation. */
static const char *fs_src =
    "#version 330 core\n"
    "in vec3 v_world, v_local, v_nrm;\n"
    "uniform mat3 u_normal_mat;\n"
    "uniform vec3 u_eye, u_albedo, u_albedo_b, u_scale;\n"
    "uniform float u_cell, u_ambient;\n"
    "uniform int u_shape, u_quad, u_nlights;\n"
    "uniform vec3 u_light_pos[8], u_light_col[8];\n"
    "out vec4 o_color;\n"
    "void main() {\n"
    "    vec3 nl = v_nrm;\n"
    "    if (u_shape == 1) nl = v_local;\n"
    "    else if (u_shape == 2 && abs(v_nrm.y) < 0.5) nl = vec3(v_local.x, 0.0, v_local.z);\n"
    "    vec3 n = normalize(u_normal_mat * nl);\n"
    "    if (dot(n, u_eye - v_world) < 0.0) n = -n;\n"
    "    vec3 albedo = u_albedo;\n"
    "    if (u_cell > 0.0) {\n"
    "        vec3 c = floor(v_local * u_scale / u_cell);\n"
    "        float k = c.x + c.y + (u_quad != 0 ? 0.0 : c.z);\n"
    "        if (k - 2.0 * floor(k * 0.5) > 0.5) albedo = u_albedo_b;\n"
    "    }\n"
    "    vec3 light = vec3(0.0);\n"
    "    for (int i = 0; i < u_nlights; i++)\n"
    "        light += u_light_col[i] * max(0.0, dot(n, normalize(u_light_pos[i] - v_world)));\n"
    "    o_color = vec4(clamp(albedo * (u_ambient + (1.0 - u_ambient) * light), 0.0, 1.0), 1.0);\n"
    "}\n";

static GLuint compile(limen_renderer *r, GLenum type, const char *src)
{
    GLuint sh = GL(CreateShader)(type);
    GL(ShaderSource)(sh, 1, &src, NULL);
    GL(CompileShader)(sh);
    GLint ok = 0;
    GL(GetShaderiv)(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        char log[400] = "";
        GL(GetShaderInfoLog)(sh, sizeof log, NULL, log);
        rfail(r, LIMEN_ERR_GL, "shader compile failed: %s", log);
        GL(DeleteShader)(sh);
        return 0;
    }
    return sh;
}

static limen_status build_program(limen_renderer *r)
{
    GLuint vs = compile(r, GL_VERTEX_SHADER, vs_src);
    GLuint fs = vs ? compile(r, GL_FRAGMENT_SHADER, fs_src) : 0;
    if (!vs || !fs) {
        if (vs)
            GL(DeleteShader)(vs);
        return LIMEN_ERR_GL;
    }
    r->prog = GL(CreateProgram)();
    GL(AttachShader)(r->prog, vs);
    GL(AttachShader)(r->prog, fs);
    GL(LinkProgram)(r->prog);
    GL(DeleteShader)(vs);
    GL(DeleteShader)(fs);
    GLint ok = 0;
    GL(GetProgramiv)(r->prog, GL_LINK_STATUS, &ok);
    if (!ok) {
        char log[400] = "";
        GL(GetProgramInfoLog)(r->prog, sizeof log, NULL, log);
        return rfail(r, LIMEN_ERR_GL, "shader link failed: %s", log);
    }
#define U(field, name) r->u.field = GL(GetUniformLocation)(r->prog, name)
    U(model, "u_model");
    U(normal_mat, "u_normal_mat");
    U(view_proj, "u_view_proj");
    U(eye, "u_eye");
    U(clip_plane, "u_clip_plane");
    U(albedo, "u_albedo");
    U(albedo_b, "u_albedo_b");
    U(cell, "u_cell");
    U(scale, "u_scale");
    U(shape, "u_shape");
    U(quad, "u_quad");
    U(ambient, "u_ambient");
    U(nlights, "u_nlights");
    U(light_pos, "u_light_pos");
    U(light_col, "u_light_col");
#undef U
    return LIMEN_OK;
}

static limen_status upload_meshes(limen_renderer *r)
{
    if (limen__meshes_build(&r->meshes))
        return rfail(r, LIMEN_ERR_NOMEM, "out of memory building meshes");
    GL(GenVertexArrays)(1, &r->vao);
    GL(BindVertexArray)(r->vao);
    GL(GenBuffers)(1, &r->vbo);
    GL(BindBuffer)(GL_ARRAY_BUFFER, r->vbo);
    GL(BufferData)(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof(limen__vertex) * r->meshes.nverts),
                   r->meshes.verts, GL_STATIC_DRAW);
    GL(GenBuffers)(1, &r->ibo);
    GL(BindBuffer)(GL_ELEMENT_ARRAY_BUFFER, r->ibo);
    GL(BufferData)(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(sizeof(uint32_t) * r->meshes.nidx),
                   r->meshes.idx, GL_STATIC_DRAW);
    GL(EnableVertexAttribArray)(0);
    GL(VertexAttribPointer)(0, 3, GL_FLOAT, GL_FALSE, sizeof(limen__vertex), (void *)0);
    GL(EnableVertexAttribArray)(1);
    GL(VertexAttribPointer)(1, 3, GL_FLOAT, GL_FALSE, sizeof(limen__vertex),
                            (void *)offsetof(limen__vertex, nrm));
    return LIMEN_OK;
}

/* ------------------------------------------------------------------ framebuffers */

static GLuint renderbuffer(limen_renderer *r, GLenum format, int samples)
{
    GLuint rb;
    GL(GenRenderbuffers)(1, &rb);
    GL(BindRenderbuffer)(GL_RENDERBUFFER, rb);
    if (samples > 1)
        GL(RenderbufferStorageMultisample)(GL_RENDERBUFFER, samples, format, r->width,
                                           r->height);
    else
        GL(RenderbufferStorage)(GL_RENDERBUFFER, format, r->width, r->height);
    return rb;
}

static limen_status build_targets(limen_renderer *r)
{
    GLenum depth_fmt = r->range == LIMEN_DEPTH_ZO_REVERSED ? GL_DEPTH32F_STENCIL8
                                                           : GL_DEPTH24_STENCIL8;
    r->color_rb = renderbuffer(r, GL_RGBA8, r->msaa);
    r->depth_rb = renderbuffer(r, depth_fmt, r->msaa);
    GL(GenFramebuffers)(1, &r->fbo);
    GL(BindFramebuffer)(GL_FRAMEBUFFER, r->fbo);
    GL(FramebufferRenderbuffer)(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                r->color_rb);
    GL(FramebufferRenderbuffer)(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                                r->depth_rb);
    if (GL(CheckFramebufferStatus)(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return rfail(r, LIMEN_ERR_UNSUPPORTED, "framebuffer %dx%d (msaa %d) is incomplete",
                     r->width, r->height, r->msaa);
    if (r->msaa > 1) {
        r->resolve_rb = renderbuffer(r, GL_RGBA8, 0);
        GL(GenFramebuffers)(1, &r->resolve_fbo);
        GL(BindFramebuffer)(GL_FRAMEBUFFER, r->resolve_fbo);
        GL(FramebufferRenderbuffer)(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                    r->resolve_rb);
        if (GL(CheckFramebufferStatus)(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            return rfail(r, LIMEN_ERR_UNSUPPORTED, "resolve framebuffer is incomplete");
    }
    return LIMEN_OK;
}

/* ------------------------------------------------------------------ create / destroy */

static bool has_gl_ext(limen_renderer *r, const char *name)
{
    GLint n = 0;
    GL(GetIntegerv)(GL_NUM_EXTENSIONS, &n);
    for (GLint i = 0; i < n; i++) {
        const char *e = (const char *)GL(GetStringi)(GL_EXTENSIONS, (GLuint)i);
        if (e && strcmp(e, name) == 0)
            return true;
    }
    return false;
}

static limen_status setup(limen_renderer *r, const limen_renderer_desc *d)
{
    r->ops = d->backend == LIMEN_BACKEND_EGL ? &limen__ctx_egl : &limen__ctx_osmesa;
    if ((unsigned)d->backend > LIMEN_BACKEND_EGL)
        return rfail(r, LIMEN_ERR_ARG, "unknown backend %d", (int)d->backend);
    if ((unsigned)d->depth_range > LIMEN_DEPTH_ZO_REVERSED)
        return rfail(r, LIMEN_ERR_ARG, "unknown depth range %d", (int)d->depth_range);
    r->width = d->width > 0 ? d->width : 640;
    r->height = d->height > 0 ? d->height : 480;
    if (d->width < 0 || d->height < 0 || r->width > 16384 || r->height > 16384)
        return rfail(r, LIMEN_ERR_ARG, "image size %dx%d out of range (1 to 16384)", d->width,
                     d->height);
    if (d->msaa < 0 || d->msaa > 64)
        return rfail(r, LIMEN_ERR_ARG, "msaa %d out of range (0 to 64)", d->msaa);
    r->msaa = d->msaa > 1 ? d->msaa : 0;
    r->range = d->depth_range;

    r->ctx = r->ops->create(r->err, sizeof r->err);
    if (!r->ctx)
        return LIMEN_ERR_GL;
    if (r->ops->make_current(r->ctx))
        return rfail(r, LIMEN_ERR_GL, "%s: cannot make the context current", r->ops->name);
    const char *missing = limen__gl_load(&r->gl, r->ops->getproc);
    if (missing)
        return rfail(r, LIMEN_ERR_UNSUPPORTED, "%s: OpenGL entry point %s missing",
                     r->ops->name, missing);
    snprintf(r->info, sizeof r->info, "%s: %s, OpenGL %s", r->ops->name,
             (const char *)GL(GetString)(GL_RENDERER), (const char *)GL(GetString)(GL_VERSION));
    if (r->msaa) {
        GLint max_samples = 0;
        GL(GetIntegerv)(GL_MAX_SAMPLES, &max_samples);
        if (r->msaa > max_samples)
            return rfail(r, LIMEN_ERR_UNSUPPORTED, "msaa %d exceeds this context's %d",
                         r->msaa, max_samples);
    }
    if (r->range != LIMEN_DEPTH_NO && !r->gl.ClipControl)
        return rfail(r, LIMEN_ERR_UNSUPPORTED, "depth range zo needs glClipControl (GL 4.5)");
    r->has_fragment_stats = has_gl_ext(r, "GL_ARB_pipeline_statistics_query");

    limen_status st = build_program(r);
    if (!st)
        st = upload_meshes(r);
    if (!st)
        st = build_targets(r);
    if (st)
        return st;
    GL(GenQueries)(1, &r->q_samples);
    GL(GenQueries)(1, &r->q_fragments);
    r->rgba = malloc((size_t)r->width * (size_t)r->height * 4);
    if (!r->rgba)
        return rfail(r, LIMEN_ERR_NOMEM, "out of memory for a %dx%d image", r->width,
                     r->height);
    GLenum e = GL(GetError)();
    if (e != GL_NO_ERROR)
        return rfail(r, LIMEN_ERR_GL, "OpenGL error 0x%x while setting up", e);
    return LIMEN_OK;
}

limen_status limen_renderer_create(const limen_renderer_desc *desc, limen_renderer **out)
{
    if (!out)
        return LIMEN_ERR_ARG;
    *out = NULL;
    limen_renderer *r = calloc(1, sizeof *r);
    if (!r)
        return LIMEN_ERR_NOMEM;
    *out = r;
    limen_renderer_desc d = desc ? *desc : (limen_renderer_desc){ 0 };
    return setup(r, &d);
}

void limen_renderer_destroy(limen_renderer *r)
{
    if (!r)
        return;
    if (r->ctx && r->prog && !r->ops->make_current(r->ctx)) {
        GL(DeleteProgram)(r->prog);
        GL(DeleteBuffers)(1, &r->vbo);
        GL(DeleteBuffers)(1, &r->ibo);
        GL(DeleteVertexArrays)(1, &r->vao);
        GL(DeleteFramebuffers)(1, &r->fbo);
        GL(DeleteRenderbuffers)(1, &r->color_rb);
        GL(DeleteRenderbuffers)(1, &r->depth_rb);
        if (r->resolve_fbo) {
            GL(DeleteFramebuffers)(1, &r->resolve_fbo);
            GL(DeleteRenderbuffers)(1, &r->resolve_rb);
        }
        GL(DeleteQueries)(1, &r->q_samples);
        GL(DeleteQueries)(1, &r->q_fragments);
    }
    if (r->ctx)
        r->ops->destroy(r->ctx);
    limen__meshes_free(&r->meshes);
    free(r->rgba);
    free(r);
}

const char *limen_renderer_error(const limen_renderer *r)
{
    return r ? r->err : "no renderer";
}

const char *limen_renderer_gl_info(const limen_renderer *r)
{
    return r ? r->info : "";
}

void limen_renderer_size(const limen_renderer *r, int *width, int *height)
{
    if (width)
        *width = r ? r->width : 0;
    if (height)
        *height = r ? r->height : 0;
}

/* ------------------------------------------------------------------ drawing */

static void set_mat4(limen_renderer *r, GLint loc, mat4 m)
{
    GL(UniformMatrix4fv)(loc, 1, GL_FALSE, (const GLfloat *)m);
}

/* Lights in world space, shared by every view. */
static int gather_lights(limen_scene *s, float pos[][3], float col[][3])
{
    int n = 0;
    for (int i = 0; i < s->cap && n < LIMEN__MAX_LIGHTS; i++) {
        limen__node *node = &s->nodes[i];
        if (!(node->gen & 1u) || node->kind != LIMEN_NODE_LIGHT || !node->visible)
            continue;
        memcpy(pos[n], node->world[3], sizeof(float) * 3);
        memcpy(col[n], node->color, sizeof(float) * 3);
        n++;
    }
    return n;
}

/* Which mesh, and how the unit mesh is scaled, for a node; false if it draws nothing. */
static bool node_mesh(limen_renderer *r, const rview *v, const limen__node *node,
                      limen__range *range, vec3 scale, int *shape)
{
    float radius = 0;
    *shape = 0;
    switch (node->kind) {
    case LIMEN_NODE_BOX:
        *range = r->meshes.box;
        glm_vec3_copy((float *)node->dims, scale);
        return true;
    case LIMEN_NODE_QUAD:
        *range = r->meshes.quad;
        glm_vec3_copy((vec3){ node->dims[0], node->dims[1], 1.0f }, scale);
        return true;
    case LIMEN_NODE_SPHERE:
        radius = node->dims[0];
        glm_vec3_broadcast(radius, scale);
        *shape = 1;
        break;
    case LIMEN_NODE_CYLINDER:
        radius = node->dims[0];
        glm_vec3_copy((vec3){ node->dims[0], node->dims[1], node->dims[0] }, scale);
        radius = fmaxf(node->dims[0], 0.5f * node->dims[1]);
        *shape = 2;
        break;
    default:
        return false;
    }
    /* Level of detail from the projected size: the largest world-space stretch of the
     * node's axes times the radius, over the view distance of its centre. */
    float stretch = fmaxf(glm_vec3_norm((float *)node->world[0]),
                          fmaxf(glm_vec3_norm((float *)node->world[1]),
                                glm_vec3_norm((float *)node->world[2])));
    float world_r = radius * stretch;
    vec4 centre = { node->world[3][0], node->world[3][1], node->world[3][2], 1.0f };
    vec4 vc;
    glm_mat4_mulv((vec4 *)v->view, centre, vc);
    float dist = -vc[2];
    int lod = LIMEN__LODS - 1;
    if (dist > world_r * 1.01f)
        lod = limen__lod_for(world_r * v->px_scale / (dist - world_r), LOD_TOLERANCE_PX);
    *range = node->kind == LIMEN_NODE_SPHERE ? r->meshes.sphere[lod] : r->meshes.cylinder[lod];
    return true;
}

static void draw_geometry(limen_renderer *r, limen_scene *s, const rview *v)
{
    float lpos[LIMEN__MAX_LIGHTS][3], lcol[LIMEN__MAX_LIGHTS][3];
    int nlights = gather_lights(s, lpos, lcol);
    GL(UseProgram)(r->prog);
    GL(BindVertexArray)(r->vao);
    set_mat4(r, r->u.view_proj, (vec4 *)v->view_proj);
    GL(Uniform3fv)(r->u.eye, 1, v->eye);
    vec4 noclip = { 0, 0, 0, 1 };
    GL(Uniform4fv)(r->u.clip_plane, 1, v->clip_on ? v->clip : noclip);
    if (v->clip_on)
        GL(Enable)(GL_CLIP_DISTANCE0);
    else
        GL(Disable)(GL_CLIP_DISTANCE0);
    GL(Uniform1f)(r->u.ambient, s->ambient);
    GL(Uniform1i)(r->u.nlights, nlights);
    if (nlights) {
        GL(Uniform3fv)(r->u.light_pos, nlights, &lpos[0][0]);
        GL(Uniform3fv)(r->u.light_col, nlights, &lcol[0][0]);
    }
    for (int i = 0; i < s->cap; i++) {
        limen__node *node = &s->nodes[i];
        if (!(node->gen & 1u) || !node->visible)
            continue;
        limen__range range;
        vec3 scale;
        int shape;
        if (!node_mesh(r, v, node, &range, scale, &shape))
            continue;
        mat4 model;
        mat3 nm;
        glm_mat4_copy(node->world, model);
        glm_scale(model, scale);
        glm_mat4_pick3(model, nm);
        glm_mat3_inv(nm, nm);
        glm_mat3_transpose(nm);
        set_mat4(r, r->u.model, model);
        GL(UniformMatrix3fv)(r->u.normal_mat, 1, GL_FALSE, (const GLfloat *)nm);
        GL(Uniform3fv)(r->u.albedo, 1, node->color);
        GL(Uniform3fv)(r->u.albedo_b, 1, node->checker_b);
        GL(Uniform1f)(r->u.cell, node->checker_cell);
        GL(Uniform3fv)(r->u.scale, 1, scale);
        GL(Uniform1i)(r->u.shape, shape);
        GL(Uniform1i)(r->u.quad, node->kind == LIMEN_NODE_QUAD);
        /* Closed shapes hide their back faces; a quad is seen from both sides. */
        if (node->kind == LIMEN_NODE_QUAD)
            GL(Disable)(GL_CULL_FACE);
        else
            GL(Enable)(GL_CULL_FACE);
        GL(DrawElements)(GL_TRIANGLES, (GLsizei)range.count, GL_UNSIGNED_INT,
                         (void *)(sizeof(uint32_t) * range.first));
    }
}

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static void begin_frame(limen_renderer *r, limen_scene *s)
{
    GL(BindFramebuffer)(GL_FRAMEBUFFER, r->fbo);
    GL(Viewport)(0, 0, r->width, r->height);
    if (r->gl.ClipControl)
        GL(ClipControl)(GL_LOWER_LEFT,
                        r->range == LIMEN_DEPTH_NO ? GL_NEGATIVE_ONE_TO_ONE : GL_ZERO_TO_ONE);
    bool reversed = r->range == LIMEN_DEPTH_ZO_REVERSED;
    GL(Disable)(GL_SCISSOR_TEST);
    GL(Disable)(GL_BLEND);
    GL(ColorMask)(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    GL(DepthMask)(GL_TRUE);
    GL(StencilMask)(0xFF);
    GL(ClearColor)(s->background[0], s->background[1], s->background[2], 1.0f);
    GL(ClearDepth)(reversed ? 0.0 : 1.0);
    GL(ClearStencil)(0);
    GL(Clear)(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
    GL(Enable)(GL_DEPTH_TEST);
    GL(DepthFunc)(reversed ? GL_GREATER : GL_LESS);
    GL(CullFace)(GL_BACK);
    GL(FrontFace)(GL_CCW);
    if (r->msaa)
        GL(Enable)(GL_MULTISAMPLE);
}

limen_status limen_render_frame(limen_renderer *r, limen_scene *s, limen_frame_stats *stats)
{
    if (!r || !s)
        return LIMEN_ERR_ARG;
    if (!r->prog)
        return rfail(r, LIMEN_ERR_GL, "renderer was not set up: %s", r->err);
    if (r->ops->make_current(r->ctx))
        return rfail(r, LIMEN_ERR_GL, "%s: cannot make the context current", r->ops->name);
    double t0 = now_ms();

    rview v;
    float view[16], proj[16];
    limen_status st = limen_camera_matrices(s, (float)r->width / (float)r->height, r->range,
                                            view, proj);
    if (st)
        return rfail(r, st, "%s", limen_last_error(s));
    memcpy(v.view, view, sizeof view);
    memcpy(v.proj, proj, sizeof proj);
    glm_mat4_mul(v.proj, v.view, v.view_proj);
    mat4 cam_world;
    glm_mat4_inv(v.view, cam_world);
    glm_vec3_copy(cam_world[3], v.eye);
    v.clip_on = false;
    glm_vec4_zero(v.clip);
    v.px_scale = v.proj[1][1] * 0.5f * (float)r->height;

    begin_frame(r, s);
    GL(BeginQuery)(GL_SAMPLES_PASSED, r->q_samples);
    if (r->has_fragment_stats)
        GL(BeginQuery)(GL_FRAGMENT_SHADER_INVOCATIONS_ARB, r->q_fragments);
    draw_geometry(r, s, &v);
    GL(EndQuery)(GL_SAMPLES_PASSED);
    if (r->has_fragment_stats)
        GL(EndQuery)(GL_FRAGMENT_SHADER_INVOCATIONS_ARB);
    if (r->msaa) {
        GL(BindFramebuffer)(GL_READ_FRAMEBUFFER, r->fbo);
        GL(BindFramebuffer)(GL_DRAW_FRAMEBUFFER, r->resolve_fbo);
        GL(BlitFramebuffer)(0, 0, r->width, r->height, 0, 0, r->width, r->height,
                            GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
    GL(Finish)();
    double t1 = now_ms();

    GLenum e = GL(GetError)();
    if (e != GL_NO_ERROR)
        return rfail(r, LIMEN_ERR_GL, "OpenGL error 0x%x while rendering", e);
    r->have_frame = true;
    if (stats) {
        GLuint64 samples = 0, frags = 0;
        GL(GetQueryObjectui64v)(r->q_samples, GL_QUERY_RESULT, &samples);
        if (r->has_fragment_stats)
            GL(GetQueryObjectui64v)(r->q_fragments, GL_QUERY_RESULT, &frags);
        stats->ms = t1 - t0;
        stats->views = 1;
        stats->samples = samples;
        stats->fragments = frags;
        stats->pixels = (uint64_t)r->width * (uint64_t)r->height;
    }
    return LIMEN_OK;
}

limen_status limen_renderer_read_rgb(limen_renderer *r, unsigned char *rgb)
{
    if (!r || !rgb)
        return LIMEN_ERR_ARG;
    if (!r->have_frame)
        return rfail(r, LIMEN_ERR_ARG, "no frame rendered yet");
    if (r->ops->make_current(r->ctx))
        return rfail(r, LIMEN_ERR_GL, "%s: cannot make the context current", r->ops->name);
    GL(BindFramebuffer)(GL_READ_FRAMEBUFFER, r->msaa ? r->resolve_fbo : r->fbo);
    GL(PixelStorei)(GL_PACK_ALIGNMENT, 1);
    GL(ReadPixels)(0, 0, r->width, r->height, GL_RGBA, GL_UNSIGNED_BYTE, r->rgba);
    size_t w = (size_t)r->width, h = (size_t)r->height;
    for (size_t y = 0; y < h; y++) {
        const unsigned char *src = r->rgba + (h - 1 - y) * w * 4;
        unsigned char *dst = rgb + y * w * 3;
        for (size_t x = 0; x < w; x++) {
            dst[3 * x + 0] = src[4 * x + 0];
            dst[3 * x + 1] = src[4 * x + 1];
            dst[3 * x + 2] = src[4 * x + 2];
        }
    }
    GLenum e = GL(GetError)();
    return e == GL_NO_ERROR ? LIMEN_OK
                            : rfail(r, LIMEN_ERR_GL, "OpenGL error 0x%x reading pixels", e);
}

limen_status limen_renderer_write_png(limen_renderer *r, const char *path)
{
    if (!r || !path)
        return LIMEN_ERR_ARG;
    unsigned char *rgb = malloc((size_t)r->width * (size_t)r->height * 3);
    if (!rgb)
        return rfail(r, LIMEN_ERR_NOMEM, "out of memory");
    limen_status st = limen_renderer_read_rgb(r, rgb);
    if (!st) {
        st = limen_write_png(path, r->width, r->height, rgb);
        if (st)
            rfail(r, st, "cannot write '%s'", path);
    }
    free(rgb);
    return st;
}
