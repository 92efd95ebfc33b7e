/* render.c - the OpenGL renderer: context, shaders, meshes, framebuffers, and a frame: the
 * plan, the drawables and the draw list built by the core, executed by gl/backend.c. Shading follows docs/DESIGN.md exactly so that the ray tracer can match it
 * pixel for pixel. */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "gl/gl_internal.h"

limen_status limen__rfail(limen_renderer *r, limen_status st, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->err, sizeof r->err, fmt, ap);
    va_end(ap);
    return st;
}

void limen__draw_fail(limen_renderer *r, limen_status st, const char *fmt, ...)
{
    if (r->draw_status)
        return;
    r->draw_status = st;
    if (!fmt)
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->err, sizeof r->err, fmt, ap);
    va_end(ap);
}

void limen__renderer_set_faults(limen_renderer *r, unsigned faults)
{
    if (r)
        r->faults = faults;
}

/* ------------------------------------------------------------------ GL loading */

const char *limen__gl_load(limen__gl *gl, limen__glproc (*getproc)(struct limen__ctx *c,
                                                                   const char *name),
                           struct limen__ctx *c)
{
#define LOAD_REQ(ret, name, args)                                                        \
    gl->name = (ret(APIENTRY *) args)getproc(c, "gl" #name);                             \
    if (!gl->name)                                                                       \
        return "gl" #name;
#define LOAD_OPT(ret, name, args) gl->name = (ret(APIENTRY *) args)getproc(c, "gl" #name);
    LIMEN_GL_REQUIRED(LOAD_REQ)
    LIMEN_GL_OPTIONAL(LOAD_OPT)
#undef LOAD_REQ
#undef LOAD_OPT
    return NULL;
}

/* ------------------------------------------------------------------ shaders */

/* Flat polygons given in NDC (x, y, z), in one colour: the surfaces' marks, seals and fills
 * and the depth resets and backgrounds of nested views. It is its own program because these
 * passes are most of the stencil method's fragments and the main program's shader costs
 * llvmpipe its full price even where colour writes are masked off; its clip distances cut
 * nothing whatever is enabled (llvmpipe, Mesa 22.3, was seen to go on clipping a draw of the
 * main program by the last view's gl_ClipDistance plane after glDisable(GL_CLIP_DISTANCE0)
 * and a new plane). */
static const char *fill_vs_src =
    "layout(location = 0) in vec3 a_pos;\n"
    "out float gl_ClipDistance[8];\n"
    "void main() {\n"
    "    gl_Position = vec4(a_pos, 1.0);\n"
    "    for (int i = 0; i < 8; i++) gl_ClipDistance[i] = 1.0;\n"
    "}\n";
static const char *fill_fs_src =
    "uniform vec3 u_color;\n"
    "out vec4 o_color;\n"
    "void main() { o_color = vec4(u_color, 1.0); }\n";

static limen_status build_program(limen_renderer *r)
{
    r->fill_prog = limen__gl_link(r, "#version 330 core\n", fill_vs_src, fill_fs_src);
    if (!r->fill_prog)
        return LIMEN_ERR_GL;
    r->u_fill_color = GL(GetUniformLocation)(r->fill_prog, "u_color");
    return LIMEN_OK;
}

/* The unit shapes' triangles (limen_unit_geometry), every level of each, in one vertex and
 * one index buffer: r->units[shape][level] is where a level's indices lie. */
static limen_status upload_units(limen_renderer *r)
{
    const limen_mesh_geometry *g[LIMEN_UNIT_COUNT] = { NULL };
    size_t nv = 0, ni = 0;
    for (int s = 1; s < LIMEN_UNIT_COUNT; s++) {
        if (!(g[s] = limen_unit_geometry((limen_unit_shape)s)))
            return limen__rfail(r, LIMEN_ERR_NOMEM, "out of memory building the unit shapes");
        r->unit_levels[s] = g[s]->lod_count < LIMEN__UNIT_SLOTS ? g[s]->lod_count
                                                                : LIMEN__UNIT_SLOTS;
        nv += (size_t)g[s]->vertex_count;
        for (int k = 0; k < r->unit_levels[s]; k++)
            ni += 3 * (size_t)g[s]->lods[k].triangle_count;
    }
    limen__vertex *verts = malloc(sizeof *verts * nv);
    uint32_t *idx = malloc(sizeof *idx * ni);
    if (!verts || !idx) {
        free(verts), free(idx);
        return limen__rfail(r, LIMEN_ERR_NOMEM, "out of memory building the unit shapes");
    }
    nv = ni = 0;
    for (int s = 1; s < LIMEN_UNIT_COUNT; s++) {
        for (int i = 0; i < g[s]->vertex_count; i++) {
            memcpy(verts[nv + (size_t)i].pos, g[s]->positions + 3 * i, sizeof verts->pos);
            memcpy(verts[nv + (size_t)i].nrm, g[s]->normals + 3 * i, sizeof verts->nrm);
        }
        for (int k = 0; k < r->unit_levels[s]; k++) {
            uint32_t n = 3 * (uint32_t)g[s]->lods[k].triangle_count;
            r->units[s][k] = (limen__range){ (uint32_t)ni, n };
            for (uint32_t i = 0; i < n; i++)
                idx[ni++] = (uint32_t)nv + g[s]->lods[k].indices[i];
        }
        nv += (size_t)g[s]->vertex_count;
    }
    GL(GenVertexArrays)(1, &r->vao);
    GL(BindVertexArray)(r->vao);
    GL(GenBuffers)(1, &r->vbo);
    GL(BindBuffer)(GL_ARRAY_BUFFER, r->vbo);
    GL(BufferData)(GL_ARRAY_BUFFER, (GLsizeiptr)(sizeof *verts * nv), verts, GL_STATIC_DRAW);
    GL(GenBuffers)(1, &r->ibo);
    GL(BindBuffer)(GL_ELEMENT_ARRAY_BUFFER, r->ibo);
    GL(BufferData)(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(sizeof *idx * ni), idx, GL_STATIC_DRAW);
    GL(EnableVertexAttribArray)(0);
    GL(VertexAttribPointer)(0, 3, GL_FLOAT, GL_FALSE, sizeof(limen__vertex), (void *)0);
    GL(EnableVertexAttribArray)(1);
    GL(VertexAttribPointer)(1, 3, GL_FLOAT, GL_FALSE, sizeof(limen__vertex),
                            (void *)offsetof(limen__vertex, nrm));
    free(verts), free(idx);
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
    if (r->host)
        return LIMEN_OK;    /* the frame is the game's framebuffer */
    GLenum depth_fmt = limen__depth_format(r);
    r->color_rb = renderbuffer(r, GL_RGBA8, r->msaa);
    r->depth_rb = renderbuffer(r, depth_fmt, r->msaa);
    GL(GenFramebuffers)(1, &r->fbo);
    GL(BindFramebuffer)(GL_FRAMEBUFFER, r->fbo);
    GL(FramebufferRenderbuffer)(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                r->color_rb);
    GL(FramebufferRenderbuffer)(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                                r->depth_rb);
    if (GL(CheckFramebufferStatus)(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
        return limen__rfail(r, LIMEN_ERR_UNSUPPORTED, "framebuffer %dx%d (msaa %d) is incomplete",
                     r->width, r->height, r->msaa);
    if (r->msaa > 1) {
        r->resolve_rb = renderbuffer(r, GL_RGBA8, 0);
        GL(GenFramebuffers)(1, &r->resolve_fbo);
        GL(BindFramebuffer)(GL_FRAMEBUFFER, r->resolve_fbo);
        GL(FramebufferRenderbuffer)(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER,
                                    r->resolve_rb);
        if (GL(CheckFramebufferStatus)(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
            return limen__rfail(r, LIMEN_ERR_UNSUPPORTED, "resolve framebuffer is incomplete");
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

static limen_status setup_gl(limen_renderer *r);

/* Runs the GL work of a public call between the context's enter and leave. */
static limen_status enter(limen_renderer *r)
{
    char err[sizeof r->err];
    if (r->ops->enter(r->ctx, &r->gl, err, sizeof err))
        return limen__rfail(r, LIMEN_ERR_GL, "%s", err);
    return LIMEN_OK;
}

static void leave(limen_renderer *r)
{
    r->ops->leave(r->ctx, &r->gl);
}

/* The host's context must be OpenGL 3.3 or later. Read from GL_VERSION, the one query every
 * version answers without an error (GL_MAJOR_VERSION is 3.0's), before limen saves any
 * state or looks for entry points an older context lacks. No context current: LIMEN_OK,
 * and enter says so. */
static limen_status check_host_version(limen_renderer *r)
{
    if (!r->gl.GetString)
        return LIMEN_OK;
    const char *v = (const char *)r->gl.GetString(GL_VERSION);
    if (!v)
        return LIMEN_OK;
    int major = 0, minor = 0;
    if (sscanf(v, "%d.%d", &major, &minor) != 2)
        return limen__rfail(r, LIMEN_ERR_UNSUPPORTED, "host: limen needs OpenGL 3.3 core, "
                            "this context is '%.64s'", v);
    if (major * 10 + minor < 33)
        return limen__rfail(r, LIMEN_ERR_UNSUPPORTED, "host: limen needs OpenGL 3.3 core, "
                            "this context is %d.%d", major, minor);
    return LIMEN_OK;
}

static limen_status setup(limen_renderer *r, const limen_renderer_desc *d)
{
    static const limen__ctx_ops *const backends[] = { &limen__ctx_osmesa, &limen__ctx_egl,
                                                      &limen__ctx_host };
    if ((unsigned)d->backend > LIMEN_BACKEND_HOST)
        return limen__rfail(r, LIMEN_ERR_ARG, "unknown backend %d", (int)d->backend);
    r->ops = backends[d->backend];
    r->host = d->backend == LIMEN_BACKEND_HOST;
    if ((unsigned)d->depth_range > LIMEN_DEPTH_ZO_REVERSED)
        return limen__rfail(r, LIMEN_ERR_ARG, "unknown depth range %d", (int)d->depth_range);
    const limen_renderer_desc full = limen_renderer_desc_defaults(d);
    r->width = full.width;
    r->height = full.height;
    if (d->width < 0 || d->height < 0 || r->width > 16384 || r->height > 16384)
        return limen__rfail(r, LIMEN_ERR_ARG, "image size %dx%d out of range (1 to 16384)", d->width,
                     d->height);
    if (d->msaa < 0 || d->msaa > 64)
        return limen__rfail(r, LIMEN_ERR_ARG, "msaa %d out of range (0 to 64)", d->msaa);
    if (r->host && d->msaa > 1)
        return limen__rfail(r, LIMEN_ERR_ARG, "host: msaa must be 0 (a multisampled host "
                                              "framebuffer is drawn multisampled as it is)");
    if (r->host) {
        r->fbo = d->framebuffer;
        r->origin[0] = d->x;
        r->origin[1] = d->y;
    }
    r->msaa = d->msaa > 1 ? d->msaa : 0;
    r->range = d->depth_range;
    if (d->depth_bits != 0 && d->depth_bits != 24 && d->depth_bits != 32)
        return limen__rfail(r, LIMEN_ERR_ARG, "depth bits must be 24 or 32 (got %d)",
                            d->depth_bits);
    r->depth_bits = full.depth_bits;

    r->ctx = r->ops->create(d, r->err, sizeof r->err);
    if (!r->ctx)
        return LIMEN_ERR_GL;
    const char *missing = limen__gl_load(&r->gl, r->ops->getproc, r->ctx);
    if (r->host) {
        limen_status vst = check_host_version(r);
        if (vst)
            return vst;
    }
    if (missing)
        return limen__rfail(r, LIMEN_ERR_UNSUPPORTED, "%s: OpenGL entry point %s missing",
                     r->ops->name, missing);
    r->loaded = true;
    limen_status st = enter(r);
    if (st)
        return st;
    st = setup_gl(r);
    leave(r);
    if (st)
        return st;
    r->ready = true;
    return LIMEN_OK;
}

static limen_status setup_gl(limen_renderer *r)
{
    snprintf(r->info, sizeof r->info, "%s: %s, OpenGL %s", r->ops->name,
             (const char *)GL(GetString)(GL_RENDERER), (const char *)GL(GetString)(GL_VERSION));
    if (r->msaa) {
        GLint max_samples = 0;
        GL(GetIntegerv)(GL_MAX_SAMPLES, &max_samples);
        if (r->msaa > max_samples)
            return limen__rfail(r, LIMEN_ERR_UNSUPPORTED, "msaa %d exceeds this context's %d",
                         r->msaa, max_samples);
    }
    if (r->range != LIMEN_DEPTH_NO && !r->gl.ClipControl)
        return limen__rfail(r, LIMEN_ERR_UNSUPPORTED, "depth range zo needs glClipControl (GL 4.5)");
    r->has_fragment_stats = has_gl_ext(r, "GL_ARB_pipeline_statistics_query");

    limen_status st = build_program(r);
    if (!st)
        st = upload_units(r);
    if (!st)
        st = build_targets(r);
    if (st)
        return st;
    if (limen_plan_create(&r->plan) || limen_drawables_create(&r->draw) ||
        limen_drawlist_create(&r->list))
        return limen__rfail(r, LIMEN_ERR_NOMEM, "out of memory");
    GL(GenQueries)(1, &r->q_fragments);
    r->rgba = malloc((size_t)r->width * (size_t)r->height * 4);
    if (!r->rgba)
        return limen__rfail(r, LIMEN_ERR_NOMEM, "out of memory for a %dx%d image", r->width,
                     r->height);
    GLenum e = GL(GetError)();
    if (e != GL_NO_ERROR)
        return limen__rfail(r, LIMEN_ERR_GL, "OpenGL error 0x%x while setting up", e);
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
    /* enter refuses a host context other than the renderer's: then limen touches no GL and
     * its objects stay in its own context, which frees them when it is destroyed */
    if (r->ctx && r->loaded && (r->fill_prog || r->host) && !enter(r)) {
        limen__variants_free(r);
        GL(DeleteProgram)(r->fill_prog);
        GL(DeleteBuffers)(1, &r->vbo);
        GL(DeleteBuffers)(1, &r->ibo);
        GL(DeleteVertexArrays)(1, &r->vao);
        if (r->poly_vao) {
            GL(DeleteVertexArrays)(1, &r->poly_vao);
            GL(DeleteBuffers)(1, &r->poly_vbo);
        }
        if (!r->host) {
            GL(DeleteFramebuffers)(1, &r->fbo);
            GL(DeleteRenderbuffers)(1, &r->color_rb);
            GL(DeleteRenderbuffers)(1, &r->depth_rb);
        }
        if (r->resolve_fbo) {
            GL(DeleteFramebuffers)(1, &r->resolve_fbo);
            GL(DeleteRenderbuffers)(1, &r->resolve_rb);
        }
        if (r->q_cap)
            GL(DeleteQueries)(r->q_cap, r->q_pool);
        GL(DeleteQueries)(1, &r->q_fragments);
        limen__targets_free(r);
        limen__gpu_assets_free(r);
        if (r->inst_vbo)
            GL(DeleteBuffers)(1, &r->inst_vbo);
        if (r->prev_fbo) {
            GL(DeleteFramebuffers)(1, &r->prev_fbo);
            GL(DeleteTextures)(1, &r->prev_tex);
        }
        if (r->ops->release)
            r->ops->release(r->ctx, &r->gl);
        leave(r);
    }
    limen_plan_destroy(r->plan);
    limen_drawables_destroy(r->draw);
    limen_drawlist_destroy(r->list);
    free(r->q_pool);
    free(r->inst);
    free(r->poly);
    if (r->ctx)
        r->ops->destroy(r->ctx);
    free(r->assets);
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

void limen_renderer_get_size(const limen_renderer *r, int *width, int *height)
{
    if (width)
        *width = r ? r->width : 0;
    if (height)
        *height = r ? r->height : 0;
}

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

/* The bits of one of the game's framebuffer attachments (0 where there is none). */
static GLint host_bits(limen_renderer *r, GLenum fbo_att, GLenum default_att, GLenum pname)
{
    GLenum att = r->fbo ? fbo_att : default_att;
    GLint type = GL_NONE, bits = 0;
    GL(GetFramebufferAttachmentParameteriv)(GL_DRAW_FRAMEBUFFER, att,
                                            GL_FRAMEBUFFER_ATTACHMENT_OBJECT_TYPE, &type);
    if (type != GL_NONE)
        GL(GetFramebufferAttachmentParameteriv)(GL_DRAW_FRAMEBUFFER, att, pname, &bits);
    return bits;
}

/* The game's framebuffer must be complete and have what the method needs. */
static limen_status check_host_target(limen_renderer *r)
{
    GLenum status = GL(CheckFramebufferStatus)(GL_DRAW_FRAMEBUFFER);
    if (status != GL_FRAMEBUFFER_COMPLETE)
        return limen__rfail(r, LIMEN_ERR_GL, "host: framebuffer %u is incomplete (0x%x)",
                            r->fbo, status);
    if (host_bits(r, GL_DEPTH_ATTACHMENT, GL_DEPTH, GL_FRAMEBUFFER_ATTACHMENT_DEPTH_SIZE) < 16)
        return limen__rfail(r, LIMEN_ERR_UNSUPPORTED, "host: framebuffer %u has no depth buffer "
                            "(limen needs one; with SDL: SDL_GL_DEPTH_SIZE 24)", r->fbo);
    if (r->opts.method == LIMEN_METHOD_STENCIL &&
        host_bits(r, GL_STENCIL_ATTACHMENT, GL_STENCIL,
                  GL_FRAMEBUFFER_ATTACHMENT_STENCIL_SIZE) < 8)
        return limen__rfail(r, LIMEN_ERR_UNSUPPORTED, "host: framebuffer %u has no 8-bit stencil "
                            "buffer, which the stencil method needs (with SDL: "
                            "SDL_GL_STENCIL_SIZE 8; or use the texture method)", r->fbo);
    return LIMEN_OK;
}

static limen_status begin_frame(limen_renderer *r)
{
    GL(BindFramebuffer)(GL_FRAMEBUFFER, r->fbo);
    if (r->host) {
        limen_status st = check_host_target(r);
        if (st)
            return st;
    }
    GL(Viewport)(r->origin[0], r->origin[1], r->width, r->height);
    if (r->gl.ClipControl)
        GL(ClipControl)(GL_LOWER_LEFT,
                        r->range == LIMEN_DEPTH_NO ? GL_NEGATIVE_ONE_TO_ONE : GL_ZERO_TO_ONE);
    /* the list's first command clears the frame (scissored to it: a game's framebuffer may
     * hold more) and sets the rest */
    GL(Disable)(GL_BLEND);
    GL(Enable)(GL_DEPTH_TEST);
    GL(CullFace)(GL_BACK);
    GL(FrontFace)(GL_CCW);
    if (r->msaa)
        GL(Enable)(GL_MULTISAMPLE);
    /* every sample shaded at its own position (GL 4.0), not once at the pixel's centre: a
     * checker's or a texture's edges inside a surface are then averaged like the shapes'
     * edges, as the tracer's samples at the same positions average them
     * (limen_trace_desc.samples) */
    if (r->msaa && r->gl.MinSampleShading) {
        GL(Enable)(GL_SAMPLE_SHADING);
        GL(MinSampleShading)(1.0f);
    }
    return LIMEN_OK;
}

void limen__samples_begin(limen_renderer *r)
{
    if (!r->counting)
        return;     /* no stats asked for: nothing to count */
    if (r->q_used == r->q_cap) {
        int old = r->q_cap;
        if (!limen__gl_grow((void **)&r->q_pool, &r->q_cap, r->q_used + 1, sizeof *r->q_pool))
            return;     /* this pass goes uncounted; the frame still renders */
        GL(GenQueries)(r->q_cap - old, r->q_pool + old);
    }
    GL(BeginQuery)(GL_SAMPLES_PASSED, r->q_pool[r->q_used++]);
    r->q_active = true;
}

void limen__samples_end(limen_renderer *r)
{
    if (r->q_active)
        GL(EndQuery)(GL_SAMPLES_PASSED);
    r->q_active = false;
}

/* Copies the finished frame into prev_tex for the next frame's LIMEN_FILL_PREVIOUS. */
static void keep_previous(limen_renderer *r)
{
    if (!r->prev_fbo) {
        r->prev_tex = limen__color_texture(r, r->width, r->height);
        GL(GenFramebuffers)(1, &r->prev_fbo);
        GL(BindFramebuffer)(GL_FRAMEBUFFER, r->prev_fbo);
        GL(FramebufferTexture2D)(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D,
                                 r->prev_tex, 0);
    }
    GL(BindFramebuffer)(GL_READ_FRAMEBUFFER, r->msaa ? r->resolve_fbo : r->fbo);
    GL(BindFramebuffer)(GL_DRAW_FRAMEBUFFER, r->prev_fbo);
    const int *o = r->origin;
    GL(BlitFramebuffer)(o[0], o[1], o[0] + r->width, o[1] + r->height, 0, 0, r->width,
                        r->height, GL_COLOR_BUFFER_BIT, GL_NEAREST);
    GL(BindFramebuffer)(GL_FRAMEBUFFER, r->fbo);
    r->have_prev = true;
}

static limen_status check_opts(limen_renderer *r, const limen_render_opts *o)
{
    if ((unsigned)o->method > LIMEN_METHOD_NAIVE)
        return limen__rfail(r, LIMEN_ERR_ARG, "unknown method %d", (int)o->method);
    if ((unsigned)o->fill > LIMEN_FILL_PREVIOUS)
        return limen__rfail(r, LIMEN_ERR_ARG, "unknown fill %d", (int)o->fill);
    if (!(o->texture_scale > 0 && o->texture_scale <= 1))
        return limen__rfail(r, LIMEN_ERR_ARG, "texture scale must be in (0, 1] (got %g)",
                            o->texture_scale);
    return LIMEN_OK;
}

static limen_status frame(limen_renderer *r, limen_scene *s, limen_frame_stats *stats);

limen_status limen_render_frame(limen_renderer *r, limen_scene *s, const limen_render_opts *opts,
                                limen_frame_stats *stats)
{
    if (!r || !s)
        return LIMEN_ERR_ARG;
    if (!r->ready)
        return limen__rfail(r, LIMEN_ERR_GL, "renderer was not set up: %s", r->err);
    r->opts = opts ? *opts : (limen_render_opts){ 0 };
    if (r->opts.texture_scale == 0 || r->opts.method == LIMEN_METHOD_NAIVE)
        r->opts.texture_scale = 1.0f;
    limen_status st = check_opts(r, &r->opts);
    if (st)
        return st;
    if ((st = enter(r)))
        return st;
    st = frame(r, s, stats);
    leave(r);
    if (!st)
        r->err[0] = '\0';     /* a successful call leaves no old failure behind */
    return st;
}

static limen_status frame(limen_renderer *r, limen_scene *s, limen_frame_stats *stats)
{
    double t0 = now_ms();

    limen_plan_desc pd = { .width = r->width, .height = r->height, .range = r->range,
                           .limits = r->opts.limits,
                           .cull = r->opts.method == LIMEN_METHOD_NAIVE ? LIMEN_CULL_FRUSTUM
                                                                        : LIMEN_CULL_SURFACE };
    pd.multisample = r->msaa > 1;   /* its samples lie off the pixels' centres */
    limen_status st = limen_plan_build(r->plan, s, &pd);
    if (!st)
        st = limen_drawables_build(r->draw, s);
    if (st)
        return limen__rfail(r, st, "%s", limen_scene_error(s));
    limen_drawables_environment(r->draw, r->background, NULL);   /* ambient: the list's */
    limen_drawlist_desc dd = { .width = r->width, .height = r->height,
                               .method = r->opts.method, .fill = r->opts.fill,
                               .texture_scale = r->opts.texture_scale, .msaa = r->msaa,
                               .range = r->range, .limits = r->opts.limits,
                               .have_previous = r->have_prev };
    if ((st = limen_drawlist_build(r->list, r->plan, r->draw, &dd)))
        return limen__rfail(r, st, "%s", limen_drawlist_error(r->list));
    if ((st = begin_frame(r)))
        return st;
    r->q_used = 0;
    r->counting = stats != NULL;
    r->bound_prog = 0;
    r->draw_status = LIMEN_OK;
    r->draw_calls = 0;
    r->triangles = 0;
    if (r->has_fragment_stats && r->counting)
        GL(BeginQuery)(GL_FRAGMENT_SHADER_INVOCATIONS_ARB, r->q_fragments);
    st = limen__execute(r, r->list);
    if (r->has_fragment_stats && r->counting)
        GL(EndQuery)(GL_FRAGMENT_SHADER_INVOCATIONS_ARB);
    if (!st)
        st = r->draw_status;    /* something could not be drawn: the message is set */
    if (st)
        return st;
    if (r->msaa) {
        GL(BindFramebuffer)(GL_READ_FRAMEBUFFER, r->fbo);
        GL(BindFramebuffer)(GL_DRAW_FRAMEBUFFER, r->resolve_fbo);
        GL(BlitFramebuffer)(0, 0, r->width, r->height, 0, 0, r->width, r->height,
                            GL_COLOR_BUFFER_BIT, GL_NEAREST);
    }
    if (r->opts.fill == LIMEN_FILL_PREVIOUS)
        keep_previous(r);
    /* stats.ms is the time to the frame's end; without stats the frame is only submitted,
     * so that a game's next frame is prepared while llvmpipe's threads shade this one (a
     * read-back or a swap waits for it) */
    if (stats)
        GL(Finish)();
    else
        GL(Flush)();
    double t1 = now_ms();
    limen__gpu_assets_sweep(r);

    GLenum e = GL(GetError)();
    if (e != GL_NO_ERROR)
        return limen__rfail(r, LIMEN_ERR_GL, "OpenGL error 0x%x while rendering", e);
    r->have_frame = true;
    if (stats) {
        GLuint64 samples = 0, frags = 0;
        for (int i = 0; i < r->q_used; i++) {
            GLuint64 n = 0;
            GL(GetQueryObjectui64v)(r->q_pool[i], GL_QUERY_RESULT, &n);
            samples += n;
        }
        if (r->has_fragment_stats)
            GL(GetQueryObjectui64v)(r->q_fragments, GL_QUERY_RESULT, &frags);
        stats->ms = t1 - t0;
        stats->views = limen_plan_count(r->plan);
        stats->truncated = limen_plan_truncated(r->plan);
        stats->samples = samples;
        stats->fragments = frags;
        stats->pixels = (uint64_t)r->width * (uint64_t)r->height;
        stats->draw_calls = r->draw_calls;
        stats->triangles = r->triangles;
    }
    return LIMEN_OK;
}

const limen_plan *limen_renderer_plan(const limen_renderer *r)
{
    return r ? r->plan : NULL;
}

limen_status limen_renderer_read_rgb(limen_renderer *r, unsigned char *rgb)
{
    if (!r || !rgb)
        return LIMEN_ERR_ARG;
    if (!r->have_frame)
        return limen__rfail(r, LIMEN_ERR_ARG, "no frame rendered yet");
    limen_status st = enter(r);
    if (st)
        return st;
    GL(BindFramebuffer)(GL_READ_FRAMEBUFFER, r->msaa ? r->resolve_fbo : r->fbo);
    GLint samples = 0;
    if (r->host)
        GL(GetIntegerv)(GL_SAMPLE_BUFFERS, &samples);
    if (samples) {
        leave(r);
        return limen__rfail(r, LIMEN_ERR_UNSUPPORTED, "host: framebuffer %u is multisampled; "
                            "resolve it and read it yourself", r->fbo);
    }
    GL(PixelStorei)(GL_PACK_ALIGNMENT, 1);
    GL(PixelStorei)(GL_PACK_ROW_LENGTH, 0);
    GL(PixelStorei)(GL_PACK_SKIP_ROWS, 0);
    GL(PixelStorei)(GL_PACK_SKIP_PIXELS, 0);
    GL(ReadPixels)(r->origin[0], r->origin[1], r->width, r->height, GL_RGBA, GL_UNSIGNED_BYTE,
                   r->rgba);
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
    leave(r);
    if (e != GL_NO_ERROR)
        return limen__rfail(r, LIMEN_ERR_GL, "OpenGL error 0x%x reading pixels", e);
    r->err[0] = '\0';
    return LIMEN_OK;
}

limen_status limen_renderer_write_png(limen_renderer *r, const char *path)
{
    if (!r || !path)
        return LIMEN_ERR_ARG;
    unsigned char *rgb = malloc((size_t)r->width * (size_t)r->height * 3);
    if (!rgb)
        return limen__rfail(r, LIMEN_ERR_NOMEM, "out of memory");
    limen_status st = limen_renderer_read_rgb(r, rgb);
    if (!st) {
        st = limen_write_png(path, r->width, r->height, rgb);
        if (st)
            limen__rfail(r, st, "cannot write '%s'", path);
    }
    free(rgb);
    return st;
}

limen_status limen_renderer_set_viewport(limen_renderer *r, unsigned framebuffer, int x, int y,
                                         int width, int height)
{
    if (!r)
        return LIMEN_ERR_ARG;
    if (!r->host)
        return limen__rfail(r, LIMEN_ERR_UNSUPPORTED, "set_viewport: only for the host backend");
    if (width < 1 || height < 1 || width > 16384 || height > 16384 || x < 0 || y < 0)
        return limen__rfail(r, LIMEN_ERR_ARG, "viewport %d,%d %dx%d out of range", x, y, width,
                            height);
    if (!r->ready)
        return limen__rfail(r, LIMEN_ERR_GL, "renderer was not set up: %s", r->err);
    if (width != r->width || height != r->height) {
        unsigned char *rgba = realloc(r->rgba, (size_t)width * (size_t)height * 4);
        if (!rgba)
            return limen__rfail(r, LIMEN_ERR_NOMEM, "out of memory for a %dx%d image", width,
                                height);
        r->rgba = rgba;
        limen_status st = enter(r);
        if (st)
            return st;
        /* offscreen targets follow the frame's size */
        limen__targets_free(r);
        if (r->prev_fbo) {
            GL(DeleteFramebuffers)(1, &r->prev_fbo);
            GL(DeleteTextures)(1, &r->prev_tex);
            r->prev_fbo = r->prev_tex = 0;
        }
        leave(r);
        r->have_prev = false;
        r->have_frame = false;
    }
    r->fbo = framebuffer;
    r->origin[0] = x;
    r->origin[1] = y;
    r->width = width;
    r->height = height;
    r->err[0] = '\0';
    return LIMEN_OK;
}
