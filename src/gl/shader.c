/* shader.c - the programs that shade things: one source, compiled into variants that each
 * hold only what a draw needs (lit, flat or textured; the mesh's normals or the true
 * sphere's or cylinder's or a smooth mesh's; checker or not; an albedo texture or not; how
 * many lights, and whether they have ranges; which clip distances). llvmpipe
 * runs every branch of a shader under a mask, so an all-purpose program pays for the paths
 * a draw does not take; a variant pays for its own. Variants are compiled on first use. The
 * values every variant reads (the view's matrix, eye, planes and tint, the lights) are kept
 * here and uploaded to a variant when it is bound after they changed. */
#include <stdio.h>
#include <string.h>

#include "gl/gl_internal.h"

static const char *vs_body =
    "#if EXACT\n"    /* the fragment shader takes them as e_* and divides by v_one */
    "#define v_world e_world\n"
    "#define v_local e_local\n"
    "#define v_nrm e_nrm\n"
    "#define v_uv e_uv\n"
    "#define v_col e_col\n"
    "#endif\n"
    "layout(location = 0) in vec3 a_pos;\n"
    "layout(location = 1) in vec3 a_nrm;\n"
    "#if TEXTURED == 3\n"
    "layout(location = 2) in vec2 a_uv;\n"
    "out vec2 v_uv;\n"
    "#endif\n"
    "#if MATERIAL\n"
    "layout(location = 11) in vec4 a_col;\n"
    "out vec4 v_col;\n"
    "#endif\n"
    "uniform mat4 u_model, u_view_proj;\n"
    "uniform vec4 u_clip_plane, u_clip_plane2;\n"
    "uniform mat3 u_normal_mat;\n"
    "out vec3 v_world, v_local, v_nrm;\n"
    "flat out vec3 v_face;\n"
    "#if EXACT\n"
    "out float v_one;\n"
    "#endif\n"
    "#if INSTANCED\n"
    "layout(location = 3) in mat4 i_model;\n"
    "layout(location = 7) in mat3 i_normal_mat;\n"
    "layout(location = 10) in vec3 i_albedo;\n"
    "flat out mat3 v_normal_mat;\n"
    "flat out vec3 v_albedo;\n"
    "#define MODEL i_model\n"
    "#define NORMAL_MAT i_normal_mat\n"
    "#else\n"
    "#define MODEL u_model\n"
    "#define NORMAL_MAT u_normal_mat\n"
    "#endif\n"
    "void main() {\n"
    "    vec4 w = MODEL * vec4(a_pos, 1.0);\n"
    "    v_world = w.xyz; v_local = a_pos; v_nrm = a_nrm;\n"
    "#if EXACT\n"
    "    v_one = w.w;\n"
    "#endif\n"
    "#if INSTANCED\n"
    "    v_normal_mat = i_normal_mat; v_albedo = i_albedo;\n"
    "#endif\n"
    "#if TEXTURED == 3\n"
    "    v_uv = a_uv;\n"
    "#endif\n"
    "#if MATERIAL\n"
    "    v_col = a_col;\n"
    "#endif\n"
    "#if MODE == 0 && SHAPE == 0\n"
    "    v_face = normalize(NORMAL_MAT * a_nrm);\n"
    "#endif\n"
    "#if CLIP0\n"
    "    gl_ClipDistance[0] = dot(u_clip_plane, w);\n"
    "#endif\n"
    "#if CLIP1\n"
    "    gl_ClipDistance[1] = dot(u_clip_plane2, w);\n"
    "#endif\n"
    "    gl_Position = u_view_proj * w;\n"
    "}\n";

/* MODE 0 lit, 1 flat, 2 textured. The normal comes from the true shape where it is curved
 * (SHAPE 1 sphere, 2 cylinder side), so that shading does not depend on the tessellation,
 * or from a smooth mesh's vertex normals (SHAPE 3). CHECKER 1: cells in x + y (quads), 2: in
 * x + y + z. TEXTURED: albedo times the texel at a plane's unit point (1), a box face's two
 * other axes (2) or the mesh's coordinates (3). RANGE: each light weighted by
 * clamp(1 - (d/R)^4, 0, 1)^2, from 1/R^2 (0 for a light without a range: weight 1). */
static const char *fs_body =
    "#if EXACT\n"
    "in vec3 e_world, e_local, e_nrm;\n"
    "in float v_one;\n"
    "vec3 v_world, v_local, v_nrm;\n"
    "#else\n"
    "in vec3 v_world, v_local, v_nrm;\n"
    "#endif\n"
    "flat in vec3 v_face;\n"
    "uniform mat3 u_normal_mat;\n"
    "uniform vec3 u_eye, u_albedo, u_albedo_b, u_scale, u_tint;\n"
    "#if INSTANCED\n"
    "flat in mat3 v_normal_mat;\n"
    "flat in vec3 v_albedo;\n"
    "#define NORMAL_MAT v_normal_mat\n"
    "#define ALBEDO v_albedo\n"
    "#else\n"
    "#define NORMAL_MAT u_normal_mat\n"
    "#define ALBEDO u_albedo\n"
    "#endif\n"
    "uniform float u_cell, u_ambient;\n"
    "#if NLIGHTS > 0\n"
    "uniform vec3 u_light_pos[NLIGHTS], u_light_col[NLIGHTS];\n"
    "#if RANGE\n"
    "uniform float u_light_inv_r2[NLIGHTS];\n"
    "#endif\n"
    "#endif\n"
    "#if TEXTURED\n"
    "uniform sampler2D u_albedo_tex;\n"
    "uniform vec2 u_uv_repeat;\n"            /* limen_node_set_texture_repeat */
    "#endif\n"
    "#if TEXTURED == 3 && EXACT\n"
    "in vec2 e_uv;\n"
    "vec2 v_uv;\n"
    "#elif TEXTURED == 3\n"
    "in vec2 v_uv;\n"
    "#endif\n"
    "#if MATERIAL && EXACT\n"
    "in vec4 e_col;\n"
    "vec4 v_col;\n"
    "#elif MATERIAL\n"
    "in vec4 v_col;\n"
    "#endif\n"
    "#if MATERIAL\n"
    "uniform vec4 u_base;\n"                 /* the part's base colour factor, RGBA */
    "uniform vec3 u_emissive;\n"
    "uniform float u_cutoff;\n"              /* mask: below it nothing is drawn (-1: none) */
    "uniform int u_emissive_on, u_blend;\n"  /* an emissive texture on unit 2; blended */
    "uniform sampler2D u_emissive_tex;\n"
    "#endif\n"
    "#if MODE == 3\n"
    "uniform sampler2DMS u_tex;\n"
    "#else\n"
    "uniform sampler2D u_tex;\n"
    "#endif\n"
    "uniform vec4 u_tex_map;\n"
    "out vec4 o_color;\n"
    "void main() {\n"
    "#if EXACT\n"
    "    float one = 1.0 / v_one;\n"
    "    v_world = e_world * one; v_local = e_local * one; v_nrm = e_nrm * one;\n"
    "#if TEXTURED == 3\n"
    "    v_uv = e_uv * one;\n"
    "#endif\n"
    "#if MATERIAL\n"
    "    v_col = e_col * one;\n"
    "#endif\n"
    "#endif\n"
    "#if MODE == 1\n"
    "    o_color = vec4(u_albedo TINTED, 1.0);\n"
    "#elif MODE == 2\n"
    "    vec2 uv = gl_FragCoord.xy * u_tex_map.xy + u_tex_map.zw;\n"
    "    o_color = vec4(texture(u_tex, uv).rgb * u_albedo, 1.0);\n"
    "#elif MODE == 3\n"
    "    ivec2 px = ivec2(floor((gl_FragCoord.xy * u_tex_map.xy + u_tex_map.zw) *\n"
    "                           vec2(textureSize(u_tex))));\n"
    "    o_color = vec4(texelFetch(u_tex, px, gl_SampleID).rgb * u_albedo, 1.0);\n"
    "#else\n"
    "#if SHAPE == 1\n"
    "    vec3 nl = v_local;\n"
    "#elif SHAPE == 2\n"
    "    vec3 nl = abs(v_nrm.y) < 0.5 ? vec3(v_local.x, 0.0, v_local.z) : v_nrm;\n"
    "#endif\n"
    "#if SHAPE == 0\n"
    "    vec3 n = v_face;\n"
    "#elif SHAPE == 3\n"
    "    vec3 n = normalize(NORMAL_MAT * v_nrm);\n"
    "#else\n"
    "    vec3 n = normalize(NORMAL_MAT * nl);\n"
    "#endif\n"
    "    if (dot(n, u_eye - v_world) < 0.0) n = -n;\n"
    "    vec3 albedo = ALBEDO;\n"
    "#if CHECKER\n"
    "    vec3 c = floor(v_local * u_scale / u_cell);\n"
    "#if CHECKER == 1\n"
    "    float k = c.x + c.y;\n"
    "#else\n"
    "    float k = c.x + c.y + c.z;\n"
    "#endif\n"
    "    if (k - 2.0 * floor(k * 0.5) > 0.5) albedo = u_albedo_b;\n"
    "#endif\n"
    "#if TEXTURED == 1\n"
    "    albedo *= texture(u_albedo_tex, (v_local.xy + 0.5) * u_uv_repeat).rgb;\n"
    "#elif TEXTURED == 2\n"
    "    vec3 ax = abs(v_nrm);\n"
    "    vec2 uv = (ax.x > 0.5 ? v_local.yz : ax.y > 0.5 ? v_local.zx : v_local.xy) + 0.5;\n"
    "    albedo *= texture(u_albedo_tex, uv * u_uv_repeat).rgb;\n"
    "#elif TEXTURED == 3 && !MATERIAL\n"
    "    albedo *= texture(u_albedo_tex, v_uv * u_uv_repeat).rgb;\n"
    "#endif\n"
    "#if MATERIAL\n"
    "    float alpha = u_base.a * v_col.a;\n"
    "    albedo *= u_base.rgb * v_col.rgb;\n"
    "#if TEXTURED == 3\n"
    "    vec4 tx = texture(u_albedo_tex, v_uv * u_uv_repeat);\n"
    "    albedo *= tx.rgb;\n"
    "    alpha *= tx.a;\n"
    "#endif\n"
    "    if (alpha < u_cutoff) discard;\n"
    "    vec3 glow = u_emissive;\n"
    "#if TEXTURED == 3\n"
    "    if (u_emissive_on != 0) glow *= texture(u_emissive_tex, v_uv * u_uv_repeat).rgb;\n"
    "#endif\n"
    "#endif\n"
    "    vec3 light = vec3(0.0);\n"
    "#if NLIGHTS > 0\n"
    "    for (int i = 0; i < NLIGHTS; i++) {\n"
    "        vec3 l = u_light_pos[i] - v_world;\n"
    "#if RANGE\n"
    "        float q = dot(l, l) * u_light_inv_r2[i];\n"
    "        float w = max(0.0, 1.0 - q * q);\n"
    "        light += u_light_col[i] * (w * w) * max(0.0, dot(n, normalize(l)));\n"
    "#else\n"
    "        light += u_light_col[i] * max(0.0, dot(n, normalize(l)));\n"
    "#endif\n"
    "    }\n"
    "#endif\n"
    "    vec3 c3 = clamp(albedo * (u_ambient + (1.0 - u_ambient) * light), 0.0, 1.0);\n"
    "#if MATERIAL\n"
    "    c3 = clamp(c3 + glow, 0.0, 1.0);\n"
    "    o_color = vec4(c3 TINTED, u_blend != 0 ? alpha : 1.0);\n"
    "#else\n"
    "    o_color = vec4(c3 TINTED, 1.0);\n"
    "#endif\n"
    "#endif\n"
    "}\n";

/* Whether a shader compiled (or a program linked); if not, its log goes into the message. */
static bool built(limen_renderer *r, GLuint obj, bool program)
{
    GLint ok = 0;
    char log[400] = "";
    if (program)
        GL(GetProgramiv)(obj, GL_LINK_STATUS, &ok);
    else
        GL(GetShaderiv)(obj, GL_COMPILE_STATUS, &ok);
    if (ok)
        return true;
    if (program)
        GL(GetProgramInfoLog)(obj, sizeof log, NULL, log);
    else
        GL(GetShaderInfoLog)(obj, sizeof log, NULL, log);
    limen__rfail(r, LIMEN_ERR_GL, "shader %s failed: %s", program ? "link" : "compile", log);
    return false;
}

static GLuint compile(limen_renderer *r, GLenum type, const char *head, const char *body)
{
    GLuint sh = GL(CreateShader)(type);
    const char *src[2] = { head, body };
    GL(ShaderSource)(sh, 2, src, NULL);
    GL(CompileShader)(sh);
    if (built(r, sh, false))
        return sh;
    GL(DeleteShader)(sh);
    return 0;
}

GLuint limen__gl_link(limen_renderer *r, const char *head, const char *vsrc, const char *fsrc)
{
    GLuint vs = compile(r, GL_VERTEX_SHADER, head, vsrc);
    GLuint fs = vs ? compile(r, GL_FRAGMENT_SHADER, head, fsrc) : 0;
    if (!vs || !fs) {
        if (vs)
            GL(DeleteShader)(vs);
        return 0;
    }
    GLuint prog = GL(CreateProgram)();
    GL(AttachShader)(prog, vs);
    GL(AttachShader)(prog, fs);
    GL(LinkProgram)(prog);
    GL(DeleteShader)(vs);
    GL(DeleteShader)(fs);
    if (built(r, prog, true))
        return prog;
    GL(DeleteProgram)(prog);
    return 0;
}

/* key: mode (2 bits), shape (2), checker (2), lights (4), clip distances 0 and 1 (1 each),
 * tint (1: the view's tint is not white; multiplying by 1 changes no colour), texture
 * coordinates (2), light ranges (1), instanced (1: model, normal matrix and albedo per
 * instance, gl/batch.c), material (1), exact (1: every sample shaded, EXACT above) */
static unsigned variant_key(int mode, int shape, int checker, int nlights, bool clip0, bool clip1,
                            bool tint, int textured, bool ranged, bool instanced, bool material,
                            bool exact)
{
    if (mode != LIMEN__MODE_LIT)
        shape = checker = nlights = textured = instanced = material = exact = 0;
    if (!nlights)
        ranged = false;
    return (unsigned)mode | (unsigned)shape << 2 | (unsigned)checker << 4 |
           (unsigned)nlights << 6 | (unsigned)clip0 << 10 | (unsigned)clip1 << 11 |
           (unsigned)tint << 12 | (unsigned)textured << 13 | (unsigned)ranged << 15 |
           (unsigned)instanced << 16 | (unsigned)material << 17 | (unsigned)exact << 18;
}

static limen__variant *variant_build(limen_renderer *r, unsigned key)
{
    if (r->nvariants == LIMEN__MAX_VARIANTS) {
        limen__rfail(r, LIMEN_ERR_GL, "more than %d shader variants", LIMEN__MAX_VARIANTS);
        return NULL;
    }
    char head[480];
    snprintf(head, sizeof head,
             "#version 330 core\n%s#define MODE %u\n#define SHAPE %u\n#define CHECKER %u\n"
             "#define NLIGHTS %u\n#define CLIP0 %u\n#define CLIP1 %u\n#define TINTED %s\n"
             "#define TEXTURED %u\n#define RANGE %u\n#define INSTANCED %u\n#define MATERIAL %u\n"
             "#define EXACT %u\n",
             (key & 3) == LIMEN__MODE_SAMPLES ? "#extension GL_ARB_sample_shading : require\n"
                                              : "",
             key & 3, key >> 2 & 3, key >> 4 & 3, key >> 6 & 15, key >> 10 & 1, key >> 11 & 1,
             key >> 12 & 1 ? "* u_tint" : "", key >> 13 & 3, key >> 15 & 1, key >> 16 & 1, key >> 17 & 1,
             key >> 18 & 1);
    GLuint prog = limen__gl_link(r, head, vs_body, fs_body);
    if (!prog)
        return NULL;
    limen__variant *v = &r->variants[r->nvariants++];
    v->key = key;
    v->prog = prog;
    v->stamp = r->shared_stamp - 1;
#define U(field, name) v->u.field = GL(GetUniformLocation)(prog, name)
    U(model, "u_model");
    U(normal_mat, "u_normal_mat");
    U(view_proj, "u_view_proj");
    U(eye, "u_eye");
    U(clip_plane, "u_clip_plane");
    U(clip_plane2, "u_clip_plane2");
    U(albedo, "u_albedo");
    U(albedo_b, "u_albedo_b");
    U(cell, "u_cell");
    U(scale, "u_scale");
    U(tint, "u_tint");
    U(tex, "u_tex");
    U(tex_map, "u_tex_map");
    U(ambient, "u_ambient");
    U(light_pos, "u_light_pos");
    U(light_col, "u_light_col");
    U(light_inv_r2, "u_light_inv_r2");
    U(uv_repeat, "u_uv_repeat");
    U(base, "u_base");
    U(emissive, "u_emissive");
    U(cutoff, "u_cutoff");
    U(emissive_on, "u_emissive_on");
    U(blend, "u_blend");
#undef U
    GL(UseProgram)(prog);
    GL(Uniform1i)(v->u.tex, 0);
    GL(Uniform1i)(GL(GetUniformLocation)(prog, "u_albedo_tex"), 1);    /* unit 1: albedo */
    GL(Uniform1i)(GL(GetUniformLocation)(prog, "u_emissive_tex"), 2);  /* unit 2: emissive */
    r->bound_prog = prog;
    return v;
}

static void upload_shared(limen_renderer *r, limen__variant *v)
{
    const limen__shared *sh = &r->shared;
    GL(UniformMatrix4fv)(v->u.view_proj, 1, GL_FALSE, sh->view_proj);
    GL(Uniform3fv)(v->u.eye, 1, sh->eye);
    GL(Uniform4fv)(v->u.clip_plane, 1, sh->clip_plane);
    GL(Uniform4fv)(v->u.clip_plane2, 1, sh->cut_plane);
    GL(Uniform3fv)(v->u.tint, 1, sh->tint);
    GL(Uniform1f)(v->u.ambient, sh->ambient);
    GL(Uniform4fv)(v->u.tex_map, 1, sh->tex_map);
    if (sh->nlights && (v->key >> 6 & 15)) {
        GL(Uniform3fv)(v->u.light_pos, sh->nlights, &sh->light_pos[0][0]);
        GL(Uniform3fv)(v->u.light_col, sh->nlights, &sh->light_col[0][0]);
        if (v->key >> 15 & 1)
            GL(Uniform1fv)(v->u.light_inv_r2, sh->nlights, sh->light_inv_r2);
    }
    v->stamp = r->shared_stamp;
}

bool limen__variant_use(limen_renderer *r, int mode, int shape, int checker, int textured)
{
    const float *t = r->shared.tint;
    bool tint = mode < LIMEN__MODE_TEXTURE && (t[0] != 1 || t[1] != 1 || t[2] != 1);
    unsigned key = variant_key(mode, shape, checker, r->shared.nlights, r->clip0_on,
                               r->clip1_on, tint, textured, r->shared.ranged, r->instanced,
                               r->material, r->msaa && r->gl.MinSampleShading);
    limen__variant *v = NULL;
    for (int i = 0; i < r->nvariants && !v; i++)
        if (r->variants[i].key == key)
            v = &r->variants[i];
    if (!v && !(v = variant_build(r, key))) {
        limen__draw_fail(r, LIMEN_ERR_GL, NULL);
        return false;
    }
    if (r->bound_prog != v->prog) {
        GL(UseProgram)(v->prog);
        r->bound_prog = v->prog;
    }
    if (v->stamp != r->shared_stamp)
        upload_shared(r, v);
    r->u = v->u;
    return true;
}

void limen__variants_free(limen_renderer *r)
{
    for (int i = 0; i < r->nvariants; i++)
        GL(DeleteProgram)(r->variants[i].prog);
    r->nvariants = 0;
    r->bound_prog = 0;
}
