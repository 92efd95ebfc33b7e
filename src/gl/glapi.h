/* glapi.h - the OpenGL entry points the renderer uses, loaded per context through the
 * context's get-proc function (OSMesa and EGL alike), so no libGL is linked and two
 * contexts of different backends can live in one process. */
#ifndef LIMEN_GLAPI_H
#define LIMEN_GLAPI_H

#include <stdbool.h>
#include <stddef.h>

#include <GL/glcorearb.h>

#ifndef GL_FRAGMENT_SHADER_INVOCATIONS_ARB
#define GL_FRAGMENT_SHADER_INVOCATIONS_ARB 0x82F4
#endif

/* X(return type, name, parameter list); the required ones first. */
#define LIMEN_GL_REQUIRED(X)                                                             \
    X(const GLubyte *, GetString, (GLenum name))                                         \
    X(const GLubyte *, GetStringi, (GLenum name, GLuint index))                          \
    X(GLsync, FenceSync, (GLenum condition, GLbitfield flags))                          \
    X(GLboolean, IsSync, (GLsync sync))                                                  \
    X(void, DeleteSync, (GLsync sync))                                                   \
    X(void, GetIntegerv, (GLenum pname, GLint *data))                                    \
    X(GLenum, GetError, (void))                                                          \
    X(void, Enable, (GLenum cap))                                                        \
    X(void, Disable, (GLenum cap))                                                       \
    X(void, Viewport, (GLint x, GLint y, GLsizei w, GLsizei h))                          \
    X(void, Scissor, (GLint x, GLint y, GLsizei w, GLsizei h))                           \
    X(void, Clear, (GLbitfield mask))                                                    \
    X(void, ClearColor, (GLfloat r, GLfloat g, GLfloat b, GLfloat a))                    \
    X(void, ClearDepth, (GLdouble d))                                                    \
    X(void, ClearStencil, (GLint s))                                                     \
    X(void, DepthFunc, (GLenum func))                                                    \
    X(void, DepthMask, (GLboolean flag))                                                 \
    X(void, DepthRange, (GLdouble n, GLdouble f))                                        \
    X(void, ColorMask, (GLboolean r, GLboolean g, GLboolean b, GLboolean a))             \
    X(void, StencilFunc, (GLenum func, GLint ref, GLuint mask))                          \
    X(void, StencilOp, (GLenum sfail, GLenum dpfail, GLenum dppass))                     \
    X(void, StencilMask, (GLuint mask))                                                  \
    X(void, FrontFace, (GLenum mode))                                                    \
    X(void, CullFace, (GLenum mode))                                                     \
    X(void, BlendFunc, (GLenum s, GLenum d))                                             \
    X(void, Finish, (void))                                                              \
    X(void, Flush, (void))                                                               \
    X(void, ReadPixels, (GLint x, GLint y, GLsizei w, GLsizei h, GLenum f, GLenum t,     \
                         void *p))                                                       \
    X(void, PixelStorei, (GLenum pname, GLint param))                                    \
    X(void, GenBuffers, (GLsizei n, GLuint *b))                                          \
    X(void, BindBuffer, (GLenum target, GLuint b))                                       \
    X(void, BufferData, (GLenum target, GLsizeiptr size, const void *data, GLenum use))  \
    X(void, BufferSubData, (GLenum target, GLintptr off, GLsizeiptr size, const void *data)) \
    X(void, DeleteBuffers, (GLsizei n, const GLuint *b))                                 \
    X(void, GenVertexArrays, (GLsizei n, GLuint *a))                                     \
    X(void, BindVertexArray, (GLuint a))                                                 \
    X(void, DeleteVertexArrays, (GLsizei n, const GLuint *a))                            \
    X(void, EnableVertexAttribArray, (GLuint i))                                         \
    X(void, VertexAttribPointer, (GLuint i, GLint size, GLenum type, GLboolean norm,     \
                                  GLsizei stride, const void *ptr))                      \
    X(GLuint, CreateShader, (GLenum type))                                               \
    X(void, ShaderSource, (GLuint sh, GLsizei n, const GLchar *const *src,               \
                           const GLint *len))                                            \
    X(void, CompileShader, (GLuint sh))                                                  \
    X(void, GetShaderiv, (GLuint sh, GLenum pname, GLint *v))                            \
    X(void, GetShaderInfoLog, (GLuint sh, GLsizei max, GLsizei *len, GLchar *log))       \
    X(GLuint, CreateProgram, (void))                                                     \
    X(void, AttachShader, (GLuint p, GLuint sh))                                         \
    X(void, LinkProgram, (GLuint p))                                                     \
    X(void, GetProgramiv, (GLuint p, GLenum pname, GLint *v))                            \
    X(void, GetProgramInfoLog, (GLuint p, GLsizei max, GLsizei *len, GLchar *log))       \
    X(void, DeleteShader, (GLuint sh))                                                   \
    X(void, DeleteProgram, (GLuint p))                                                   \
    X(void, UseProgram, (GLuint p))                                                      \
    X(GLint, GetUniformLocation, (GLuint p, const GLchar *name))                         \
    X(void, Uniform1i, (GLint loc, GLint v))                                             \
    X(void, Uniform1f, (GLint loc, GLfloat v))                                           \
    X(void, Uniform1fv, (GLint loc, GLsizei n, const GLfloat *v))                        \
    X(void, Uniform2fv, (GLint loc, GLsizei n, const GLfloat *v))                        \
    X(void, Uniform3fv, (GLint loc, GLsizei n, const GLfloat *v))                        \
    X(void, Uniform4fv, (GLint loc, GLsizei n, const GLfloat *v))                        \
    X(void, UniformMatrix3fv, (GLint loc, GLsizei n, GLboolean t, const GLfloat *v))     \
    X(void, UniformMatrix4fv, (GLint loc, GLsizei n, GLboolean t, const GLfloat *v))     \
    X(void, GenFramebuffers, (GLsizei n, GLuint *f))                                     \
    X(void, BindFramebuffer, (GLenum target, GLuint f))                                  \
    X(void, DeleteFramebuffers, (GLsizei n, const GLuint *f))                            \
    X(void, FramebufferRenderbuffer, (GLenum t, GLenum att, GLenum rbt, GLuint rb))      \
    X(void, FramebufferTexture2D, (GLenum t, GLenum att, GLenum tt, GLuint tex,          \
                                   GLint level))                                         \
    X(GLenum, CheckFramebufferStatus, (GLenum target))                                   \
    X(void, GenRenderbuffers, (GLsizei n, GLuint *r))                                    \
    X(void, BindRenderbuffer, (GLenum target, GLuint r))                                 \
    X(void, DeleteRenderbuffers, (GLsizei n, const GLuint *r))                           \
    X(void, RenderbufferStorage, (GLenum t, GLenum fmt, GLsizei w, GLsizei h))           \
    X(void, RenderbufferStorageMultisample, (GLenum t, GLsizei samples, GLenum fmt,      \
                                             GLsizei w, GLsizei h))                      \
    X(void, TexImage2DMultisample, (GLenum t, GLsizei samples, GLenum fmt, GLsizei w,    \
                                    GLsizei h, GLboolean fixed))                         \
    X(void, BlitFramebuffer, (GLint sx0, GLint sy0, GLint sx1, GLint sy1, GLint dx0,     \
                              GLint dy0, GLint dx1, GLint dy1, GLbitfield mask,          \
                              GLenum filter))                                            \
    X(void, GenTextures, (GLsizei n, GLuint *t))                                         \
    X(void, BindTexture, (GLenum target, GLuint t))                                      \
    X(void, DeleteTextures, (GLsizei n, const GLuint *t))                                \
    X(void, TexImage2D, (GLenum t, GLint level, GLint ifmt, GLsizei w, GLsizei h,        \
                         GLint border, GLenum fmt, GLenum type, const void *data))       \
    X(void, TexParameteri, (GLenum t, GLenum pname, GLint v))                            \
    X(void, ActiveTexture, (GLenum unit))                                                \
    X(void, GenQueries, (GLsizei n, GLuint *q))                                          \
    X(void, DeleteQueries, (GLsizei n, const GLuint *q))                                 \
    X(void, BeginQuery, (GLenum target, GLuint q))                                       \
    X(void, EndQuery, (GLenum target))                                                   \
    X(void, GetQueryObjectui64v, (GLuint q, GLenum pname, GLuint64 *v))                  \
    X(void, DrawElements, (GLenum mode, GLsizei count, GLenum type, const void *idx))    \
    X(void, DrawArrays, (GLenum mode, GLint first, GLsizei count))                     \
    X(void, DrawArraysInstanced, (GLenum mode, GLint first, GLsizei count, GLsizei n))   \
    X(void, VertexAttribDivisor, (GLuint i, GLuint divisor))                             \
    X(void, DrawElementsInstanced, (GLenum mode, GLsizei count, GLenum type,             \
                                    const void *idx, GLsizei n))                         \
    X(GLboolean, IsEnabled, (GLenum cap))                                                \
    X(void, GetBooleanv, (GLenum pname, GLboolean *data))                                \
    X(void, GetFloatv, (GLenum pname, GLfloat *data))                                    \
    X(void, GetDoublev, (GLenum pname, GLdouble *data))                                  \
    X(void, StencilFuncSeparate, (GLenum face, GLenum func, GLint ref, GLuint mask))     \
    X(void, StencilOpSeparate, (GLenum face, GLenum sfail, GLenum dpfail, GLenum dppass))\
    X(void, StencilMaskSeparate, (GLenum face, GLuint mask))                             \
    X(void, PolygonMode, (GLenum face, GLenum mode))                                     \
    X(void, BindSampler, (GLuint unit, GLuint sampler))                                  \
    X(void, GetFramebufferAttachmentParameteriv, (GLenum target, GLenum att,             \
                                                  GLenum pname, GLint *v))

/* May be missing (NULL): glClipControl needs GL 4.5 or ARB_clip_control. */
#define LIMEN_GL_OPTIONAL(X)                                                             \
    X(void, ClipControl, (GLenum origin, GLenum depth))                                  \
    X(void, MinSampleShading, (GLfloat value))

typedef struct limen__gl {
#define LIMEN_GL_FIELD(ret, name, args) ret(APIENTRY *name) args;
    LIMEN_GL_REQUIRED(LIMEN_GL_FIELD)
    LIMEN_GL_OPTIONAL(LIMEN_GL_FIELD)
#undef LIMEN_GL_FIELD
} limen__gl;

typedef void (*limen__glproc)(void);
struct limen__ctx;

/* Fills gl from getproc(c, name); returns the name of the first required entry point
 * missing, or NULL when all are there. */
const char *limen__gl_load(limen__gl *gl, limen__glproc (*getproc)(struct limen__ctx *c,
                                                                   const char *name),
                           struct limen__ctx *c);

/* ------------------------------------------------------------------ contexts */

typedef struct limen__ctx limen__ctx;
struct limen_renderer_desc;

/* Every public call that touches GL runs between enter and leave, so that the caller's GL
 * world is as it was afterwards: limen's own contexts (OSMesa, EGL) give the thread back the
 * context that was current before; the host's context gets back the GL state limen
 * changes (ctx_host.c lists it). */
typedef struct limen__ctx_ops {
    const char *name;
    /* Creates the context (for the host's: takes its loader); on failure returns NULL with
     * a message in err. */
    limen__ctx *(*create)(const struct limen_renderer_desc *d, char *err, size_t errsize);
    /* Makes the context current (or, for the host's, checks that one is and saves its
     * state); -1 with a message in err if it cannot. gl: the loaded table. */
    int (*enter)(limen__ctx *c, const limen__gl *gl, char *err, size_t errsize);
    void (*leave)(limen__ctx *c, const limen__gl *gl);
    limen__glproc (*getproc)(limen__ctx *c, const char *name);
    void (*destroy)(limen__ctx *c);
    /* Deletes what the context keeps in GL (between enter and leave, before destroy);
     * NULL where it keeps nothing. */
    void (*release)(limen__ctx *c, const limen__gl *gl);
} limen__ctx_ops;

extern const limen__ctx_ops limen__ctx_osmesa;
extern const limen__ctx_ops limen__ctx_egl;
extern const limen__ctx_ops limen__ctx_host;

#endif
