/* targets.c - the texture method's offscreen targets: one per depth of nesting, colour (RGBA8,
 * sampled linear and clamped) and depth-stencil, the size the draw list asks for. */
#include <string.h>

#include "gl/gl_internal.h"

static void target_free(limen_renderer *r, limen__target *t)
{
    GL(DeleteFramebuffers)(1, &t->fbo);
    GL(DeleteFramebuffers)(1, &t->resolve_fbo);
    GL(DeleteTextures)(1, &t->tex);
    GL(DeleteRenderbuffers)(1, &t->depth_rb);
    GL(DeleteTextures)(1, &t->ms_tex);
    memset(t, 0, sizeof *t);
}

void limen__targets_free(limen_renderer *r)
{
    for (int i = 0; i < LIMEN__MAX_TARGETS; i++)
        if (r->targets[i].fbo)
            target_free(r, &r->targets[i]);
}

GLuint limen__color_texture(limen_renderer *r, int w, int h)
{
    GLuint tex;
    GL(GenTextures)(1, &tex);
    GL(BindTexture)(GL_TEXTURE_2D, tex);
    GL(TexImage2D)(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, NULL);
    GL(TexParameteri)(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    GL(TexParameteri)(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    GL(TexParameteri)(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    GL(TexParameteri)(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    return tex;
}

static GLuint storage(limen_renderer *r, GLenum format, int samples, int w, int h)
{
    GLuint rb;
    GL(GenRenderbuffers)(1, &rb);
    GL(BindRenderbuffer)(GL_RENDERBUFFER, rb);
    if (samples > 1)
        GL(RenderbufferStorageMultisample)(GL_RENDERBUFFER, samples, format, w, h);
    else
        GL(RenderbufferStorage)(GL_RENDERBUFFER, format, w, h);
    return rb;
}

/* A target is drawn with the frame's samples (a view seen in a mirror is as smooth as one
 * seen directly): read sample by sample where it lies pixel for pixel over the frame
 * (texture_scale 1), else averaged into its texture (limen__target_texture). */
limen__target *limen__target_get(limen_renderer *r, int k, int w, int h)
{
    if (k < 1 || k >= LIMEN__MAX_TARGETS || w < 1 || h < 1 || w > 16384 || h > 16384)
        return NULL;
    limen__target *t = &r->targets[k];
    if (t->fbo && (t->w != w || t->h != h))
        target_free(r, t);
    if (t->fbo)
        return t;
    t->w = w;
    t->h = h;
    t->tex = limen__color_texture(r, t->w, t->h);
    t->depth_rb = storage(r, limen__depth_format(r), r->msaa, t->w, t->h);
    bool complete = true;
    if (r->msaa > 1) {
        GL(GenTextures)(1, &t->ms_tex);
        GL(BindTexture)(GL_TEXTURE_2D_MULTISAMPLE, t->ms_tex);
        GL(TexImage2DMultisample)(GL_TEXTURE_2D_MULTISAMPLE, r->msaa, GL_RGBA8, t->w, t->h,
                                  GL_TRUE);
        GL(GenFramebuffers)(1, &t->resolve_fbo);
        GL(BindFramebuffer)(GL_FRAMEBUFFER, t->resolve_fbo);
        GL(FramebufferTexture2D)(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t->tex, 0);
        complete = GL(CheckFramebufferStatus)(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
    }
    GL(GenFramebuffers)(1, &t->fbo);
    GL(BindFramebuffer)(GL_FRAMEBUFFER, t->fbo);
    if (t->ms_tex)
        GL(FramebufferTexture2D)(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D_MULTISAMPLE,
                                 t->ms_tex, 0);
    else
        GL(FramebufferTexture2D)(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t->tex, 0);
    GL(FramebufferRenderbuffer)(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                                t->depth_rb);
    if (!complete || GL(CheckFramebufferStatus)(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        target_free(r, t);
        return NULL;
    }
    return t;
}

GLuint limen__target_texture(limen_renderer *r, int k, GLuint bound)
{
    if (k < 1 || k >= LIMEN__MAX_TARGETS || !r->targets[k].fbo)
        return 0;
    limen__target *t = &r->targets[k];
    if (t->resolve_fbo && t->dirty) {
        GLboolean scissor = GL(IsEnabled)(GL_SCISSOR_TEST);
        GL(Disable)(GL_SCISSOR_TEST);      /* (a blit is scissored) */
        GL(BindFramebuffer)(GL_READ_FRAMEBUFFER, t->fbo);
        GL(BindFramebuffer)(GL_DRAW_FRAMEBUFFER, t->resolve_fbo);
        GL(BlitFramebuffer)(0, 0, t->w, t->h, 0, 0, t->w, t->h, GL_COLOR_BUFFER_BIT, GL_NEAREST);
        GL(BindFramebuffer)(GL_FRAMEBUFFER, bound);
        if (scissor)
            GL(Enable)(GL_SCISSOR_TEST);
        t->dirty = false;
    }
    return t->tex;
}
