/* ctx_osmesa.c - an OSMesa context (Mesa's software rasterizer, llvmpipe). The renderer
 * draws into its own framebuffer objects; OSMesa's buffer is only a token to make the
 * context current. A call gives the thread back the OSMesa context that was current
 * before, with its buffer (OSMesa cannot say that buffer's type: it is taken to be
 * GL_UNSIGNED_BYTE, the type nearly everyone uses). */
#include <stdio.h>
#include <stdlib.h>

#include <GL/osmesa.h>

#include "limen.h"
#include "gl/glapi.h"

struct limen__ctx {
    OSMesaContext ctx;
    unsigned char buffer[4 * 4 * 4];
    int depth;                  /* enter/leave nesting */
    OSMesaContext prev;         /* what was current at the outermost enter */
    void *prev_buffer;
    GLint prev_w, prev_h;
};

static limen__ctx *osmesa_create(const limen_renderer_desc *d, char *err, size_t errsize)
{
    static const int versions[][2] = { { 4, 5 }, { 4, 3 }, { 3, 3 } };
    limen__ctx *c = calloc(1, sizeof *c);
    if (!c) {
        snprintf(err, errsize, "osmesa: out of memory");
        return NULL;
    }
    for (size_t i = 0; i < sizeof versions / sizeof versions[0] && !c->ctx; i++) {
        const int attribs[] = { OSMESA_FORMAT, OSMESA_RGBA,
                                OSMESA_DEPTH_BITS, 0,
                                OSMESA_STENCIL_BITS, 0,
                                OSMESA_ACCUM_BITS, 0,
                                OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                                OSMESA_CONTEXT_MAJOR_VERSION, versions[i][0],
                                OSMESA_CONTEXT_MINOR_VERSION, versions[i][1],
                                0 };
        c->ctx = OSMesaCreateContextAttribs(attribs, NULL);
    }
    if (!c->ctx) {
        snprintf(err, errsize, "osmesa: cannot create an OpenGL 3.3 core context");
        free(c);
        return NULL;
    }
    return c;
}

static int osmesa_enter(limen__ctx *c, const limen__gl *gl, char *err, size_t errsize)
{
    if (c->depth++)
        return 0;
    c->prev = OSMesaGetCurrentContext();
    c->prev_buffer = NULL;
    GLint format;
    if (c->prev && c->prev != c->ctx &&
        !OSMesaGetColorBuffer(c->prev, &c->prev_w, &c->prev_h, &format, &c->prev_buffer))
        c->prev_buffer = NULL;
    if (!OSMesaMakeCurrent(c->ctx, c->buffer, GL_UNSIGNED_BYTE, 4, 4)) {
        c->depth = 0;
        snprintf(err, errsize, "osmesa: cannot make the context current");
        return -1;
    }
    return 0;
}

static void osmesa_leave(limen__ctx *c, const limen__gl *gl)
{
    if (c->depth == 0 || --c->depth)
        return;
    if (c->prev == c->ctx)
        return;
    if (c->prev && c->prev_buffer)
        OSMesaMakeCurrent(c->prev, c->prev_buffer, GL_UNSIGNED_BYTE, c->prev_w, c->prev_h);
    else
        OSMesaMakeCurrent(NULL, NULL, GL_UNSIGNED_BYTE, 0, 0);
}

static limen__glproc osmesa_getproc(limen__ctx *c, const char *name)
{
    return (limen__glproc)OSMesaGetProcAddress(name);
}

static void osmesa_destroy(limen__ctx *c)
{
    if (!c)
        return;
    if (c->ctx) {
        if (OSMesaGetCurrentContext() == c->ctx)
            OSMesaMakeCurrent(NULL, NULL, GL_UNSIGNED_BYTE, 0, 0);
        OSMesaDestroyContext(c->ctx);
    }
    free(c);
}

const limen__ctx_ops limen__ctx_osmesa = {
    "osmesa", osmesa_create, osmesa_enter, osmesa_leave, osmesa_getproc, osmesa_destroy,
    NULL,
};
