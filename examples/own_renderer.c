/* own_renderer.c - a game that draws limen's draw list with OpenGL of its own.
 *
 * limen keeps the game's scene graph (nodes, mirrors, portals, moving through them) and hands
 * it, every frame, a draw list: commands in the order to run them, each with what to draw and
 * the pipeline state to draw it with (docs/DESIGN.md, "The draw list"). The game needs no plan
 * logic, clipping or sorting: it makes a context and limen's shading once (game_create), and
 * every frame builds the plan, the drawables and the list (game_frame), uploads the list's
 * lights, vertices and instances, then runs each command: its state, then one function per
 * op (game_draw). Meshes, unit shapes and images go up once, keyed on their id.
 * tests/test_example_game.c holds its frames to limen's own.
 *     make examples && build/examples/own_renderer scenes/portals.lua portals.png
 */
#define GL_GLEXT_PROTOTYPES
#include <GL/glcorearb.h>
#include <GL/osmesa.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "limen.h"

#define UNIFORMS(X) X(view_proj) X(clip) X(cut) X(scale) X(facets) X(eye) \
    X(albedo_b) X(cell) X(tint) X(ambient) X(textured) X(repeat) X(base) X(emissive) X(cutoff) \
    X(nlights) X(lights) X(flat)
#define U_FIELD(name) GLint name;
#define U_FIND(name) g->u.name = glGetUniformLocation(g->prog, "u_" #name);

typedef struct gpu { uint64_t id; GLuint vao, tex, ibo[16]; } gpu;   /* by id; ibo: levels */

typedef struct game {
    int w, h, ncache;
    OSMesaContext ctx;
    unsigned char token[64];            /* OSMesa wants a buffer; we draw into our FBO */
    PFNGLCLIPCONTROLPROC clip_control;  /* GL 4.5's, for LIMEN_DEPTH_ZO */
    GLuint fbo, prog, poly_vao, poly_vbo, inst_vbo;
    struct { UNIFORMS(U_FIELD) } u;
    gpu *cache;                         /* the meshes and images uploaded so far */
    limen_plan *plan; limen_drawables *draw; limen_drawlist *list;  /* limen's, per frame */
    const limen_drawable *items;        /* this frame's, and its list's passes */
    const limen_draw_pass *passes;
} game;

/* ============================================================ 1. shader */

#define GLSL(...) "#version 330 core\n" #__VA_ARGS__

static const char *vs_src = GLSL(
    layout(location = 0) in vec3 a_pos;   layout(location = 1) in vec3 a_nrm;
    layout(location = 2) in vec2 a_uv;    layout(location = 3) in vec4 a_col;
    layout(location = 4) in mat4 a_world; layout(location = 8) in vec3 a_albedo;
    uniform mat4 u_view_proj; uniform vec4 u_clip, u_cut;
    uniform vec3 u_scale;                           /* unit shape -> node-local units */
    out vec3 v_world, v_local, v_normal; out vec2 v_uv; out vec4 v_col; flat out vec3 v_albedo;
    void main() {
        vec4 w = a_world * vec4(a_pos, 1.0);
        v_world = w.xyz; v_local = a_pos * u_scale; v_uv = a_uv; v_col = a_col; v_albedo = a_albedo;
        v_normal = transpose(inverse(mat3(a_world))) * a_nrm;
        gl_ClipDistance[0] = dot(u_clip, w); gl_ClipDistance[1] = dot(u_cut, w);
        gl_Position = u_view_proj * w;
    });

static const char *fs_src = GLSL(
    in vec3 v_world, v_local, v_normal; in vec2 v_uv; in vec4 v_col; flat in vec3 v_albedo;
    uniform int u_facets, u_textured, u_nlights, u_flat;
    uniform vec3 u_eye, u_albedo_b, u_tint, u_emissive;
    uniform vec4 u_lights[16];                  /* limen_draw_light: pos, 1/range^2; colour */
    uniform float u_cell, u_ambient, u_cutoff;
    uniform vec4 u_base; uniform vec2 u_repeat; uniform sampler2D u_tex;
    out vec4 o_color;
    void main() {
        if (u_flat != 0) { o_color = vec4(v_albedo, 1.0); return; }  /* a POLYGON's */
        vec3 n = normalize(u_facets != 0 ? cross(dFdx(v_world), dFdy(v_world)) : v_normal);
        if (dot(n, u_eye - v_world) < 0.0) n = -n;  /* two-sided: face the eye */
        vec3 albedo = v_albedo * u_base.rgb * v_col.rgb, c = floor(v_local / u_cell);
        float alpha = u_base.a * v_col.a, k = c.x + c.y + c.z;
        if (u_cell > 0.0 && k - 2.0 * floor(k * 0.5) > 0.5) albedo = u_albedo_b;
        if (u_textured != 0) {                      /* rows went up top first */
            vec4 t = texture(u_tex, vec2(0.0, 1.0) + vec2(1.0, -1.0) * v_uv * u_repeat);
            albedo *= t.rgb; alpha *= t.a;
        }
        if (alpha < u_cutoff) discard;
        vec3 light = vec3(0.0);
        for (int i = 0; i < u_nlights; i++) {       /* w: a light's falloff with its range */
            vec3 d = u_lights[2 * i].xyz - v_world;
            float q = dot(d, d) * u_lights[2 * i].w, w = clamp(1.0 - q * q, 0.0, 1.0);
            light += u_lights[2 * i + 1].rgb * w * w * max(0.0, dot(n, normalize(d)));
        }
        vec3 lit = clamp(albedo * (u_ambient + (1.0 - u_ambient) * light), 0.0, 1.0);
        o_color = vec4(clamp(lit + u_emissive, 0.0, 1.0) * u_tint, alpha);
    });

static GLuint program(const char *vs, const char *fs)
{
    GLint ok = 0;
    GLuint prog = glCreateProgram();
    for (int i = 0; i < 2; i++) {
        GLuint sh = glCreateShader(i ? GL_FRAGMENT_SHADER : GL_VERTEX_SHADER);
        glShaderSource(sh, 1, i ? &fs : &vs, NULL), glCompileShader(sh);
        glAttachShader(prog, sh), glDeleteShader(sh);       /* goes with the program */
    }
    glLinkProgram(prog), glGetProgramiv(prog, GL_LINK_STATUS, &ok);
    return ok ? prog : 0;
}

static int programs_create(game *g)
{
    if (!(g->prog = program(vs_src, fs_src)))
        return -1;
    UNIFORMS(U_FIND)
    glUseProgram(g->prog);
    glVertexAttrib4f(3, 1, 1, 1, 1);            /* the colour of vertices without one */
    glBlendFunc(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA);
    return 0;
}

/* ============================================================ 2. meshes, images, context */

/* The GPU copy of what has this id, or a new zeroed entry (*fresh); NULL out of memory. */
static gpu *cached(game *g, uint64_t id, int *fresh)
{
    for (int i = 0; i < g->ncache; i++)
        if (g->cache[i].id == id)
            return *fresh = 0, &g->cache[i];
    gpu *grown = realloc(g->cache, sizeof *grown * (size_t)(g->ncache + 1));
    if (!grown)
        return NULL;
    g->cache = grown, *fresh = 1;
    return memset(&grown[g->ncache++], 0, sizeof *grown);
}

/* A mesh on the GPU: an attribute per array it has (one it lacks keeps its constant: uv 0,
 * colour white), each level's indices a buffer of its own. */
static const gpu *mesh_upload(game *g, const limen_mesh_geometry *m)
{
    const float *data[4] = { m->positions, m->normals, m->uvs, m->colors };
    static const int size[4] = { 3, 3, 2, 4 };
    int fresh;
    gpu *c = cached(g, m->id, &fresh);
    GLuint buf;
    if (!c || !fresh)
        return c;
    glGenVertexArrays(1, &c->vao), glBindVertexArray(c->vao);
    for (GLuint a = 0; a < 4; a++) {
        if (!data[a])
            continue;
        glGenBuffers(1, &buf), glBindBuffer(GL_ARRAY_BUFFER, buf);
        glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)sizeof(float) * size[a] * m->vertex_count,
                     data[a], GL_STATIC_DRAW);
        glEnableVertexAttribArray(a), glVertexAttribPointer(a, size[a], GL_FLOAT, 0, 0, NULL);
    }
    glGenBuffers(m->lod_count < 16 ? m->lod_count : 16, c->ibo);
    for (int k = 0; k < m->lod_count && k < 16; k++)
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, c->ibo[k]),
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)sizeof(GLuint) * 3 *
                     m->lods[k].triangle_count, m->lods[k].indices, GL_STATIC_DRAW);
    return c;
}

/* An image on the GPU with limen's own mipmap levels (so that the texels are the tracer's),
 * repeating; with alpha (a material's) RGBA. 0 if out of memory. */
static GLuint image_upload(game *g, const limen_image *im)
{
    int fresh, n = im->width * im->height;
    gpu *c = cached(g, im->id, &fresh);
    if (!c || !fresh)
        return c ? c->tex : 0;
    unsigned char *rgba = im->alpha ? malloc(4 * (size_t)n) : NULL;
    for (int i = 0; rgba && i < n; i++)
        memcpy(rgba + 4 * i, im->rgb + 3 * i, 3), rgba[4 * i + 3] = im->alpha[i];
    glGenTextures(1, &c->tex), glBindTexture(GL_TEXTURE_2D, c->tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    for (int k = 0; k < im->level_count; k++)   /* (an image with alpha has one level) */
        glTexImage2D(GL_TEXTURE_2D, k, rgba ? GL_RGBA8 : GL_RGB8, im->levels[k].width,
                     im->levels[k].height, 0, rgba ? GL_RGBA : GL_RGB, GL_UNSIGNED_BYTE,
                     rgba ? rgba : im->levels[k].rgb);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, im->level_count - 1);
    free(rgba);
    return c->tex;
}

/* (Destroying the context, NULL or not, deletes every GL object the game made in it.) */
static void game_destroy(game *g)
{
    OSMesaDestroyContext(g->ctx);
    limen_plan_destroy(g->plan), limen_drawables_destroy(g->draw);
    limen_drawlist_destroy(g->list), free(g->cache), free(g);
}

static int make_current(game *g)
{
    return OSMesaMakeCurrent(g->ctx, g->token, GL_UNSIGNED_BYTE, 4, 4) ? 0 : -1;
}

static game *game_create(int w, int h)
{
    game *g = calloc(1, sizeof *g);
    const int attribs[] = { OSMESA_FORMAT, OSMESA_RGBA, OSMESA_DEPTH_BITS, 0,
                            OSMESA_STENCIL_BITS, 0, OSMESA_PROFILE, OSMESA_CORE_PROFILE,
                            OSMESA_CONTEXT_MAJOR_VERSION, 4, OSMESA_CONTEXT_MINOR_VERSION, 5, 0 };
    if (g && (g->ctx = OSMesaCreateContextAttribs(attribs, NULL)))
        g->clip_control = (PFNGLCLIPCONTROLPROC)OSMesaGetProcAddress("glClipControl");
    if (!g || !g->clip_control || make_current(g) || programs_create(g) ||
        limen_plan_create(&g->plan) || limen_drawables_create(&g->draw) ||
        limen_drawlist_create(&g->list)) {
        if (g)
            game_destroy(g);
        return NULL;
    }
    g->w = w, g->h = h;
    GLuint rb[2];                               /* the frame: colour, depth and stencil */
    glGenRenderbuffers(2, rb), glGenFramebuffers(1, &g->fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo);
    for (int i = 0; i < 2; i++) {
        glBindRenderbuffer(GL_RENDERBUFFER, rb[i]);
        glRenderbufferStorage(GL_RENDERBUFFER, i ? GL_DEPTH24_STENCIL8 : GL_RGBA8, w, h);
        glFramebufferRenderbuffer(GL_FRAMEBUFFER, i ? GL_DEPTH_STENCIL_ATTACHMENT
                                                    : GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, rb[i]);
    }
    glGenVertexArrays(1, &g->poly_vao), glBindVertexArray(g->poly_vao);
    glGenBuffers(1, &g->poly_vbo), glBindBuffer(GL_ARRAY_BUFFER, g->poly_vbo);
    glEnableVertexAttribArray(0), glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 0, NULL);
    glGenBuffers(1, &g->inst_vbo), glEnable(GL_CLIP_DISTANCE0), glEnable(GL_CLIP_DISTANCE1);
    return g;
}

/* ============================================================ 3. one function per op */

/* A command's pipeline state, and its pass's camera. */
static void set_state(game *g, const limen_draw_state *s, const limen_draw_pass *p)
{
    static const GLenum compare[LIMEN_COMPARE_COUNT] = { GL_ALWAYS, GL_LESS, GL_LEQUAL,
                                                         GL_EQUAL, GL_GREATER, GL_GEQUAL };
    static const GLenum stencil_op[LIMEN_STENCIL_OP_COUNT] = { GL_KEEP, GL_INVERT, GL_DECR };
    static const GLenum caps[4] = { GL_DEPTH_CLAMP, GL_CULL_FACE, GL_BLEND, GL_STENCIL_TEST };
    static const float keep_all[4] = { 0, 0, 0, 1 };
    const int on[4] = { s->depth_clamp, s->cull_back, s->blend, s->stencil_test };
    for (int i = 0; i < 4; i++)
        (on[i] ? glEnable : glDisable)(caps[i]);
    glScissor(s->scissor[0], s->scissor[1], s->scissor[2], s->scissor[3]);
    glColorMask(s->color_write, s->color_write, s->color_write, s->color_write);
    glDepthMask(s->depth_write), glDepthFunc(compare[s->depth_test]);
    glStencilFunc(GL_EQUAL, s->stencil_ref, 0xFF), glStencilMask(s->stencil_write_mask);
    glStencilOp(GL_KEEP, GL_KEEP, stencil_op[s->stencil_pass]);
    /* both clip distances stay on (game_create): a plane that is off keeps all */
    glUniform4fv(g->u.clip, 1, s->clip_on ? s->clip : keep_all);
    glUniform4fv(g->u.cut, 1, s->cut_on ? s->cut : keep_all);
    glFrontFace(p->front_cw ? GL_CW : GL_CCW);
    glUniformMatrix4fv(g->u.view_proj, 1, GL_FALSE, p->view_proj);
    glUniform3fv(g->u.eye, 1, p->eye), glUniform3fv(g->u.tint, 1, p->tint);
}

/* Within the scissor, what the state's masks let through: depth (far), colour, stencil (0). */
static void op_clear(game *g, const limen_draw_cmd *c)
{
    glClearColor(c->color[0], c->color[1], c->color[2], 1.0f);
    glClear(GL_DEPTH_BUFFER_BIT | GL_COLOR_BUFFER_BIT | GL_STENCIL_BUFFER_BIT);
}

/* A fan in normalized device coordinates (world and camera the identity), flat colour. */
static void op_polygon(game *g, const limen_draw_cmd *c)
{
    static const float id[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
    for (GLuint col = 0; col < 4; col++)
        glVertexAttrib4fv(4 + col, id + 4 * col);
    glVertexAttrib3fv(8, c->color), glUniformMatrix4fv(g->u.view_proj, 1, GL_FALSE, id);
    glUniform1i(g->u.flat, 1), glBindVertexArray(g->poly_vao);
    glDrawArrays(GL_TRIANGLE_FAN, c->first, c->count), glUniform1i(g->u.flat, 0);
}

/* What a drawable's shading takes besides its colour: checker, texture (im: NULL none). */
static void use_item(game *g, const limen_drawable *d, const limen_image *im)
{
    GLuint tex = im ? image_upload(g, im) : 0;
    int f = d->texture_filter;
    glUniform3fv(g->u.albedo_b, 1, d->checker), glUniform1f(g->u.cell, d->cell);
    glUniform1i(g->u.textured, tex != 0), glUniform2fv(g->u.repeat, 1, d->texture_repeat);
    glBindTexture(GL_TEXTURE_2D, tex);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, f == LIMEN_FILTER_NEAREST ? GL_NEAREST
                    : f == LIMEN_FILTER_LINEAR ? GL_LINEAR : GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER,
                    f == LIMEN_FILTER_NEAREST ? GL_NEAREST : GL_LINEAR);
}

/* SHAPE and MESHES alike: `count` list instances from `first` (world matrix, albedo) of a
 * geometry at level `lod`: a mesh's, its opaque or its blended parts, each in its material
 * (base colour and texture, alpha mask, emission); or the unit shape of the drawable's kind
 * (limen_unit_geometry: one white part, its uvs the kind's) with its stretch `scale` for
 * the local point (the checker's). */
static void op_draw(game *g, const limen_draw_cmd *c)
{
    static const float one[3] = { 1, 1, 1 };
    const limen_drawable *d = &g->items[c->item];
    int shape = c->op == LIMEN_DRAW_SHAPE;
    const limen_mesh_geometry *m = shape ? limen_unit_geometry(limen_kind_get(d->kind)->unit)
                                         : d->mesh;
    int lod = m && c->lod < m->lod_count && c->lod < 16 ? c->lod : 0;
    if (!shape && m && m->lods[lod].baked && !d->texture)
        m = m->lods[lod].baked, lod = 0;        /* a level with a texture of its own */
    const gpu *gm = m ? mesh_upload(g, m) : NULL;
    if (!gm)
        return;
    GLuint ibo = gm->ibo[lod];                  /* (an image's upload may move the cache) */
    glBindVertexArray(gm->vao), glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ibo);
    glBindBuffer(GL_ARRAY_BUFFER, g->inst_vbo);
    for (GLuint a = 4; a < 9; a++) {            /* world matrix columns, albedo */
        glEnableVertexAttribArray(a), glVertexAttribDivisor(a, 1);
        glVertexAttribPointer(a, a < 8 ? 4 : 3, GL_FLOAT, GL_FALSE, sizeof(limen_draw_instance),
                              (void *)(sizeof(limen_draw_instance) * (size_t)c->first +
                                       sizeof(float) * 4 * (a - 4)));
    }
    glUniform3fv(g->u.scale, 1, shape ? c->scale : one);
    glUniform1i(g->u.facets, !shape && !d->smooth);
    const limen_mesh_part *parts = m->lods[lod].parts ? m->lods[lod].parts : m->parts;
    for (int p = 0; p < m->part_count; p++) {
        const limen_material *mt = &m->materials[parts[p].material];
        if ((mt->alpha_mode == LIMEN_ALPHA_BLEND) != (c->parts == LIMEN_PARTS_BLENDED))
            continue;
        use_item(g, d, d->texture ? d->texture : mt->base_texture);
        glUniform4fv(g->u.base, 1, mt->base_color), glUniform3fv(g->u.emissive, 1, mt->emissive);
        glUniform1f(g->u.cutoff, mt->alpha_mode == LIMEN_ALPHA_MASK ? mt->alpha_cutoff : -1);
        glDrawElementsInstanced(GL_TRIANGLES, 3 * parts[p].triangle_count, GL_UNSIGNED_INT,
                                (void *)(sizeof(GLuint) * 3 * parts[p].first_triangle), c->count);
    }
}

/* ============================================================ 4. one frame */

/* Runs commands cmd[0 .. n) of the built list in order; rgb (w*h*3, top row first) gets
 * the frame. The context is made current first (a test runs limen's renderer beside it). */
static int game_draw(game *g, const limen_draw_cmd *cmd, int n, limen_depth_range range,
                     unsigned char *rgb)
{
    static void (*const op[LIMEN_DRAW_OP_COUNT])(game *, const limen_draw_cmd *) = {
        NULL, op_clear, op_polygon, op_draw, op_draw, NULL  /* no TARGET (stencil); FLUSH: a hint */
    };
    if (make_current(g) || range == LIMEN_DEPTH_ZO_REVERSED)
        return -1;      /* (reversed depth would want a float depth buffer) */
    g->clip_control(GL_LOWER_LEFT, range ? GL_ZERO_TO_ONE : GL_NEGATIVE_ONE_TO_ONE);
    const limen_draw_light *l;                  /* the frame's lights, vertices, instances */
    const float (*v)[3];
    const limen_draw_instance *inst;
    float ambient;
    int nl = limen_drawlist_lights(g->list, &l, &ambient);
    int nv = limen_drawlist_vertices(g->list, &v), ni = limen_drawlist_instances(g->list, &inst);
    glUseProgram(g->prog), glUniform1i(g->u.nlights, nl), glUniform1f(g->u.ambient, ambient);
    glUniform4fv(g->u.lights, 2 * nl, l->pos);
    glBindBuffer(GL_ARRAY_BUFFER, g->poly_vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)sizeof *v * nv, v, GL_STREAM_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, g->inst_vbo);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)sizeof *inst * ni, inst, GL_STREAM_DRAW);
    limen_drawlist_passes(g->list, &g->passes), limen_drawables_items(g->draw, &g->items);
    glBindFramebuffer(GL_FRAMEBUFFER, g->fbo), glViewport(0, 0, g->w, g->h);
    glEnable(GL_DEPTH_TEST), glEnable(GL_SCISSOR_TEST);
    for (int i = 0; i < n; i++)
        if (op[cmd[i].op])
            set_state(g, &cmd[i].state, &g->passes[cmd[i].pass]), op[cmd[i].op](g, &cmd[i]);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    for (int y = 0; y < g->h; y++)              /* OpenGL's rows run bottom-up */
        glReadPixels(0, g->h - 1 - y, g->w, 1, GL_RGB, GL_UNSIGNED_BYTE, rgb + 3 * g->w * y);
    return glGetError() == GL_NO_ERROR ? 0 : -1;
}

/* Plans scene s for this game's size and depth range, lists the frame's commands for the
 * stencil method (one framebuffer; the game keeps no previous frame) and draws them. */
static int game_frame(game *g, limen_scene *s, limen_depth_range range, limen_clip_method clip,
                      unsigned char *rgb)
{
    limen_plan_desc pd = { .width = g->w, .height = g->h, .range = range, .limits.clip = clip };
    limen_drawlist_desc dd = { .width = g->w, .height = g->h, .method = LIMEN_METHOD_STENCIL,
                               .range = range, .limits = pd.limits };
    const limen_draw_cmd *cmd;
    if (limen_plan_build(g->plan, s, &pd) || limen_drawables_build(g->draw, s))
        return fprintf(stderr, "  plan: %s\n", limen_scene_error(s)), -1;
    if (limen_drawlist_build(g->list, g->plan, g->draw, &dd))
        return fprintf(stderr, "  draw list: %s\n", limen_drawlist_error(g->list)), -1;
    return game_draw(g, cmd, limen_drawlist_commands(g->list, &cmd), range, rgb);
}

#ifndef LIMEN_EXAMPLE_NO_MAIN
/* own_renderer SCENE.lua OUT.png [WxH]: one frame of the scene, drawn by the game. */
int main(int argc, char **argv)
{
    int w = 640, h = 480, rc = 1;
    limen_script *sc = NULL;
    if (argc < 3 || (argc > 3 && sscanf(argv[3], "%dx%d", &w, &h) != 2) || w < 1 || h < 1)
        return fprintf(stderr, "usage: own_renderer SCENE.lua OUT.png [WxH]\n"), 2;
    game *g = limen_script_load(argv[1], NULL, &sc) ? NULL : game_create(w, h);
    unsigned char *rgb = malloc((size_t)w * (size_t)h * 3);
    if (g && rgb)                               /* (limen_write_png writes whole or not) */
        rc = game_frame(g, limen_script_scene(sc), LIMEN_DEPTH_NO, LIMEN_CLIP_OBLIQUE, rgb) ||
             limen_write_png(argv[2], w, h, rgb);
    if (rc)
        fprintf(stderr, "own_renderer: cannot draw %s (%s)\n", argv[1],
                sc ? limen_script_error(sc) : "no script");
    if (g)
        game_destroy(g);
    free(rgb), limen_script_destroy(sc);
    return rc;
}
#endif
