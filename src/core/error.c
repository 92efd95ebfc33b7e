/* error.c - status codes and per-object error messages. */
#include <stdio.h>

#include "core/internal.h"

const char *limen_status_string(limen_status st)
{
    switch (st) {
    case LIMEN_OK: return "ok";
    case LIMEN_ERR_ARG: return "invalid argument";
    case LIMEN_ERR_DEGENERATE: return "degenerate geometry";
    case LIMEN_ERR_NOMEM: return "out of memory";
    case LIMEN_ERR_HANDLE: return "invalid node handle";
    case LIMEN_ERR_CYCLE: return "cycle in the parent chain";
    case LIMEN_ERR_SCRIPT: return "script error";
    case LIMEN_ERR_GL: return "OpenGL error";
    case LIMEN_ERR_IO: return "input/output error";
    case LIMEN_ERR_UNSUPPORTED: return "unsupported";
    case LIMEN_STATUS_COUNT: break;
    }
    return "unknown status";
}

void limen__vformat(char *buf, size_t size, const char *fmt, va_list ap)
{
    if (!buf || !size)
        return;
    vsnprintf(buf, size, fmt, ap);
}

limen_status limen__fail(limen_scene *s, limen_status st, const char *fmt, ...)
{
    if (s) {
        va_list ap;
        va_start(ap, fmt);
        limen__vformat(s->err, sizeof s->err, fmt, ap);
        va_end(ap);
    }
    return st;
}

const char *limen_scene_error(const limen_scene *s)
{
    return s ? s->err : "no scene";
}
