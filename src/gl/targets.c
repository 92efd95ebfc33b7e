/* targets.c - the texture method's offscreen targets: one per depth of nesting, colour (RGBA8,
 * sampled linear and clamped) and depth-stencil, the size the draw list asks for. */
#include <string.h>

#include "gl/gl_internal.h"

void limen__targets_free(limen_renderer *r)
{
    for (int i = 0; i < LIMEN__MAX_TARGETS; i++) {
        limen__target *t = &r->targets[i];
        if (t->fbo) {
            GL(DeleteFramebuffers)(1, &t->fbo);
            GL(DeleteTextures)(1, &t->tex);
            GL(DeleteRenderbuffers)(1, &t->depth_rb);
        }
        memset(t, 0, sizeof *t);
    }
}

static void target_free(limen_renderer *r, limen__target *t)
{
    GL(DeleteFramebuffers)(1, &t->fbo);
    GL(DeleteTextures)(1, &t->tex);
    GL(DeleteRenderbuffers)(1, &t->depth_rb);
    memset(t, 0, sizeof *t);
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

const limen__target *limen__target_get(limen_renderer *r, int k, int w, int h)
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
    GL(GenRenderbuffers)(1, &t->depth_rb);
    GL(BindRenderbuffer)(GL_RENDERBUFFER, t->depth_rb);
    GL(RenderbufferStorage)(GL_RENDERBUFFER, limen__depth_format(r), t->w, t->h);
    GL(GenFramebuffers)(1, &t->fbo);
    GL(BindFramebuffer)(GL_FRAMEBUFFER, t->fbo);
    GL(FramebufferTexture2D)(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, t->tex, 0);
    GL(FramebufferRenderbuffer)(GL_FRAMEBUFFER, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                                t->depth_rb);
    if (GL(CheckFramebufferStatus)(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        target_free(r, t);
        return NULL;
    }
    return t;
}
