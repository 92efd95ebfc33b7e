/* ctx_osmesa.c - an OSMesa context (Mesa's software rasterizer, llvmpipe). The renderer
 * draws into its own framebuffer objects; OSMesa's buffer is only a token to make the
 * context current. */
#include <stdio.h>
#include <stdlib.h>

#include <GL/osmesa.h>

#include "gl/glapi.h"

struct limen__ctx {
    OSMesaContext ctx;
    unsigned char buffer[4 * 4 * 4];
};

static limen__ctx *osmesa_create(char *err, size_t errsize)
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

static int osmesa_make_current(limen__ctx *c)
{
    return OSMesaMakeCurrent(c->ctx, c->buffer, GL_UNSIGNED_BYTE, 4, 4) ? 0 : -1;
}

static limen__glproc osmesa_getproc(const char *name)
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
    "osmesa", osmesa_create, osmesa_make_current, osmesa_getproc, osmesa_destroy,
};
