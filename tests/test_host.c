/* test_host.c - limen drawing into a game's own context (LIMEN_BACKEND_HOST), and limen's own
 * contexts leaving the thread's current context as they found it.
 *
 * The "game" here is an OSMesa context of its own with a depth and stencil buffer, which it
 * draws into with its own GL (the functions libOSMesa exports): it sets up state of its own,
 * lets limen draw a frame into its framebuffer, checks that every piece of state limen
 * promises to restore is as it was, and draws on top with its own program, checking the
 * pixels. limen's frames must match what limen's own OSMesa renderer draws of the scene. */
#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>
#include <GL/osmesa.h>
#define EGL_EGLEXT_PROTOTYPES
#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <fcntl.h>
#include <spawn.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>

#include "limen.h"
#include "check.h"
#include "load.h"

#define W 160
#define H 120

typedef struct game {
    OSMesaContext ctx;
    unsigned char *buf;         /* the default framebuffer's memory */
    int w, h;
    GLuint prog, vao, vbo, tex, sampler;
    GLint u_color;
} game;

static void *loader(const char *name)
{
    OSMESAproc p = OSMesaGetProcAddress(name);
    void *v;
    memcpy(&v, &p, sizeof v);
    return v;
}

static int game_current(game *g)
{
    return OSMesaMakeCurrent(g->ctx, g->buf, GL_UNSIGNED_BYTE, g->w, g->h) ? 0 : -1;
}

static const char *vs = "#version 330 core\n"
                        "layout(location = 0) in vec2 p;\n"
                        "void main() { gl_Position = vec4(p, 0.5, 1.0); }\n";
static const char *fs = "#version 330 core\n"
                        "uniform vec4 u_color; out vec4 o;\n"
                        "void main() { o = u_color; }\n";

static GLuint shader(GLenum type, const char *src)
{
    GLuint s = glCreateShader(type);
    glShaderSource(s, 1, &src, NULL);
    glCompileShader(s);
    return s;
}

/* A game with a w x h default framebuffer (depth 24, `stencil` bits) and a program that
 * fills the viewport with one colour. */
static int game_create(game *g, int w, int h, int stencil)
{
    memset(g, 0, sizeof *g);
    static const int versions[][2] = { { 4, 5 }, { 3, 3 } };
    for (int i = 0; i < 2 && !g->ctx; i++) {
        const int attribs[] = { OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 24,
                                OSMESA_STENCIL_BITS, stencil, OSMESA_PROFILE,
                                OSMESA_CORE_PROFILE, OSMESA_CONTEXT_MAJOR_VERSION,
                                versions[i][0], OSMESA_CONTEXT_MINOR_VERSION, versions[i][1],
                                0 };
        g->ctx = OSMesaCreateContextAttribs(attribs, NULL);
    }
    g->w = w, g->h = h;
    g->buf = calloc((size_t)w * (size_t)h, 4);
    if (!g->ctx || !g->buf || game_current(g))
        return -1;
    GLuint v = shader(GL_VERTEX_SHADER, vs), f = shader(GL_FRAGMENT_SHADER, fs);
    g->prog = glCreateProgram();
    glAttachShader(g->prog, v);
    glAttachShader(g->prog, f);
    glLinkProgram(g->prog);
    glDeleteShader(v);
    glDeleteShader(f);
    g->u_color = glGetUniformLocation(g->prog, "u_color");
    static const float quad[] = { -1, -1, 3, -1, -1, 3 };
    glGenVertexArrays(1, &g->vao);
    glBindVertexArray(g->vao);
    glGenBuffers(1, &g->vbo);
    glBindBuffer(GL_ARRAY_BUFFER, g->vbo);
    glBufferData(GL_ARRAY_BUFFER, sizeof quad, quad, GL_STATIC_DRAW);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 0, NULL);
    glGenTextures(1, &g->tex);
    glGenSamplers(1, &g->sampler);
    GLint linked = 0;
    glGetProgramiv(g->prog, GL_LINK_STATUS, &linked);
    return linked ? 0 : -1;
}

static void game_destroy(game *g)
{
    if (g->ctx) {
        game_current(g);
        glDeleteProgram(g->prog);
        glDeleteBuffers(1, &g->vbo);
        glDeleteVertexArrays(1, &g->vao);
        glDeleteTextures(1, &g->tex);
        glDeleteSamplers(1, &g->sampler);
        OSMesaMakeCurrent(NULL, NULL, GL_UNSIGNED_BYTE, 0, 0);
        OSMesaDestroyContext(g->ctx);
    }
    free(g->buf);
}

/* ------------------------------------------------------------------ the game's state */

/* Everything limen.h promises to give back, read the game's own way. */
typedef struct snapshot {
    GLint ints[48];
    GLboolean bools[40];
    GLfloat floats[8];
} snapshot;

static void take(snapshot *s)
{
    static const GLenum ints[] = {
        GL_CURRENT_PROGRAM, GL_VERTEX_ARRAY_BINDING, GL_ELEMENT_ARRAY_BUFFER_BINDING,
        GL_ARRAY_BUFFER_BINDING, GL_DRAW_FRAMEBUFFER_BINDING, GL_READ_FRAMEBUFFER_BINDING,
        GL_RENDERBUFFER_BINDING, GL_ACTIVE_TEXTURE, GL_PIXEL_PACK_BUFFER_BINDING,
        GL_PIXEL_UNPACK_BUFFER_BINDING, GL_PACK_ALIGNMENT, GL_PACK_ROW_LENGTH,
        GL_UNPACK_ALIGNMENT, GL_UNPACK_ROW_LENGTH, GL_DEPTH_FUNC,
        GL_CULL_FACE_MODE, GL_FRONT_FACE, GL_STENCIL_FUNC, GL_STENCIL_REF,
        GL_STENCIL_VALUE_MASK, GL_STENCIL_FAIL, GL_STENCIL_PASS_DEPTH_FAIL,
        GL_STENCIL_PASS_DEPTH_PASS, GL_STENCIL_WRITEMASK, GL_STENCIL_BACK_FUNC,
        GL_STENCIL_BACK_REF, GL_STENCIL_BACK_WRITEMASK, GL_STENCIL_BACK_PASS_DEPTH_PASS,
        GL_STENCIL_CLEAR_VALUE, GL_POLYGON_MODE,
    };
    static const GLenum caps[] = {
        GL_DEPTH_TEST, GL_STENCIL_TEST, GL_SCISSOR_TEST, GL_BLEND, GL_CULL_FACE,
        GL_DEPTH_CLAMP, GL_CLIP_DISTANCE0, GL_CLIP_DISTANCE1, GL_CLIP_DISTANCE3,
        GL_FRAMEBUFFER_SRGB, GL_POLYGON_OFFSET_FILL, GL_PRIMITIVE_RESTART,
    };
    memset(s, 0, sizeof *s);
    int k = 0;
    for (size_t i = 0; i < sizeof ints / sizeof ints[0]; i++)
        glGetIntegerv(ints[i], &s->ints[k++]);
    glGetIntegerv(GL_VIEWPORT, &s->ints[k]), k += 4;
    glGetIntegerv(GL_SCISSOR_BOX, &s->ints[k]), k += 4;
    GLint unit;
    glGetIntegerv(GL_ACTIVE_TEXTURE, &unit);
    for (int u = 0; u < 2; u++) {   /* the units limen samples from */
        glActiveTexture(GL_TEXTURE0 + (GLenum)u);
        glGetIntegerv(GL_TEXTURE_BINDING_2D, &s->ints[k++]);
        glGetIntegerv(GL_SAMPLER_BINDING, &s->ints[k++]);
    }
    glActiveTexture((GLenum)unit);
    k = 0;
    for (size_t i = 0; i < sizeof caps / sizeof caps[0]; i++)
        s->bools[k++] = glIsEnabled(caps[i]);
    glGetBooleanv(GL_DEPTH_WRITEMASK, &s->bools[k++]);
    glGetBooleanv(GL_COLOR_WRITEMASK, &s->bools[k]), k += 4;
    glGetFloatv(GL_COLOR_CLEAR_VALUE, s->floats);
    glGetFloatv(GL_DEPTH_CLEAR_VALUE, &s->floats[4]);
    glGetFloatv(GL_DEPTH_RANGE, &s->floats[5]);
}

/* State a game may well have when it calls limen, none of it what limen draws with. */
static void odd_state(game *g, GLuint fbo)
{
    glUseProgram(g->prog);
    glBindVertexArray(g->vao);
    glBindBuffer(GL_ARRAY_BUFFER, g->vbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glActiveTexture(GL_TEXTURE3);
    glBindTexture(GL_TEXTURE_2D, g->tex);
    glActiveTexture(GL_TEXTURE1);
    glBindTexture(GL_TEXTURE_2D, g->tex);
    glBindSampler(1, g->sampler);
    glActiveTexture(GL_TEXTURE0);
    glBindTexture(GL_TEXTURE_2D, g->tex);
    glBindSampler(0, g->sampler);
    glSamplerParameteri(g->sampler, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glActiveTexture(GL_TEXTURE3);
    glPixelStorei(GL_PACK_ALIGNMENT, 8);
    glPixelStorei(GL_PACK_ROW_LENGTH, 7);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 8);      /* limen uploads textures: not with these */
    glPixelStorei(GL_UNPACK_ROW_LENGTH, 5);
    glViewport(3, 2, W / 2, H / 2);
    glEnable(GL_SCISSOR_TEST);
    glScissor(0, 0, W / 4, H / 4);
    glDisable(GL_DEPTH_TEST);
    glDepthFunc(GL_GEQUAL);
    glDepthMask(GL_FALSE);
    glEnable(GL_STENCIL_TEST);
    glStencilFuncSeparate(GL_FRONT, GL_NOTEQUAL, 3, 0x0F);
    glStencilFuncSeparate(GL_BACK, GL_LESS, 5, 0xF0);
    glStencilOpSeparate(GL_FRONT, GL_INCR, GL_DECR, GL_REPLACE);
    glStencilMaskSeparate(GL_BACK, 0x3C);
    glClearStencil(9);
    glEnable(GL_BLEND);
    glBlendFunc(GL_ONE, GL_ONE);
    glEnable(GL_CULL_FACE);
    glCullFace(GL_FRONT);
    glFrontFace(GL_CW);
    glColorMask(GL_TRUE, GL_FALSE, GL_TRUE, GL_TRUE);
    glClearColor(0.2f, 0.4f, 0.6f, 1.0f);
    glClearDepth(0.25);
    glDepthRange(0.2, 0.9);
    glEnable(GL_CLIP_DISTANCE3);
    glEnable(GL_FRAMEBUFFER_SRGB);
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(4, 4);
    glPolygonMode(GL_FRONT_AND_BACK, GL_LINE);
}

static bool same_state(const snapshot *a, const snapshot *b)
{
    bool same = true;
    for (int i = 0; i < 40; i++)
        if (a->ints[i] != b->ints[i]) {
            CHECK_MSG(0, "integer state %d: %d before limen, %d after", i, a->ints[i],
                      b->ints[i]);
            same = false;
        }
    for (int i = 0; i < 40; i++)
        if (a->bools[i] != b->bools[i]) {
            CHECK_MSG(0, "flag %d: %d before limen, %d after", i, a->bools[i], b->bools[i]);
            same = false;
        }
    for (int i = 0; i < 8; i++)
        if (a->floats[i] != b->floats[i]) {
            CHECK_MSG(0, "value %d: %g before limen, %g after", i, a->floats[i], b->floats[i]);
            same = false;
        }
    return same;
}

/* ------------------------------------------------------------------ references */

/* The scene as limen's own OSMesa renderer draws it. */
static unsigned char *reference(limen_scene *s, limen_method method)
{
    limen_renderer *r = NULL;
    unsigned char *rgb = calloc(W * H * 3, 1);
    limen_status st = limen_renderer_create(&(limen_renderer_desc){ .width = W, .height = H }, &r);
    CHECK_MSG(st == LIMEN_OK, "reference: %s", r ? limen_renderer_error(r) : "");
    if (!st) {
        CHECK_OK(limen_render_frame(r, s, &(limen_render_opts){ .method = method }, NULL));
        CHECK_OK(limen_renderer_read_rgb(r, rgb));
    }
    limen_renderer_destroy(r);
    return rgb;
}

static double share_off(const unsigned char *a, const unsigned char *b)
{
    limen_diff d;
    limen_image_diff(a, b, W, H, 8, &d, NULL);
    return d.bad_share;
}

/* A colour-and-depth-stencil framebuffer of the game's, fw x fh, cleared to `clear`. */
static GLuint game_fbo(int fw, int fh, GLenum depth_format, GLuint rb[2], const float clear[4])
{
    GLuint fbo;
    glGenRenderbuffers(2, rb);
    glBindRenderbuffer(GL_RENDERBUFFER, rb[0]);
    glRenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, fw, fh);
    glBindRenderbuffer(GL_RENDERBUFFER, rb[1]);
    glRenderbufferStorage(GL_RENDERBUFFER, depth_format, fw, fh);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb[0]);
    glFramebufferRenderbuffer(GL_FRAMEBUFFER,
                              depth_format == GL_DEPTH24_STENCIL8 ? GL_DEPTH_STENCIL_ATTACHMENT
                                                                  : GL_DEPTH_ATTACHMENT,
                              GL_RENDERBUFFER, rb[1]);
    glClearColor(clear[0], clear[1], clear[2], clear[3]);
    glClear(GL_COLOR_BUFFER_BIT);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    return fbo;
}

static void game_fbo_free(GLuint fbo, GLuint rb[2])
{
    if (fbo) {
        glDeleteFramebuffers(1, &fbo);
        glDeleteRenderbuffers(2, rb);
    }
}

/* The share of pixels of r's last frame off limen's own renderer's (the game current). */
static double off_reference(game *g, limen_renderer *r, limen_scene *s, limen_method method)
{
    unsigned char *rgb = calloc(W * H * 3, 1), *ref = reference(s, method);
    game_current(g);
    CHECK_OK(limen_renderer_read_rgb(r, rgb));
    double off = share_off(rgb, ref);
    free(rgb);
    free(ref);
    return off;
}

/* ------------------------------------------------------------------ tests */

/* limen draws scenes into the game's default framebuffer and into a framebuffer object at
 * an offset viewport, both methods: the same pixels as its own renderer, the game's state
 * as it was, and the game's own draw afterwards lands where and how the game meant. */
static void host_frames(void)
{
    /* portal_rooms: meshes and textures, which bind arrays and a texture unit of their own */
    static const char *scenes[] = { "scenes/portals.lua", "scenes/mirror_room.lua",
                                    "scenes/portal_rooms.lua" };
    for (int sc_i = 0; sc_i < 3; sc_i++) {
        limen_script *sc = check_load_script(scenes[sc_i]);
        if (!sc)
            return;
        limen_scene *s = limen_script_scene(sc);
        for (int m = 0; m < 2; m++) {
            limen_method method = m ? LIMEN_METHOD_TEXTURE : LIMEN_METHOD_STENCIL;
            unsigned char *ref = reference(s, method);
            for (int use_fbo = 0; use_fbo < 2; use_fbo++) {
                const int ox = use_fbo ? 16 : 0, oy = use_fbo ? 8 : 0;
                const int fw = W + 2 * ox, fh = H + 2 * oy;
                game g;
                CHECK_OK(game_create(&g, fw, fh, 8));
                static const float marker[4] = { 1, 0, 1, 1 };
                GLuint rb[2] = { 0, 0 }, fbo = 0;
                if (use_fbo)
                    fbo = game_fbo(fw, fh, GL_DEPTH24_STENCIL8, rb, marker);
                limen_renderer *r = NULL;
                limen_renderer_desc d = { .backend = LIMEN_BACKEND_HOST, .width = W, .height = H,
                                          .gl_loader = loader, .framebuffer = fbo, .x = ox,
                                          .y = oy };
                odd_state(&g, fbo);
                snapshot before, after;
                take(&before);
                limen_status st = limen_renderer_create(&d, &r);
                CHECK_MSG(st == LIMEN_OK, "host create: %s", limen_renderer_error(r));
                take(&after);
                CHECK(same_state(&before, &after));
                unsigned char *rgb = calloc(W * H * 3, 1);
                if (!st) {
                    st = limen_render_frame(r, s, &(limen_render_opts){ .method = method },
                                            NULL);
                    CHECK_MSG(st == LIMEN_OK, "%s: %s", scenes[sc_i], limen_renderer_error(r));
                    take(&after);
                    CHECK(same_state(&before, &after));
                    CHECK_OK(limen_renderer_read_rgb(r, rgb));
                    take(&after);
                    CHECK(same_state(&before, &after));
                    double off = share_off(rgb, ref);
                    CHECK_MSG(off == 0, "%s %s fbo %d: %.4f%% off limen's own frame",
                              scenes[sc_i], m ? "texture" : "stencil", use_fbo, 100 * off);
                }
                CHECK(OSMesaGetCurrentContext() == g.ctx);
                CHECK(glGetError() == GL_NO_ERROR);
                /* the game draws on with its own state: its program fills its viewport,
                 * cut by its scissor, added (blend one, one) and without green (mask) */
                glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
                glDisable(GL_STENCIL_TEST);
                glDisable(GL_CLIP_DISTANCE3);
                glDisable(GL_FRAMEBUFFER_SRGB);
                glDisable(GL_CULL_FACE);
                glUniform4f(g.u_color, 0.25f, 0.5f, 0.0f, 1.0f);
                glDrawArrays(GL_TRIANGLES, 0, 3);
                unsigned char *px = malloc((size_t)fw * (size_t)fh * 4);
                glPixelStorei(GL_PACK_ALIGNMENT, 4);
                glPixelStorei(GL_PACK_ROW_LENGTH, 0);
                glBindFramebuffer(GL_READ_FRAMEBUFFER, fbo);
                glReadPixels(0, 0, fw, fh, GL_RGBA, GL_UNSIGNED_BYTE, px);
                int wrong = 0;
                for (int y = 0; y < fh; y++)
                    for (int x = 0; x < fw; x++) {
                        const unsigned char *p = px + ((size_t)y * (size_t)fw + (size_t)x) * 4;
                        int inside = x >= ox && x < ox + W && y >= oy && y < oy + H;
                        unsigned char want[3] = { 255, 0, 255 };        /* the marker */
                        if (inside)
                            memcpy(want, rgb + ((size_t)(H - 1 - (y - oy)) * W + (size_t)(x - ox)) * 3, 3);
                        /* the game's quad: viewport (3, 2, W/2, H/2) within scissor
                         * (0, 0, W/4, H/4) */
                        if (x >= 3 && x < W / 4 && y >= 2 && y < H / 4) {
                            want[0] = (unsigned char)(want[0] + 64 > 255 ? 255 : want[0] + 64);
                        }
                        for (int c = 0; c < 3; c++)
                            if (abs((int)p[c] - (int)want[c]) > 1)
                                wrong++;
                    }
                CHECK_MSG(wrong == 0, "%s fbo %d: %d channels not what the game drew",
                          scenes[sc_i], use_fbo, wrong);
                free(px);
                free(rgb);
                limen_renderer_destroy(r);
                game_fbo_free(fbo, rb);
                game_destroy(&g);
            }
            free(ref);
        }
        limen_script_destroy(sc);
    }
}

/* Without a stencil buffer the stencil method says so; the texture method draws. */
static void host_without_stencil(void)
{
    limen_script *sc = check_load_script("scenes/portals.lua");
    if (!sc)
        return;
    limen_scene *s = limen_script_scene(sc);
    for (int use_fbo = 0; use_fbo < 2; use_fbo++) {
        game g;
        CHECK_OK(game_create(&g, W, H, 0));
        GLuint rb[2] = { 0, 0 }, fbo = 0;
        if (use_fbo)
            fbo = game_fbo(W, H, GL_DEPTH_COMPONENT24, rb, (const float[4]){ 0, 0, 0, 1 });
        limen_renderer *r = NULL;
        limen_renderer_desc d = { .backend = LIMEN_BACKEND_HOST, .width = W, .height = H,
                                  .gl_loader = loader, .framebuffer = fbo };
        CHECK_OK(limen_renderer_create(&d, &r));
        limen_status st = limen_render_frame(r, s, NULL, NULL);
        CHECK(st == LIMEN_ERR_UNSUPPORTED);
        CHECK_MSG(strstr(limen_renderer_error(r), "stencil"), "message: %s",
                  limen_renderer_error(r));
        CHECK(glGetError() == GL_NO_ERROR);
        st = limen_render_frame(r, s, &(limen_render_opts){ .method = LIMEN_METHOD_TEXTURE },
                                NULL);
        CHECK_MSG(st == LIMEN_OK, "texture method: %s", limen_renderer_error(r));
        CHECK(off_reference(&g, r, s, LIMEN_METHOD_TEXTURE) == 0);
        limen_renderer_destroy(r);
        game_fbo_free(fbo, rb);
        game_destroy(&g);
    }
    limen_script_destroy(sc);
}

/* No context current, no loader, a sub-3.3 request: clear errors, no crash. */
static void host_errors(void)
{
    limen_renderer *r = NULL;
    limen_renderer_desc d = { .backend = LIMEN_BACKEND_HOST };
    CHECK(limen_renderer_create(&d, &r) != LIMEN_OK);
    CHECK_MSG(strstr(limen_renderer_error(r), "loader"), "%s", limen_renderer_error(r));
    limen_renderer_destroy(r);
    OSMesaMakeCurrent(NULL, NULL, GL_UNSIGNED_BYTE, 0, 0);
    d.gl_loader = loader;
    r = NULL;
    CHECK(limen_renderer_create(&d, &r) == LIMEN_ERR_GL);
    CHECK_MSG(strstr(limen_renderer_error(r), "no OpenGL context is current"), "%s",
              limen_renderer_error(r));
    limen_renderer_destroy(r);
    d.msaa = 4;
    r = NULL;
    CHECK(limen_renderer_create(&d, &r) == LIMEN_ERR_ARG);
    limen_renderer_destroy(r);
    /* set_viewport is the host's alone */
    r = NULL;
    if (limen_renderer_create(&(limen_renderer_desc){ .width = 8, .height = 8 }, &r) == LIMEN_OK)
        CHECK(limen_renderer_set_viewport(r, 0, 0, 0, 8, 8) == LIMEN_ERR_UNSUPPORTED);
    limen_renderer_destroy(r);
}

/* The viewport follows a resized window: set_viewport, then frames of the new size. */
static void host_resize(void)
{
    limen_script *sc = check_load_script("scenes/portals.lua");
    if (!sc)
        return;
    limen_scene *s = limen_script_scene(sc);
    game g;
    CHECK_OK(game_create(&g, W, H, 8));
    limen_renderer *r = NULL;
    limen_renderer_desc d = { .backend = LIMEN_BACKEND_HOST, .width = W / 2, .height = H / 2,
                              .gl_loader = loader };
    CHECK_OK(limen_renderer_create(&d, &r));
    CHECK_OK(limen_render_frame(r, s, &(limen_render_opts){ .fill = LIMEN_FILL_PREVIOUS }, NULL));
    CHECK_OK(limen_renderer_set_viewport(r, 0, 0, 0, W, H));
    int w, h;
    limen_renderer_get_size(r, &w, &h);
    CHECK(w == W && h == H);
    CHECK_OK(limen_render_frame(r, s, NULL, NULL));
    CHECK(off_reference(&g, r, s, LIMEN_METHOD_STENCIL) == 0);
    limen_renderer_destroy(r);
    game_destroy(&g);
    limen_script_destroy(sc);
}

/* limen's own OSMesa context: after every call the game's context is current again, with
 * its buffer, and the game's GL still draws there; with none current before, none after. */
static void osmesa_leaves_context(void)
{
    limen_script *sc = check_load_script("scenes/portals.lua");
    if (!sc)
        return;
    game g;
    CHECK_OK(game_create(&g, 8, 8, 0));
    limen_renderer *r = NULL;
    CHECK_OK(limen_renderer_create(&(limen_renderer_desc){ .width = W, .height = H }, &r));
    CHECK(OSMesaGetCurrentContext() == g.ctx);
    CHECK_OK(limen_render_frame(r, limen_script_scene(sc), NULL, NULL));
    CHECK(OSMesaGetCurrentContext() == g.ctx);
    unsigned char *rgb = calloc(W * H * 3, 1);
    CHECK_OK(limen_renderer_read_rgb(r, rgb));
    CHECK(OSMesaGetCurrentContext() == g.ctx);
    GLint bw = 0, bh = 0, format = 0;
    void *buffer = NULL;
    CHECK(OSMesaGetColorBuffer(g.ctx, &bw, &bh, &format, &buffer) && buffer == g.buf && bw == 8);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    glDisable(GL_SCISSOR_TEST);
    glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
    glClearColor(0, 1, 0, 1);
    glClear(GL_COLOR_BUFFER_BIT);
    glFinish();
    CHECK(g.buf[0] == 0 && g.buf[1] == 255 && g.buf[2] == 0);
    limen_renderer_destroy(r);
    CHECK(OSMesaGetCurrentContext() == g.ctx);
    game_destroy(&g);
    CHECK(OSMesaGetCurrentContext() == NULL);
    CHECK_OK(limen_renderer_create(&(limen_renderer_desc){ .width = W, .height = H }, &r));
    CHECK_OK(limen_render_frame(r, limen_script_scene(sc), NULL, NULL));
    CHECK(OSMesaGetCurrentContext() == NULL);
    limen_renderer_destroy(r);
    free(rgb);
    limen_script_destroy(sc);
}

/* limen's own EGL context: the game's EGL context is current again after every call. */
static void egl_leaves_context(void)
{
    limen_script *sc = check_load_script("scenes/portals.lua");
    if (!sc)
        return;
    EGLDisplay dpy = eglGetPlatformDisplay(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY,
                                           NULL);
    CHECK(dpy != EGL_NO_DISPLAY && eglInitialize(dpy, NULL, NULL));
    CHECK(eglBindAPI(EGL_OPENGL_API));
    const EGLint attribs[] = { EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                               EGL_CONTEXT_OPENGL_PROFILE_MASK,
                               EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE };
    EGLContext mine = eglCreateContext(dpy, EGL_NO_CONFIG_KHR, EGL_NO_CONTEXT, attribs);
    CHECK(mine != EGL_NO_CONTEXT);
    CHECK(eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, mine));
    limen_renderer *r = NULL;
    limen_status st = limen_renderer_create(
        &(limen_renderer_desc){ .backend = LIMEN_BACKEND_EGL, .width = W, .height = H }, &r);
    CHECK_MSG(st == LIMEN_OK, "egl: %s", limen_renderer_error(r));
    CHECK(eglGetCurrentContext() == mine);
    if (!st) {
        CHECK_OK(limen_render_frame(r, limen_script_scene(sc), NULL, NULL));
        CHECK(eglGetCurrentContext() == mine);
        CHECK(eglQueryAPI() == EGL_OPENGL_API);
    }
    limen_renderer_destroy(r);
    CHECK(eglGetCurrentContext() == mine);
    eglMakeCurrent(dpy, EGL_NO_SURFACE, EGL_NO_SURFACE, EGL_NO_CONTEXT);
    eglDestroyContext(dpy, mine);
    limen_script_destroy(sc);
}

/* ------------------------------------------------------------------ contexts not limen's */

/* Objects of the game's own, many of each, so that the names limen uses in its context
 * (1, 2, 3, ...) are names of the game's too. */
#define MANY 48
typedef struct objects {
    GLuint prog[MANY], buf[MANY], vao[MANY], tex[MANY], fbo[MANY];
} objects;

static void objects_make(objects *o)
{
    for (int i = 0; i < MANY; i++)
        o->prog[i] = glCreateProgram();
    glGenBuffers(MANY, o->buf);
    glGenVertexArrays(MANY, o->vao);
    glGenTextures(MANY, o->tex);
    glGenFramebuffers(MANY, o->fbo);
    for (int i = 0; i < MANY; i++) {        /* a name is an object once bound */
        glBindBuffer(GL_ARRAY_BUFFER, o->buf[i]);
        glBindVertexArray(o->vao[i]);
        glBindTexture(GL_TEXTURE_2D, o->tex[i]);
        glBindFramebuffer(GL_FRAMEBUFFER, o->fbo[i]);
    }
    glBindBuffer(GL_ARRAY_BUFFER, 0);
    glBindVertexArray(0);
    glBindTexture(GL_TEXTURE_2D, 0);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
}

static int objects_missing(const objects *o)
{
    int missing = 0;
    for (int i = 0; i < MANY; i++)
        missing += !glIsProgram(o->prog[i]) + !glIsBuffer(o->buf[i]) +
                   !glIsVertexArray(o->vao[i]) + !glIsTexture(o->tex[i]) +
                   !glIsFramebuffer(o->fbo[i]);
    return missing;
}

/* A renderer made in the game's context A, called while the game's other context B is
 * current: the frame is refused and says why, nothing in B changes (its state, pixels,
 * objects, errors), and destroying the renderer there deletes none of B's objects. Back in
 * A the renderer draws, and that success clears the refusal's message. */
static void host_other_context(void)
{
    limen_script *sc = check_load_script("scenes/mirror_room.lua");
    if (!sc)
        return;
    limen_scene *s = limen_script_scene(sc);
    game a, b;
    CHECK_OK(game_create(&a, W, H, 8));
    CHECK_OK(game_create(&b, W, H, 8));
    limen_renderer_desc d = { .backend = LIMEN_BACKEND_HOST, .width = W, .height = H,
                              .gl_loader = loader };
    for (int round = 0; round < 2; round++) {
        CHECK_OK(game_current(&a));
        limen_renderer *r = NULL;
        CHECK_OK(limen_renderer_create(&d, &r));
        /* the texture method: targets, framebuffers and textures of limen's own in A */
        CHECK_OK(limen_render_frame(r, s, &(limen_render_opts){ .method = LIMEN_METHOD_TEXTURE },
                                    NULL));
        CHECK_OK(game_current(&b));
        objects o;
        objects_make(&o);
        glClearColor(0, 1, 0, 1);
        glClear(GL_COLOR_BUFFER_BIT);
        glFinish();
        CHECK(objects_missing(&o) == 0);
        odd_state(&b, 0);
        snapshot before, after;
        take(&before);
        if (round == 0) {
            limen_status st = limen_render_frame(r, s, NULL, NULL);
            CHECK(st != LIMEN_OK);
            CHECK_MSG(strstr(limen_renderer_error(r), "not the one this renderer was created in"),
                      "message: %s", limen_renderer_error(r));
            CHECK(limen_renderer_read_rgb(r, (unsigned char[W * H * 3]){ 0 }) != LIMEN_OK);
            CHECK(glGetError() == GL_NO_ERROR);
            take(&after);
            CHECK(same_state(&before, &after));
            glFinish();
            int touched = 0;
            for (int i = 0; i < W * H; i++)
                touched += b.buf[4 * i] != 0 || b.buf[4 * i + 1] != 255 || b.buf[4 * i + 2] != 0;
            CHECK_MSG(touched == 0, "%d of the game's pixels drawn over in its other context",
                      touched);
            /* back in A: it draws, and the old message is gone */
            CHECK_OK(game_current(&a));
            CHECK_OK(limen_render_frame(r, s, NULL, NULL));
            CHECK_MSG(limen_renderer_error(r)[0] == '\0', "after a good frame: %s",
                      limen_renderer_error(r));
            CHECK(off_reference(&a, r, s, LIMEN_METHOD_STENCIL) == 0);
            CHECK_OK(game_current(&b));
        }
        limen_renderer_destroy(r);      /* B current: limen's objects live in A */
        CHECK(glGetError() == GL_NO_ERROR);
        CHECK_MSG(objects_missing(&o) == 0, "%d of the game's objects deleted by limen",
                  objects_missing(&o));
        take(&after);
        CHECK(same_state(&before, &after));
        CHECK(OSMesaGetCurrentContext() == b.ctx);
    }
    game_destroy(&b);
    game_destroy(&a);
    limen_script_destroy(sc);
}

/* An OpenGL 2.1 context (Mesa's version override, set for a child process of this test
 * since Mesa reads it once) is refused by name and version, with no GL error left. */
static void host_old_context(void)
{
    if (getenv("LIMEN_TEST_OLD_GL")) {     /* the child: its context is 2.1 */
        OSMesaContext c = OSMesaCreateContextExt(OSMESA_RGBA, 24, 8, 0, NULL);
        unsigned char *buf = calloc(W * H, 4);
        CHECK(c && buf && OSMesaMakeCurrent(c, buf, GL_UNSIGNED_BYTE, W, H));
        CHECK_MSG(strncmp((const char *)glGetString(GL_VERSION), "2.1", 3) == 0, "version %s",
                  (const char *)glGetString(GL_VERSION));
        limen_renderer *r = NULL;
        limen_renderer_desc d = { .backend = LIMEN_BACKEND_HOST, .width = W, .height = H,
                                  .gl_loader = loader };
        CHECK(limen_renderer_create(&d, &r) == LIMEN_ERR_UNSUPPORTED);
        CHECK_MSG(strstr(limen_renderer_error(r), "needs OpenGL 3.3 core, this context is 2.1"),
                  "message: %s", limen_renderer_error(r));
        CHECK_MSG(glGetError() == GL_NO_ERROR, "a GL error left pending");
        limen_renderer_destroy(r);
        CHECK(glGetError() == GL_NO_ERROR);
        OSMesaMakeCurrent(NULL, NULL, GL_UNSIGNED_BYTE, 0, 0);
        OSMesaDestroyContext(c);
        free(buf);
        return;
    }
    extern char **environ;
    int n = 0;
    while (environ[n])
        n++;
    char **env = calloc((size_t)n + 3, sizeof *env);
    if (!env)
        return;
    memcpy(env, environ, sizeof *env * (size_t)n);
    env[n] = "MESA_GL_VERSION_OVERRIDE=2.1";
    env[n + 1] = "LIMEN_TEST_OLD_GL=1";
    char *argv[] = { "test_host", "host_old_context", NULL };
    pid_t pid;
    int status = -1;
    posix_spawn_file_actions_t fa;      /* the child's summary line is not this run's */
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
    CHECK(posix_spawn(&pid, "/proc/self/exe", &fa, NULL, argv, env) == 0 &&
          waitpid(pid, &status, 0) == pid);
    posix_spawn_file_actions_destroy(&fa);
    CHECK_MSG(WIFEXITED(status) && WEXITSTATUS(status) == 0, "the 2.1 context's run failed");
    free(env);
}

static const check_case cases[] = {
    { "host_frames", host_frames },
    { "host_without_stencil", host_without_stencil },
    { "host_errors", host_errors },
    { "host_resize", host_resize },
    { "osmesa_leaves_context", osmesa_leaves_context },
    { "egl_leaves_context", egl_leaves_context },
    { "host_other_context", host_other_context },
    { "host_old_context", host_old_context },
    { 0 },
};

int main(int argc, char **argv)
{
    return check_run(argc, argv, cases);
}
