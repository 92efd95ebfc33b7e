/* ctx_host.c - the game's own context (LIMEN_BACKEND_HOST). limen makes nothing current:
 * entering a call saves the GL state that limen's drawing changes and sets what that
 * drawing relies on; leaving puts the saved state back, so that the game's next draw sees
 * its own state. The list here is the one limen.h promises. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "limen.h"
#include "gl/glapi.h"

/* Capabilities limen either sets during a frame or must not inherit from the game. */
static const GLenum caps[] = {
    GL_DEPTH_TEST, GL_STENCIL_TEST, GL_SCISSOR_TEST, GL_BLEND, GL_CULL_FACE, GL_DEPTH_CLAMP,
    GL_CLIP_DISTANCE0, GL_CLIP_DISTANCE1, GL_CLIP_DISTANCE2, GL_CLIP_DISTANCE3,
    GL_CLIP_DISTANCE4, GL_CLIP_DISTANCE5, GL_CLIP_DISTANCE6, GL_CLIP_DISTANCE7,
    GL_MULTISAMPLE, GL_FRAMEBUFFER_SRGB, GL_POLYGON_OFFSET_FILL, GL_COLOR_LOGIC_OP,
    GL_SAMPLE_ALPHA_TO_COVERAGE, GL_SAMPLE_COVERAGE, GL_SAMPLE_MASK, GL_RASTERIZER_DISCARD,
    GL_PRIMITIVE_RESTART,
};
#define NCAPS (sizeof caps / sizeof caps[0])
/* the first of caps that limen leaves as the game had them during a frame */
#define KEEP_FROM 14

/* Integer state: read with glGetIntegerv, put back by restore(). */
enum {
    I_PROGRAM, I_VAO, I_ARRAY_BUFFER, I_DRAW_FB, I_READ_FB, I_RENDERBUFFER, I_ACTIVE_TEXTURE,
    I_TEXTURE0, I_SAMPLER0, I_TEXTURE1, I_SAMPLER1, I_TEXTURE2, I_SAMPLER2, I_PACK_BUFFER, I_UNPACK_BUFFER,
    I_PACK_ALIGNMENT, I_PACK_ROW_LENGTH, I_PACK_SKIP_ROWS, I_PACK_SKIP_PIXELS,
    I_UNPACK_ALIGNMENT, I_UNPACK_ROW_LENGTH, I_UNPACK_SKIP_ROWS, I_UNPACK_SKIP_PIXELS,
    I_UNPACK_IMAGE_HEIGHT, I_DEPTH_FUNC, I_CULL_MODE,
    I_FRONT_FACE, I_STENCIL_CLEAR, I_BLEND_SRC, I_BLEND_DST, I_CLIP_ORIGIN, I_CLIP_DEPTH, I_COUNT
};

/* GL_STENCIL_FUNC, _REF, _VALUE_MASK, _FAIL, _PASS_DEPTH_FAIL, _PASS_DEPTH_PASS, _WRITEMASK
 * for one face */
typedef struct stencil_face {
    GLint func, ref, mask, fail, zfail, zpass, write;
} stencil_face;

typedef struct saved {
    GLint i[I_COUNT];
    GLint viewport[4], scissor[4], polygon_mode[2];
    GLboolean caps[NCAPS], depth_mask, color_mask[4];
    GLfloat color_clear[4];
    GLdouble depth_clear, depth_range[2];
    stencil_face front, back;
} saved;

struct limen__ctx {
    limen_gl_loader load;
    saved st;
    int depth;                  /* enter/leave nesting: only the outermost saves */
    /* A fence made in the context the renderer was created in. GL names are per context
     * (another context has its own program 1), but a sync object is a pointer that
     * glIsSync finds only in the context (and share group) that made it, without a flush:
     * it tells, on every call, whether the current context is the renderer's. */
    GLsync mark;
};

static limen__ctx *host_create(const limen_renderer_desc *d, char *err, size_t errsize)
{
    if (!d->gl_loader) {
        snprintf(err, errsize, "host: no OpenGL function loader given (gl_loader, e.g. "
                               "SDL_GL_GetProcAddress)");
        return NULL;
    }
    limen__ctx *c = calloc(1, sizeof *c);
    if (!c) {
        snprintf(err, errsize, "host: out of memory");
        return NULL;
    }
    c->load = d->gl_loader;
    return c;
}

static limen__glproc host_getproc(limen__ctx *c, const char *name)
{
    limen__glproc f;
    void *p = c->load(name);
    memcpy(&f, &p, sizeof f);   /* a loader's object pointer is a function's address */
    return f;
}

static void get_face(const limen__gl *gl, bool back, stencil_face *f)
{
    gl->GetIntegerv(back ? GL_STENCIL_BACK_FUNC : GL_STENCIL_FUNC, &f->func);
    gl->GetIntegerv(back ? GL_STENCIL_BACK_REF : GL_STENCIL_REF, &f->ref);
    gl->GetIntegerv(back ? GL_STENCIL_BACK_VALUE_MASK : GL_STENCIL_VALUE_MASK, &f->mask);
    gl->GetIntegerv(back ? GL_STENCIL_BACK_FAIL : GL_STENCIL_FAIL, &f->fail);
    gl->GetIntegerv(back ? GL_STENCIL_BACK_PASS_DEPTH_FAIL : GL_STENCIL_PASS_DEPTH_FAIL,
                    &f->zfail);
    gl->GetIntegerv(back ? GL_STENCIL_BACK_PASS_DEPTH_PASS : GL_STENCIL_PASS_DEPTH_PASS,
                    &f->zpass);
    gl->GetIntegerv(back ? GL_STENCIL_BACK_WRITEMASK : GL_STENCIL_WRITEMASK, &f->write);
}

static void set_face(const limen__gl *gl, GLenum face, const stencil_face *f)
{
    gl->StencilFuncSeparate(face, (GLenum)f->func, f->ref, (GLuint)f->mask);
    gl->StencilOpSeparate(face, (GLenum)f->fail, (GLenum)f->zfail, (GLenum)f->zpass);
    gl->StencilMaskSeparate(face, (GLuint)f->write);
}

static void save(const limen__gl *gl, saved *sv)
{
    static const GLenum ints[I_COUNT] = {
        [I_PROGRAM] = GL_CURRENT_PROGRAM, [I_VAO] = GL_VERTEX_ARRAY_BINDING,
        [I_ARRAY_BUFFER] = GL_ARRAY_BUFFER_BINDING, [I_DRAW_FB] = GL_DRAW_FRAMEBUFFER_BINDING,
        [I_READ_FB] = GL_READ_FRAMEBUFFER_BINDING, [I_RENDERBUFFER] = GL_RENDERBUFFER_BINDING,
        [I_ACTIVE_TEXTURE] = GL_ACTIVE_TEXTURE, [I_PACK_BUFFER] = GL_PIXEL_PACK_BUFFER_BINDING,
        [I_UNPACK_BUFFER] = GL_PIXEL_UNPACK_BUFFER_BINDING,
        [I_PACK_ALIGNMENT] = GL_PACK_ALIGNMENT, [I_PACK_ROW_LENGTH] = GL_PACK_ROW_LENGTH,
        [I_PACK_SKIP_ROWS] = GL_PACK_SKIP_ROWS, [I_PACK_SKIP_PIXELS] = GL_PACK_SKIP_PIXELS,
        [I_UNPACK_ALIGNMENT] = GL_UNPACK_ALIGNMENT, [I_UNPACK_ROW_LENGTH] = GL_UNPACK_ROW_LENGTH,
        [I_UNPACK_SKIP_ROWS] = GL_UNPACK_SKIP_ROWS,
        [I_UNPACK_SKIP_PIXELS] = GL_UNPACK_SKIP_PIXELS,
        [I_UNPACK_IMAGE_HEIGHT] = GL_UNPACK_IMAGE_HEIGHT,
        [I_DEPTH_FUNC] = GL_DEPTH_FUNC, [I_CULL_MODE] = GL_CULL_FACE_MODE,
        [I_FRONT_FACE] = GL_FRONT_FACE, [I_STENCIL_CLEAR] = GL_STENCIL_CLEAR_VALUE,
        [I_BLEND_SRC] = GL_BLEND_SRC_RGB, [I_BLEND_DST] = GL_BLEND_DST_RGB,
    };
    for (int k = 0; k < I_COUNT; k++)
        if (ints[k])
            gl->GetIntegerv(ints[k], &sv->i[k]);
    if (gl->ClipControl) {
        gl->GetIntegerv(GL_CLIP_ORIGIN, &sv->i[I_CLIP_ORIGIN]);
        gl->GetIntegerv(GL_CLIP_DEPTH_MODE, &sv->i[I_CLIP_DEPTH]);
    }
    /* units 0 (views' images), 1 (albedo textures) and 2 (emissive textures) are the ones
     * limen samples from */
    gl->ActiveTexture(GL_TEXTURE2);
    gl->GetIntegerv(GL_TEXTURE_BINDING_2D, &sv->i[I_TEXTURE2]);
    gl->GetIntegerv(GL_SAMPLER_BINDING, &sv->i[I_SAMPLER2]);
    gl->ActiveTexture(GL_TEXTURE1);
    gl->GetIntegerv(GL_TEXTURE_BINDING_2D, &sv->i[I_TEXTURE1]);
    gl->GetIntegerv(GL_SAMPLER_BINDING, &sv->i[I_SAMPLER1]);
    gl->ActiveTexture(GL_TEXTURE0);
    gl->GetIntegerv(GL_TEXTURE_BINDING_2D, &sv->i[I_TEXTURE0]);
    gl->GetIntegerv(GL_SAMPLER_BINDING, &sv->i[I_SAMPLER0]);
    gl->GetIntegerv(GL_VIEWPORT, sv->viewport);
    gl->GetIntegerv(GL_SCISSOR_BOX, sv->scissor);
    sv->polygon_mode[0] = sv->polygon_mode[1] = GL_FILL;
    gl->GetIntegerv(GL_POLYGON_MODE, sv->polygon_mode);
    for (size_t k = 0; k < NCAPS; k++)
        sv->caps[k] = gl->IsEnabled(caps[k]);
    gl->GetBooleanv(GL_DEPTH_WRITEMASK, &sv->depth_mask);
    gl->GetBooleanv(GL_COLOR_WRITEMASK, sv->color_mask);
    gl->GetFloatv(GL_COLOR_CLEAR_VALUE, sv->color_clear);
    gl->GetDoublev(GL_DEPTH_CLEAR_VALUE, &sv->depth_clear);
    gl->GetDoublev(GL_DEPTH_RANGE, sv->depth_range);
    get_face(gl, false, &sv->front);
    get_face(gl, true, &sv->back);
}

/* What limen's drawing relies on and a game may have set otherwise. */
static void neutral(const limen__gl *gl)
{
    for (size_t k = KEEP_FROM; k < NCAPS; k++)
        if (caps[k] != GL_MULTISAMPLE)
            gl->Disable(caps[k]);
    for (int k = 2; k < 8; k++)
        gl->Disable(GL_CLIP_DISTANCE0 + (GLenum)k);
    gl->Disable(GL_BLEND);
    gl->PolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    gl->DepthRange(0.0, 1.0);
    gl->BindSampler(0, 0);
    gl->BindSampler(1, 0);
    gl->BindSampler(2, 0);
    gl->BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    gl->BindBuffer(GL_PIXEL_UNPACK_BUFFER, 0);
    /* textures are uploaded as tightly packed rows */
    gl->PixelStorei(GL_UNPACK_ALIGNMENT, 1);
    gl->PixelStorei(GL_UNPACK_ROW_LENGTH, 0);
    gl->PixelStorei(GL_UNPACK_SKIP_ROWS, 0);
    gl->PixelStorei(GL_UNPACK_SKIP_PIXELS, 0);
    gl->PixelStorei(GL_UNPACK_IMAGE_HEIGHT, 0);
}

static void enable(const limen__gl *gl, GLenum cap, GLboolean on)
{
    if (on)
        gl->Enable(cap);
    else
        gl->Disable(cap);
}

static void restore(const limen__gl *gl, const saved *sv)
{
    gl->UseProgram((GLuint)sv->i[I_PROGRAM]);
    gl->BindVertexArray((GLuint)sv->i[I_VAO]);
    gl->BindBuffer(GL_ARRAY_BUFFER, (GLuint)sv->i[I_ARRAY_BUFFER]);
    gl->BindFramebuffer(GL_DRAW_FRAMEBUFFER, (GLuint)sv->i[I_DRAW_FB]);
    gl->BindFramebuffer(GL_READ_FRAMEBUFFER, (GLuint)sv->i[I_READ_FB]);
    gl->BindRenderbuffer(GL_RENDERBUFFER, (GLuint)sv->i[I_RENDERBUFFER]);
    gl->ActiveTexture(GL_TEXTURE2);
    gl->BindTexture(GL_TEXTURE_2D, (GLuint)sv->i[I_TEXTURE2]);
    gl->BindSampler(2, (GLuint)sv->i[I_SAMPLER2]);
    gl->ActiveTexture(GL_TEXTURE1);
    gl->BindTexture(GL_TEXTURE_2D, (GLuint)sv->i[I_TEXTURE1]);
    gl->BindSampler(1, (GLuint)sv->i[I_SAMPLER1]);
    gl->ActiveTexture(GL_TEXTURE0);
    gl->BindTexture(GL_TEXTURE_2D, (GLuint)sv->i[I_TEXTURE0]);
    gl->BindSampler(0, (GLuint)sv->i[I_SAMPLER0]);
    gl->ActiveTexture((GLenum)sv->i[I_ACTIVE_TEXTURE]);
    gl->BindBuffer(GL_PIXEL_PACK_BUFFER, (GLuint)sv->i[I_PACK_BUFFER]);
    gl->BindBuffer(GL_PIXEL_UNPACK_BUFFER, (GLuint)sv->i[I_UNPACK_BUFFER]);
    gl->PixelStorei(GL_PACK_ALIGNMENT, sv->i[I_PACK_ALIGNMENT]);
    gl->PixelStorei(GL_PACK_ROW_LENGTH, sv->i[I_PACK_ROW_LENGTH]);
    gl->PixelStorei(GL_PACK_SKIP_ROWS, sv->i[I_PACK_SKIP_ROWS]);
    gl->PixelStorei(GL_PACK_SKIP_PIXELS, sv->i[I_PACK_SKIP_PIXELS]);
    gl->PixelStorei(GL_UNPACK_ALIGNMENT, sv->i[I_UNPACK_ALIGNMENT]);
    gl->PixelStorei(GL_UNPACK_ROW_LENGTH, sv->i[I_UNPACK_ROW_LENGTH]);
    gl->PixelStorei(GL_UNPACK_SKIP_ROWS, sv->i[I_UNPACK_SKIP_ROWS]);
    gl->PixelStorei(GL_UNPACK_SKIP_PIXELS, sv->i[I_UNPACK_SKIP_PIXELS]);
    gl->PixelStorei(GL_UNPACK_IMAGE_HEIGHT, sv->i[I_UNPACK_IMAGE_HEIGHT]);
    gl->Viewport(sv->viewport[0], sv->viewport[1], sv->viewport[2], sv->viewport[3]);
    gl->Scissor(sv->scissor[0], sv->scissor[1], sv->scissor[2], sv->scissor[3]);
    for (size_t k = 0; k < NCAPS; k++)
        enable(gl, caps[k], sv->caps[k]);
    gl->DepthFunc((GLenum)sv->i[I_DEPTH_FUNC]);
    gl->BlendFunc((GLenum)sv->i[I_BLEND_SRC], (GLenum)sv->i[I_BLEND_DST]);
    gl->DepthMask(sv->depth_mask);
    gl->ClearDepth(sv->depth_clear);
    gl->DepthRange(sv->depth_range[0], sv->depth_range[1]);
    set_face(gl, GL_FRONT, &sv->front);
    set_face(gl, GL_BACK, &sv->back);
    gl->ClearStencil(sv->i[I_STENCIL_CLEAR]);
    gl->ColorMask(sv->color_mask[0], sv->color_mask[1], sv->color_mask[2], sv->color_mask[3]);
    gl->ClearColor(sv->color_clear[0], sv->color_clear[1], sv->color_clear[2],
                   sv->color_clear[3]);
    gl->CullFace((GLenum)sv->i[I_CULL_MODE]);
    gl->FrontFace((GLenum)sv->i[I_FRONT_FACE]);
    gl->PolygonMode(GL_FRONT_AND_BACK, (GLenum)sv->polygon_mode[0]);
    if (gl->ClipControl)
        gl->ClipControl((GLenum)sv->i[I_CLIP_ORIGIN], (GLenum)sv->i[I_CLIP_DEPTH]);
}

static int host_enter(limen__ctx *c, const limen__gl *gl, char *err, size_t errsize)
{
    if (c->depth++)
        return 0;
    /* with no context current, a loader's entry points return nothing */
    if (!gl->GetString(GL_VERSION)) {
        c->depth = 0;
        snprintf(err, errsize, "host: no OpenGL context is current (make the game's context "
                               "current before calling limen)");
        return -1;
    }
    if (c->mark && !gl->IsSync(c->mark)) {
        c->depth = 0;
        snprintf(err, errsize, "host: the current OpenGL context is not the one this renderer "
                               "was created in (make that one current; limen draws into and "
                               "deletes from no other)");
        return -1;
    }
    /* the game's pending errors, so that limen's checks see its own; bounded, as a context
     * that is lost may answer GL_CONTEXT_LOST to every call */
    for (int k = 0; k < 64 && gl->GetError() != GL_NO_ERROR; k++)
        ;
    save(gl, &c->st);
    neutral(gl);
    if (!c->mark)
        c->mark = gl->FenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    return 0;
}

static void host_leave(limen__ctx *c, const limen__gl *gl)
{
    if (c->depth == 0 || --c->depth)
        return;
    restore(gl, &c->st);
}

static void host_destroy(limen__ctx *c)
{
    free(c);
}

static void host_release(limen__ctx *c, const limen__gl *gl)
{
    if (c->mark)
        gl->DeleteSync(c->mark);
    c->mark = NULL;
}

const limen__ctx_ops limen__ctx_host = {
    "host", host_create, host_enter, host_leave, host_getproc, host_destroy, host_release,
};
