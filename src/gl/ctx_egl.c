/* ctx_egl.c - an EGL context with no surface (EGL_MESA_platform_surfaceless, or the first
 * EGL device): the same code runs on a GPU or, without one, on Mesa's software driver. A
 * call gives the thread back its EGL context, surfaces and bound API as they were. (A
 * context current through GLX is beyond EGL's reach: use LIMEN_BACKEND_HOST there.) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define EGL_EGLEXT_PROTOTYPES
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include "limen.h"
#include "gl/glapi.h"

struct limen__ctx {
    EGLDisplay dpy;
    EGLContext ctx;
    int depth;                  /* enter/leave nesting */
    EGLenum prev_api;           /* what was current at the outermost enter */
    EGLDisplay prev_dpy;
    EGLContext prev_ctx;
    EGLSurface prev_draw, prev_read;
};

static bool has_ext(const char *list, const char *ext)
{
    size_t n = strlen(ext);
    for (const char *p = list; p && (p = strstr(p, ext)); p += n)
        if ((p == list || p[-1] == ' ') && (p[n] == ' ' || p[n] == '\0'))
            return true;
    return false;
}

static EGLDisplay open_display(void)
{
    const char *client = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
    PFNEGLGETPLATFORMDISPLAYEXTPROC get_display =
        (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
    if (!get_display)
        return EGL_NO_DISPLAY;
    EGLDisplay dpy = EGL_NO_DISPLAY;
    /* A GPU through EGL devices first, where there is one; then Mesa's surfaceless
     * platform, which falls back to software rendering. */
    if (has_ext(client, "EGL_EXT_platform_device")) {
        PFNEGLQUERYDEVICESEXTPROC query_devices =
            (PFNEGLQUERYDEVICESEXTPROC)eglGetProcAddress("eglQueryDevicesEXT");
        PFNEGLQUERYDEVICESTRINGEXTPROC device_string =
            (PFNEGLQUERYDEVICESTRINGEXTPROC)eglGetProcAddress("eglQueryDeviceStringEXT");
        EGLDeviceEXT devices[8];
        EGLint count = 0;
        if (query_devices && query_devices(8, devices, &count)) {
            for (EGLint i = 0; i < count && dpy == EGL_NO_DISPLAY; i++) {
                const char *exts = device_string ? device_string(devices[i], EGL_EXTENSIONS)
                                                 : NULL;
                /* Skip Mesa's software device here: surfaceless covers it. */
                if (exts && has_ext(exts, "EGL_MESA_device_software"))
                    continue;
                EGLDisplay d = get_display(EGL_PLATFORM_DEVICE_EXT, devices[i], NULL);
                if (d != EGL_NO_DISPLAY && eglInitialize(d, NULL, NULL))
                    dpy = d;
            }
        }
    }
    if (dpy == EGL_NO_DISPLAY && has_ext(client, "EGL_MESA_platform_surfaceless")) {
        EGLDisplay d = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
        if (d != EGL_NO_DISPLAY && eglInitialize(d, NULL, NULL))
            dpy = d;
    }
    return dpy;
}

static limen__ctx *egl_create(const limen_renderer_desc *d, char *err, size_t errsize)
{
    limen__ctx *c = calloc(1, sizeof *c);
    if (!c) {
        snprintf(err, errsize, "egl: out of memory");
        return NULL;
    }
    c->dpy = open_display();
    if (c->dpy == EGL_NO_DISPLAY) {
        snprintf(err, errsize, "egl: no display (needs EGL_EXT_platform_device or "
                               "EGL_MESA_platform_surfaceless)");
        free(c);
        return NULL;
    }
    const char *exts = eglQueryString(c->dpy, EGL_EXTENSIONS);
    if (!has_ext(exts, "EGL_KHR_surfaceless_context") ||
        !has_ext(exts, "EGL_KHR_no_config_context")) {
        snprintf(err, errsize, "egl: the display lacks surfaceless or config-less contexts");
        eglTerminate(c->dpy);
        free(c);
        return NULL;
    }
    EGLenum api = eglQueryAPI();
    if (!eglBindAPI(EGL_OPENGL_API)) {
        snprintf(err, errsize, "egl: desktop OpenGL is not available");
        eglTerminate(c->dpy);
        free(c);
        return NULL;
    }
    static const int versions[][2] = { { 4, 5 }, { 4, 3 }, { 3, 3 } };
    for (size_t i = 0; i < sizeof versions / sizeof versions[0] && !c->ctx; i++) {
        const EGLint attribs[] = { EGL_CONTEXT_MAJOR_VERSION, versions[i][0],
                                   EGL_CONTEXT_MINOR_VERSION, versions[i][1],
                                   EGL_CONTEXT_OPENGL_PROFILE_MASK,
                                   EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE };
        c->ctx = eglCreateContext(c->dpy, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
        if (c->ctx == EGL_NO_CONTEXT)
            c->ctx = NULL;
    }
    eglBindAPI(api);
    if (!c->ctx) {
        snprintf(err, errsize, "egl: cannot create an OpenGL 3.3 core context (0x%x)",
                 (unsigned)eglGetError());
        eglTerminate(c->dpy);
        free(c);
        return NULL;
    }
    return c;
}

static int egl_enter(limen__ctx *c, const limen__gl *gl, char *err, size_t errsize)
{
    if (c->depth++)
        return 0;
    c->prev_api = eglQueryAPI();
    c->prev_dpy = eglGetCurrentDisplay();
    c->prev_ctx = eglGetCurrentContext();
    c->prev_draw = eglGetCurrentSurface(EGL_DRAW);
    c->prev_read = eglGetCurrentSurface(EGL_READ);
    if (!eglBindAPI(EGL_OPENGL_API) ||
        !eglMakeCurrent(c->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, c->ctx)) {
        eglBindAPI(c->prev_api);
        c->depth = 0;
        snprintf(err, errsize, "egl: cannot make the context current (0x%x)",
                 (unsigned)eglGetError());
        return -1;
    }
    return 0;
}

static void egl_leave(limen__ctx *c, const limen__gl *gl)
{
    if (c->depth == 0 || --c->depth)
        return;
    if (c->prev_ctx == c->ctx)
        return;
    if (c->prev_ctx != EGL_NO_CONTEXT) {
        eglBindAPI(c->prev_api);
        eglMakeCurrent(c->prev_dpy, c->prev_draw, c->prev_read, c->prev_ctx);
    } else {
        eglMakeCurrent(c->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglBindAPI(c->prev_api);
    }
}

static limen__glproc egl_getproc(limen__ctx *c, const char *name)
{
    return (limen__glproc)eglGetProcAddress(name);
}

static void egl_destroy(limen__ctx *c)
{
    if (!c)
        return;
    if (c->ctx) {
        if (eglGetCurrentContext() == c->ctx)
            eglMakeCurrent(c->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
        eglDestroyContext(c->dpy, c->ctx);
    }
    /* eglTerminate would pull the display from under other renderers in this process
     * that share it (EGL displays are per platform and device, not per caller). */
    free(c);
}

const limen__ctx_ops limen__ctx_egl = {
    "egl", egl_create, egl_enter, egl_leave, egl_getproc, egl_destroy, NULL,
};
