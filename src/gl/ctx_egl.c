/* ctx_egl.c - an EGL context with no surface (EGL_MESA_platform_surfaceless, or the first
 * EGL device): the same code runs on a GPU or, without one, on Mesa's software driver. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define EGL_EGLEXT_PROTOTYPES
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include "gl/glapi.h"

struct limen__ctx {
    EGLDisplay dpy;
    EGLContext ctx;
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

static limen__ctx *egl_create(char *err, size_t errsize)
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
    if (!c->ctx) {
        snprintf(err, errsize, "egl: cannot create an OpenGL 3.3 core context (0x%x)",
                 (unsigned)eglGetError());
        eglTerminate(c->dpy);
        free(c);
        return NULL;
    }
    return c;
}

static int egl_make_current(limen__ctx *c)
{
    return eglMakeCurrent(c->dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, c->ctx) ? 0 : -1;
}

static limen__glproc egl_getproc(const char *name)
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
    "egl", egl_create, egl_make_current, egl_getproc, egl_destroy,
};
