/* import.c - a model file through assimp into one pointer-free block (core/import.h): its
 * meshes as parts, its materials and their decoded textures, its node hierarchy, cameras and
 * lights, and what went wrong without spoiling it (warnings).
 *
 * Textures: "*N" (or an embedded texture's own name) is one held in the file (GLB, FBX). A
 * path is read as written where it is relative and stays inside the model's folder; where it
 * is absent there, absolute, or climbs out of the folder, the same base name beside the
 * model (any case) is taken, with a warning; where none is found the parts keep their colour,
 * with a warning. A missing texture never rejects a model. */
#include <ctype.h>
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include <assimp/cimport.h>
#include <assimp/material.h>
#include <assimp/metadata.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include "core/import.h"
#include "core/pages.h"
#include "core/texture.h"

#define NONE LIMEN__IMPORT_NONE
#define MAX_SIDE 16384

/* ------------------------------------------------------------------ growing arrays */

typedef struct arr {
    unsigned char *p;
    size_t n, cap, elem;        /* n elements of elem bytes */
} arr;

static void *arr_push(arr *a, size_t count)
{
    if (a->n + count > a->cap) {
        size_t cap = a->cap ? a->cap : 16;
        while (cap < a->n + count)
            cap *= 2;
        unsigned char *p = realloc(a->p, cap * a->elem);
        if (!p)
            return NULL;
        a->p = p;
        a->cap = cap;
    }
    void *at = a->p + a->n * a->elem;
    memset(at, 0, count * a->elem);
    a->n += count;
    return at;
}

/* Room for cap elements in all, made at once (where the count is known: no copies while
 * they come); false when out of memory. */
static bool arr_reserve(arr *a, size_t cap)
{
    if (cap <= a->cap)
        return true;
    unsigned char *p = realloc(a->p, cap * a->elem);
    if (!p)
        return false;
    /* what it is reserved for is written next (a PLY's elements, counted in its header) */
    limen__populate(p + a->cap * a->elem, (cap - a->cap) * a->elem);
    a->p = p;
    a->cap = cap;
    return true;
}

typedef struct builder {
    const char *path;           /* the model file */
    char dir[1024];             /* its folder, with a trailing '/', or "" */
    const struct aiScene *sc;
    unsigned flags;
    size_t max_bytes, bytes;
    arr verts, tris, parts, mats, texs, texels, nodes, node_parts, cams, lights, warns, strs;
    bool nomem, toobig;
    bool uv0;                   /* a PLY read here: it had texture coordinates */
    char *mtl;                  /* an OBJ's material libraries, read here for what assimp
                                 * skips (map_Kd's -o and -s), or NULL */
    size_t mtl_len;
} builder;

static uint32_t str_add(builder *b, const char *s)
{
    size_t len = strlen(s) + 1;
    char *at = arr_push(&b->strs, len);
    if (!at) {
        b->nomem = true;
        return NONE;
    }
    memcpy(at, s, len);
    return (uint32_t)(b->strs.n - len);
}

static void warn(builder *b, const char *fmt, ...)
{
    char msg[700];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    for (size_t i = 0; i < b->warns.n; i++)     /* once each */
        if (strcmp((const char *)b->strs.p + ((uint32_t *)b->warns.p)[i], msg) == 0)
            return;
    uint32_t off = str_add(b, msg);
    uint32_t *w = off == NONE ? NULL : arr_push(&b->warns, 1);
    if (w)
        *w = off;
}

static bool charge(builder *b, size_t n)
{
    b->bytes += n;
    if (b->bytes > b->max_bytes)
        b->toobig = true;
    return !b->toobig;
}

/* ------------------------------------------------------------------ textures */

_Thread_local const limen__import_files *limen__import_files_hook;

static unsigned char *read_whole(const char *path, size_t max, size_t *len)
{
    const limen__import_files *hook = limen__import_files_hook;
    if (hook)
        return hook->read(hook->ctx, path, max, len);
    struct stat st;
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    unsigned char *buf = NULL;
    if (fstat(fileno(f), &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0 &&
        (uint64_t)st.st_size <= max && (buf = malloc((size_t)st.st_size))) {
        *len = fread(buf, 1, (size_t)st.st_size, f);
        if (*len != (size_t)st.st_size) {
            free(buf);
            buf = NULL;
        }
    }
    fclose(f);
    return buf;
}

static bool is_file(const char *path)
{
    const limen__import_files *hook = limen__import_files_hook;
    if (hook)
        return hook->exists(hook->ctx, path);
    struct stat st;
    return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

/* A file named base (any case) in dir; full gets its path. */
static bool beside(const char *dir, const char *base, char *full, size_t size)
{
    snprintf(full, size, "%s%s", dir, base);
    if (is_file(full))
        return true;
    DIR *d = opendir(dir[0] ? dir : ".");
    if (!d)
        return false;
    bool found = false;
    for (struct dirent *e; !found && (e = readdir(d));)
        if (strcasecmp(e->d_name, base) == 0) {
            snprintf(full, size, "%s%s", dir, e->d_name);
            found = is_file(full);
        }
    closedir(d);
    return found;
}

/* The texture's texels into the block's texel area from RGBA8 rgba (w x h). */
static bool keep_texels(builder *b, limen__import_texture *t, const unsigned char *rgba, int w,
                        int h)
{
    size_t n = (size_t)w * (size_t)h * 4;
    if (!charge(b, n))
        return false;
    size_t at = b->texels.n;
    unsigned char *dst = arr_push(&b->texels, (n + 7) & ~(size_t)7);
    if (!dst) {
        b->nomem = true;
        return false;
    }
    memcpy(dst, rgba, n);
    t->width = (uint32_t)w;
    t->height = (uint32_t)h;
    t->texels = at;     /* relative to the texel area until the block is packed */
    for (size_t i = 3; i < n; i += 4)
        if (rgba[i] < 255) {
            t->has_alpha = 1;
            break;
        }
    return true;
}

static void decode_into(builder *b, limen__import_texture *t, const unsigned char *buf,
                        size_t len, const char *name)
{
    int w = 0, h = 0;
    if (!limen__image_info(buf, len, &w, &h)) {
        warn(b, "texture '%s' is not an image read here (%s): the parts keep their colour",
             name, limen__image_why());
        return;
    }
    if (w < 1 || h < 1 || w > MAX_SIDE || h > MAX_SIDE) {
        warn(b, "texture '%s' is %dx%d pixels (1 to %d a side): the parts keep their colour",
             name, w, h, MAX_SIDE);
        return;
    }
    if (!charge(b, (size_t)w * (size_t)h * 4))
        return;
    b->bytes -= (size_t)w * (size_t)h * 4;
    unsigned char *rgba = limen__image_decode_rgba(buf, len, &w, &h);
    if (!rgba) {
        warn(b, "texture '%s' cannot be decoded (%s): the parts keep their colour", name,
             limen__image_why());
        return;
    }
    keep_texels(b, t, rgba, w, h);
    free(rgba);
}

static const struct aiTexture *embedded(const struct aiScene *sc, const char *name)
{
    if (name[0] == '*') {
        char *end;
        unsigned long k = strtoul(name + 1, &end, 10);
        return *end == '\0' && k < sc->mNumTextures ? sc->mTextures[k] : NULL;
    }
    const char *base = strrchr(name, '/');
    base = base ? base + 1 : name;
    for (unsigned i = 0; i < sc->mNumTextures; i++) {
        const char *f = sc->mTextures[i]->mFilename.data, *fb = strrchr(f, '/');
        const char *fb2 = strrchr(f, '\\');
        fb = fb2 > fb ? fb2 : fb;
        if (f[0] && (strcmp(f, name) == 0 || strcasecmp(fb ? fb + 1 : f, base) == 0))
            return sc->mTextures[i];
    }
    return NULL;
}

static void load_texture(builder *b, limen__import_texture *t, const char *given)
{
    const struct aiTexture *at = embedded(b->sc, given);
    if (at) {
        if (at->mHeight == 0) {
            decode_into(b, t, (const unsigned char *)at->pcData, at->mWidth, given);
            return;
        }
        /* raw BGRA texels */
        if (at->mWidth > MAX_SIDE || at->mHeight > MAX_SIDE) {
            warn(b, "texture '%s' is too large: the parts keep their colour", given);
            return;
        }
        size_t n = (size_t)at->mWidth * at->mHeight;
        unsigned char *rgba = malloc(n * 4);
        if (!rgba) {
            b->nomem = true;
            return;
        }
        for (size_t i = 0; i < n; i++) {
            rgba[i * 4] = at->pcData[i].r;
            rgba[i * 4 + 1] = at->pcData[i].g;
            rgba[i * 4 + 2] = at->pcData[i].b;
            rgba[i * 4 + 3] = at->pcData[i].a;
        }
        keep_texels(b, t, rgba, (int)at->mWidth, (int)at->mHeight);
        free(rgba);
        return;
    }
    if (given[0] == '*') {
        warn(b, "embedded texture '%s' is not in the file: the parts keep their colour", given);
        return;
    }
    char name[1024];
    snprintf(name, sizeof name, "%s", given);
    for (char *c = name; *c; c++)
        if (*c == '\\')
            *c = '/';
    bool absolute = name[0] == '/' || (isalpha((unsigned char)name[0]) && name[1] == ':');
    bool climbs = strcmp(name, "..") == 0 || strncmp(name, "../", 3) == 0 ||
                  strstr(name, "/../") != NULL;
    char full[2200];
    bool found = false;
    if (!absolute && !climbs) {
        snprintf(full, sizeof full, "%s%s", b->dir, name);
        found = is_file(full);
    }
    if (!found) {
        const char *base = strrchr(name, '/');
        base = base ? base + 1 : name;
        if (base[0] && beside(b->dir, base, full, sizeof full)) {
            warn(b, "texture '%s' %s: using '%s' beside the model", given,
                 absolute ? "is an absolute path" : climbs ? "is outside the model's folder"
                                                           : "is not found",
                 full);
            found = true;
        }
    }
    if (!found) {
        warn(b, "texture '%s' not found (nor beside the model): the parts keep their colour",
             given);
        return;
    }
    size_t len = 0;
    unsigned char *buf = read_whole(full, b->max_bytes, &len);
    if (!buf) {
        warn(b, "texture '%s' cannot be read (%s): the parts keep their colour", full,
             strerror(errno));
        return;
    }
    decode_into(b, t, buf, len, full);
    free(buf);
}

/* The index of the texture the file names `given`, read the first time it is named. */
static uint32_t texture_index(builder *b, const char *given)
{
    limen__import_texture *ts = (limen__import_texture *)b->texs.p;
    for (size_t i = 0; i < b->texs.n; i++)
        if (strcmp((const char *)b->strs.p + ts[i].name, given) == 0)
            return (uint32_t)i;
    uint32_t name = str_add(b, given);
    limen__import_texture *t = name == NONE ? NULL : arr_push(&b->texs, 1);
    if (!t) {
        b->nomem = true;
        return NONE;
    }
    t->name = name;
    t->texels = 0;
    limen__import_texture tmp = *t;     /* the array may move while decoding */
    load_texture(b, &tmp, given);
    ((limen__import_texture *)b->texs.p)[b->texs.n - 1] = tmp;
    return (uint32_t)(b->texs.n - 1);
}

/* ------------------------------------------------------------------ materials */

static uint32_t material_texture(builder *b, const struct aiMaterial *m, enum aiTextureType type,
                                 uint32_t *uv_set)
{
    struct aiString str;
    unsigned uvindex = 0;
    if (aiGetMaterialTexture(m, type, 0, &str, NULL, &uvindex, NULL, NULL, NULL, NULL) !=
            aiReturn_SUCCESS ||
        !str.data[0])
        return NONE;
    if (uv_set)
        *uv_set = uvindex > 1 ? 0 : uvindex;
    if (uvindex > 1)
        warn(b, "texture '%s' reads texture-coordinate set %u: set 0 is used", str.data,
             uvindex);
    if (b->flags & LIMEN__IMPORT_NO_TEXTURES)
        return NONE;
    return texture_index(b, str.data);
}

/* ------------------------------------------------------------------ MTL options */

/* The next word of [*p, end) (spaces and tabs between), NUL-free; its length, 0 at the line's
 * end. */
static size_t mtl_word(const char **p, const char *end, const char **w)
{
    const char *q = *p;
    while (q < end && (*q == ' ' || *q == '\t' || *q == '\r'))
        q++;
    *w = q;
    while (q < end && *q != ' ' && *q != '\t' && *q != '\r' && *q != '\n')
        q++;
    *p = q;
    return (size_t)(q - *w);
}

static bool mtl_is(const char *w, size_t n, const char *word)
{
    return n == strlen(word) && memcmp(w, word, n) == 0;
}

/* A number word of at most 63 characters; false for anything else. */
static bool mtl_number(const char *w, size_t n, float *out)
{
    char buf[64];
    if (n == 0 || n >= sizeof buf)
        return false;
    memcpy(buf, w, n);
    buf[n] = '\0';
    char *e;
    double v = strtod(buf, &e);
    if (*e || !isfinite(v) || fabs(v) > 1e6)
        return false;
    *out = (float)v;
    return true;
}

/* The -o (offset) and -s (scale) options of material `name`'s map_Kd in the OBJ's material
 * libraries (the MTL format: uv' = uv x s + o), as a 2x3 transform in x; false where none is
 * given. assimp reads the options and drops them. */
static bool mtl_transform(const builder *b, const char *name, float x[6])
{
    if (!b->mtl || !name)
        return false;
    const char *p = b->mtl, *end = b->mtl + b->mtl_len;
    bool ours = false, found = false;
    while (p < end) {
        const char *line_end = memchr(p, '\n', (size_t)(end - p));
        if (!line_end)
            line_end = end;
        const char *w;
        size_t n = mtl_word(&p, line_end, &w);
        if (mtl_is(w, n, "newmtl")) {
            const char *nm;
            size_t nn = mtl_word(&p, line_end, &nm);
            ours = nn == strlen(name) && memcmp(nm, name, nn) == 0;
        } else if (ours && mtl_is(w, n, "map_Kd")) {
            float o[2] = { 0, 0 }, sc[2] = { 1, 1 };
            for (;;) {
                const char *opt;
                size_t on = mtl_word(&p, line_end, &opt);
                if (on == 0 || opt[0] != '-')
                    break;
                float *into = mtl_is(opt, on, "-o") ? o : mtl_is(opt, on, "-s") ? sc : NULL;
                /* -o and -s take up to three numbers (u [v [w]]); other options are skipped
                 * with the numbers after them */
                for (int k = 0; k < 3; k++) {
                    const char *save = p, *num;
                    float v;
                    size_t nl = mtl_word(&p, line_end, &num);
                    if (!mtl_number(num, nl, &v)) {
                        /* the next option is left for the loop; any other word (on, off, a
                         * channel, the file's name) is passed */
                        bool option = nl > 1 && num[0] == '-' &&
                                      isalpha((unsigned char)num[1]);
                        if (option)
                            p = save;
                        break;
                    }
                    if (into && k < 2)
                        into[k] = v;
                }
                if (into)
                    found = true;
            }
            if (found) {
                x[0] = sc[0];
                x[1] = 0;
                x[2] = 0;
                x[3] = sc[1];
                x[4] = o[0];
                x[5] = o[1];
                return true;
            }
        }
        p = line_end < end ? line_end + 1 : end;
    }
    return false;
}

/* An OBJ's material libraries (its mtllib lines), read through the same way in as the file,
 * into b->mtl; nothing for other files or where none can be read. */
static void mtl_read(builder *b)
{
    size_t plen = strlen(b->path);
    if (plen < 4 || strcasecmp(b->path + plen - 4, ".obj") != 0)
        return;
    size_t len;
    unsigned char *obj = read_whole(b->path, b->max_bytes, &len);
    if (!obj)
        return;
    const char *p = (const char *)obj, *end = p + len;
    while (p < end) {
        const char *line_end = memchr(p, '\n', (size_t)(end - p));
        if (!line_end)
            line_end = end;
        const char *w;
        size_t n = mtl_word(&p, line_end, &w);
        if (mtl_is(w, n, "mtllib")) {
            const char *f;
            size_t fn;
            while ((fn = mtl_word(&p, line_end, &f)) > 0) {
                char name[512], full[1600];
                if (fn >= sizeof name || memchr(f, '\0', fn))
                    continue;
                memcpy(name, f, fn);
                name[fn] = '\0';
                snprintf(full, sizeof full, "%s%s", b->dir, name);
                size_t ml;
                unsigned char *m = read_whole(full, b->max_bytes, &ml);
                char *grown = m ? realloc(b->mtl, b->mtl_len + ml + 1) : NULL;
                if (grown) {
                    memcpy(grown + b->mtl_len, m, ml);
                    b->mtl_len += ml;
                    grown[b->mtl_len++] = '\n';
                    b->mtl = grown;
                }
                free(m);
            }
        }
        p = line_end < end ? line_end + 1 : end;
    }
    free(obj);
}

static void material(builder *b, const struct aiMaterial *m, limen__import_material *out)
{
    struct aiString str;
    struct aiColor4D c;
    out->name = aiGetMaterialString(m, AI_MATKEY_NAME, &str) == aiReturn_SUCCESS
                    ? str_add(b, str.data) : NONE;
    out->base[0] = out->base[1] = out->base[2] = out->base[3] = 1;
    /* the material assimp makes for a file that names none is white here (its grey would
     * darken every model without materials) */
    bool made_up = out->name != NONE && strcmp(str.data, AI_DEFAULT_MATERIAL_NAME) == 0;
    if (!made_up && (aiGetMaterialColor(m, AI_MATKEY_BASE_COLOR, &c) == aiReturn_SUCCESS ||
                     aiGetMaterialColor(m, AI_MATKEY_COLOR_DIFFUSE, &c) == aiReturn_SUCCESS)) {
        out->base[0] = c.r;
        out->base[1] = c.g;
        out->base[2] = c.b;
        out->base[3] = c.a;
    }
    out->alpha_cutoff = 0.5f;
    out->alpha_mode = LIMEN__ALPHA_OPAQUE;
    float f;
    if (aiGetMaterialString(m, "$mat.gltf.alphaMode", 0, 0, &str) == aiReturn_SUCCESS) {
        out->alpha_mode = strcmp(str.data, "MASK") == 0    ? LIMEN__ALPHA_MASK
                          : strcmp(str.data, "BLEND") == 0 ? LIMEN__ALPHA_BLEND
                                                           : LIMEN__ALPHA_OPAQUE;
        if (aiGetMaterialFloatArray(m, "$mat.gltf.alphaCutoff", 0, 0, &f, NULL) ==
            aiReturn_SUCCESS)
            out->alpha_cutoff = f;
    } else {
        if (aiGetMaterialFloatArray(m, AI_MATKEY_OPACITY, &f, NULL) == aiReturn_SUCCESS &&
            f < 1 && f >= 0) {
            out->base[3] = f;
            out->alpha_mode = LIMEN__ALPHA_BLEND;
        } else {
            out->base[3] = 1;
        }
    }
    out->base_tex = material_texture(b, m, aiTextureType_BASE_COLOR, &out->base_uv);
    if (out->base_tex == NONE)
        out->base_tex = material_texture(b, m, aiTextureType_DIFFUSE, &out->base_uv);
    float x[6] = { 1, 0, 0, 1, 0, 0 };
    struct aiUVTransform t;
    unsigned n = sizeof t / sizeof(float);
    if (out->base_tex != NONE &&
        (aiGetMaterialFloatArray(m, "$tex.uvtrafo", aiTextureType_BASE_COLOR, 0, (float *)&t,
                                 &n) == aiReturn_SUCCESS ||
         (n = sizeof t / sizeof(float),
          aiGetMaterialFloatArray(m, "$tex.uvtrafo", aiTextureType_DIFFUSE, 0, (float *)&t,
                                  &n) == aiReturn_SUCCESS))) {
        /* scale, then rotation (counter-clockwise), then translation */
        float cs = cosf(t.mRotation), sn = sinf(t.mRotation);
        x[0] = cs * t.mScaling.x;
        x[1] = sn * t.mScaling.x;
        x[2] = -sn * t.mScaling.y;
        x[3] = cs * t.mScaling.y;
        x[4] = t.mTranslation.x;
        x[5] = t.mTranslation.y;
    } else if (out->base_tex != NONE && out->name != NONE) {
        mtl_transform(b, (const char *)b->strs.p + out->name, x);
    }
    memcpy(out->base_xform, x, sizeof x);
    /* an OBJ's map_d: a mask, read from the base texture's alpha where it is the same image */
    if (aiGetMaterialTexture(m, aiTextureType_OPACITY, 0, &str, NULL, NULL, NULL, NULL, NULL,
                             NULL) == aiReturn_SUCCESS && str.data[0]) {
        out->alpha_mode = LIMEN__ALPHA_MASK;
        const limen__import_texture *ts = (const limen__import_texture *)b->texs.p;
        if (out->base_tex == NONE ||
            strcmp((const char *)b->strs.p + ts[out->base_tex].name, str.data) != 0)
            warn(b, "opacity map '%s' is not the base texture: its alpha is used instead",
                 str.data);
    }
    if (aiGetMaterialColor(m, AI_MATKEY_COLOR_EMISSIVE, &c) == aiReturn_SUCCESS) {
        out->emissive[0] = c.r;
        out->emissive[1] = c.g;
        out->emissive[2] = c.b;
    }
    out->emissive_tex = material_texture(b, m, aiTextureType_EMISSIVE, &out->emissive_uv);
    if (out->emissive_tex != NONE && !out->emissive[0] && !out->emissive[1] && !out->emissive[2])
        out->emissive[0] = out->emissive[1] = out->emissive[2] = 1;
    int two = 0;
    if (aiGetMaterialIntegerArray(m, AI_MATKEY_TWOSIDED, &two, NULL) == aiReturn_SUCCESS)
        out->double_sided = two != 0;
    out->metallic = out->roughness = 1;
    out->normal_scale = out->occlusion_strength = 1;
    if (aiGetMaterialFloatArray(m, AI_MATKEY_METALLIC_FACTOR, &f, NULL) == aiReturn_SUCCESS)
        out->metallic = f;
    if (aiGetMaterialFloatArray(m, AI_MATKEY_ROUGHNESS_FACTOR, &f, NULL) == aiReturn_SUCCESS)
        out->roughness = f;
    out->metal_rough_tex = material_texture(b, m, aiTextureType_UNKNOWN, NULL);
    if (out->metal_rough_tex == NONE)
        out->metal_rough_tex = material_texture(b, m, aiTextureType_METALNESS, NULL);
    out->normal_tex = material_texture(b, m, aiTextureType_NORMALS, NULL);
    out->occlusion_tex = material_texture(b, m, aiTextureType_AMBIENT_OCCLUSION, NULL);
    if (out->occlusion_tex == NONE)
        out->occlusion_tex = material_texture(b, m, aiTextureType_LIGHTMAP, NULL);
}

/* ------------------------------------------------------------------ meshes */

static void mesh(builder *b, const struct aiMesh *am, limen__import_part *p)
{
    p->first_vertex = (uint32_t)b->verts.n;
    p->first_tri = (uint32_t)(b->tris.n / 3);
    p->material = am->mMaterialIndex < b->sc->mNumMaterials ? am->mMaterialIndex : 0;
    p->has_normals = am->mNormals != NULL;
    p->name = am->mName.length ? str_add(b, am->mName.data) : NONE;
    /* geometry is charged where it is kept (core/mesh.c), textures here */
    limen__import_vertex *v = arr_push(&b->verts, am->mNumVertices);
    if (!v) {
        b->nomem = true;
        return;
    }
    p->vertex_count = am->mNumVertices;
    for (unsigned i = 0; i < am->mNumVertices; i++, v++) {
        v->pos[0] = am->mVertices[i].x;
        v->pos[1] = am->mVertices[i].y;
        v->pos[2] = am->mVertices[i].z;
        if (am->mNormals) {
            v->nrm[0] = am->mNormals[i].x;
            v->nrm[1] = am->mNormals[i].y;
            v->nrm[2] = am->mNormals[i].z;
        }
        for (int s = 0; s < 2; s++)
            if (am->mTextureCoords[s]) {
                v->uv[s][0] = am->mTextureCoords[s][i].x;
                v->uv[s][1] = am->mTextureCoords[s][i].y;
            }
        if (am->mColors[0]) {
            v->col[0] = am->mColors[0][i].r;
            v->col[1] = am->mColors[0][i].g;
            v->col[2] = am->mColors[0][i].b;
            v->col[3] = am->mColors[0][i].a;
        } else {
            v->col[0] = v->col[1] = v->col[2] = v->col[3] = 1;
        }
    }
    unsigned skipped = 0;
    for (unsigned f = 0; f < am->mNumFaces; f++) {
        const struct aiFace *face = &am->mFaces[f];
        if (face->mNumIndices != 3) {
            skipped++;
            continue;
        }
        uint32_t *t = arr_push(&b->tris, 3);
        if (!t) {
            b->nomem = true;
            return;
        }
        for (int k = 0; k < 3; k++)
            t[k] = face->mIndices[k] < am->mNumVertices ? face->mIndices[k] : 0;
        p->tri_count++;
    }
    if (skipped)
        warn(b, "%u points or lines skipped (a mesh is made of triangles)", skipped);
}

/* ------------------------------------------------------------------ hierarchy */

static void json_string(arr *j, const char *s)
{
    char *c = arr_push(j, 1);
    if (c)
        *c = '"';
    for (; *s; s++) {
        char esc[8];
        unsigned char u = (unsigned char)*s;
        if (u == '"' || u == '\\')
            snprintf(esc, sizeof esc, "\\%c", u);
        else if (u < 0x20)
            snprintf(esc, sizeof esc, "\\u%04x", u);
        else
            snprintf(esc, sizeof esc, "%c", u);
        size_t n = strlen(esc);
        char *at = arr_push(j, n);
        if (at)
            memcpy(at, esc, n);
    }
    c = arr_push(j, 1);
    if (c)
        *c = '"';
}

static void json_text(arr *j, const char *s)
{
    size_t n = strlen(s);
    char *at = arr_push(j, n);
    if (at)
        memcpy(at, s, n);
}

/* A node's metadata (glTF extras, FBX user properties) as a JSON object. */
static void json_meta(arr *j, const struct aiMetadata *md, int depth)
{
    json_text(j, "{");
    for (unsigned i = 0; md && i < md->mNumProperties; i++) {
        if (i)
            json_text(j, ", ");
        json_string(j, md->mKeys[i].data);
        json_text(j, ": ");
        const struct aiMetadataEntry *e = &md->mValues[i];
        char num[96];
        num[0] = '\0';
        if (!e->mData) {
            json_text(j, "null");
            continue;
        }
        switch (e->mType) {
        case AI_BOOL: json_text(j, *(const bool *)e->mData ? "true" : "false"); break;
        case AI_INT32: snprintf(num, sizeof num, "%d", *(const int32_t *)e->mData); break;
        case AI_UINT64:
            snprintf(num, sizeof num, "%llu", (unsigned long long)*(const uint64_t *)e->mData);
            break;
        case AI_FLOAT: snprintf(num, sizeof num, "%.9g", *(const float *)e->mData); break;
        case AI_DOUBLE: snprintf(num, sizeof num, "%.17g", *(const double *)e->mData); break;
        case AI_AISTRING: json_string(j, ((const struct aiString *)e->mData)->data); break;
        case AI_AIVECTOR3D: {
            const struct aiVector3D *v = e->mData;
            snprintf(num, sizeof num, "[%.9g, %.9g, %.9g]", v->x, v->y, v->z);
            break;
        }
        case AI_AIMETADATA:
            if (depth < 16)
                json_meta(j, e->mData, depth + 1);
            else
                json_text(j, "null");
            break;
        default: json_text(j, "null"); break;
        }
        if (num[0])
            json_text(j, num);
    }
    json_text(j, "}");
}

static void node(builder *b, const struct aiNode *n, uint32_t parent, int depth)
{
    if (depth > 256) {
        warn(b, "node hierarchy deeper than 256: the rest is left out");
        return;
    }
    limen__import_node *out = arr_push(&b->nodes, 1);
    if (!out) {
        b->nomem = true;
        return;
    }
    uint32_t self = (uint32_t)(b->nodes.n - 1);
    limen__import_node nd = { .parent = parent, .extras = NONE };
    nd.name = str_add(b, n->mName.data);
    const struct aiMatrix4x4 *m = &n->mTransformation;
    const float rows[4][4] = { { m->a1, m->a2, m->a3, m->a4 }, { m->b1, m->b2, m->b3, m->b4 },
                               { m->c1, m->c2, m->c3, m->c4 }, { m->d1, m->d2, m->d3, m->d4 } };
    for (int i = 0; i < 4; i++)
        for (int jj = 0; jj < 4; jj++)
            nd.matrix[jj * 4 + i] = rows[i][jj];
    nd.first_part = (uint32_t)b->node_parts.n;
    for (unsigned i = 0; i < n->mNumMeshes; i++) {
        if (n->mMeshes[i] >= b->sc->mNumMeshes)
            continue;
        uint32_t *p = arr_push(&b->node_parts, 1);
        if (!p) {
            b->nomem = true;
            return;
        }
        *p = n->mMeshes[i];
        nd.part_count++;
    }
    if (n->mMetaData && n->mMetaData->mNumProperties) {
        arr j = { .elem = 1 };
        json_meta(&j, n->mMetaData, 0);
        char *z = arr_push(&j, 1);
        if (z)
            nd.extras = str_add(b, (const char *)j.p);
        else
            b->nomem = true;
        free(j.p);
    }
    ((limen__import_node *)b->nodes.p)[self] = nd;
    for (unsigned i = 0; i < n->mNumChildren; i++)
        node(b, n->mChildren[i], self, depth + 1);
}

static void cameras_lights(builder *b)
{
    const struct aiScene *sc = b->sc;
    for (unsigned i = 0; i < sc->mNumCameras; i++) {
        const struct aiCamera *c = sc->mCameras[i];
        limen__import_camera *o = arr_push(&b->cams, 1);
        if (!o) {
            b->nomem = true;
            return;
        }
        limen__import_camera cam = { .fovy = 0 };
        cam.pos[0] = c->mPosition.x, cam.pos[1] = c->mPosition.y, cam.pos[2] = c->mPosition.z;
        cam.look[0] = c->mLookAt.x, cam.look[1] = c->mLookAt.y, cam.look[2] = c->mLookAt.z;
        cam.up[0] = c->mUp.x, cam.up[1] = c->mUp.y, cam.up[2] = c->mUp.z;
        cam.aspect = c->mAspect;
        /* assimp keeps half the horizontal angle */
        double hx = tan((double)c->mHorizontalFOV);
        cam.fovy = (float)(c->mAspect > 0 ? 2.0 * atan(hx / c->mAspect) : 2.0 * c->mHorizontalFOV);
        cam.znear = c->mClipPlaneNear;
        cam.zfar = c->mClipPlaneFar;
        cam.name = str_add(b, c->mName.data);
        *(limen__import_camera *)(b->cams.p + (b->cams.n - 1) * b->cams.elem) = cam;
    }
    for (unsigned i = 0; i < sc->mNumLights; i++) {
        const struct aiLight *l = sc->mLights[i];
        limen__import_light *o = arr_push(&b->lights, 1);
        if (!o) {
            b->nomem = true;
            return;
        }
        limen__import_light li = { .type = (uint32_t)l->mType };
        li.pos[0] = l->mPosition.x, li.pos[1] = l->mPosition.y, li.pos[2] = l->mPosition.z;
        li.colour[0] = l->mColorDiffuse.r;
        li.colour[1] = l->mColorDiffuse.g;
        li.colour[2] = l->mColorDiffuse.b;
        li.name = str_add(b, l->mName.data);
        *(limen__import_light *)(b->lights.p + (b->lights.n - 1) * b->lights.elem) = li;
    }
}

/* ------------------------------------------------------------------ the block */

static size_t align8(size_t n)
{
    return (n + 7) & ~(size_t)7;
}

static limen__import *pack(builder *b)
{
    size_t off = align8(sizeof(limen__import));
    arr *parts[] = { &b->verts, &b->tris, &b->parts, &b->mats, &b->texs, &b->nodes,
                     &b->node_parts, &b->cams, &b->lights, &b->warns, &b->texels, &b->strs };
    enum { NARR = sizeof parts / sizeof parts[0] };
    size_t at[NARR];
    for (int i = 0; i < NARR; i++) {
        at[i] = off;
        off = align8(off + parts[i]->n * parts[i]->elem);
    }
    /* the arrays copied in, one after another */
    limen__import *blk = limen__calloc_populated(1, off);
    if (!blk)
        return NULL;
    for (int i = 0; i < NARR; i++)
        if (parts[i]->n)
            memcpy((unsigned char *)blk + at[i], parts[i]->p, parts[i]->n * parts[i]->elem);
    *blk = (limen__import){
        .magic = LIMEN__IMPORT_MAGIC, .version = LIMEN__IMPORT_VERSION, .size = off,
        .nverts = (uint32_t)b->verts.n, .ntris = (uint32_t)(b->tris.n / 3),
        .nparts = (uint32_t)b->parts.n, .nmaterials = (uint32_t)b->mats.n,
        .ntextures = (uint32_t)b->texs.n, .nnodes = (uint32_t)b->nodes.n,
        .nnode_parts = (uint32_t)b->node_parts.n, .ncameras = (uint32_t)b->cams.n,
        .nlights = (uint32_t)b->lights.n, .nwarnings = (uint32_t)b->warns.n,
        .verts = at[0], .tris = at[1], .parts = at[2], .materials = at[3], .textures = at[4],
        .nodes = at[5], .node_parts = at[6], .cameras = at[7], .lights = at[8],
        .warnings = at[9], .strings = at[11], .strings_size = b->strs.n,
    };
    limen__import_texture *ts = LIMEN__IMP(blk, textures, limen__import_texture);
    for (uint32_t i = 0; i < blk->ntextures; i++)
        ts[i].texels = ts[i].width ? at[10] + ts[i].texels : 0;
    const limen__import_part *ps = LIMEN__IMP(blk, parts, limen__import_part);
    const limen__import_vertex *vs = LIMEN__IMP(blk, verts, limen__import_vertex);
    bool normals = blk->nparts > 0, colours = false;
    for (uint32_t i = 0; i < blk->nparts; i++)
        normals = normals && (ps[i].has_normals || !ps[i].tri_count);
    for (uint32_t v = 0; v < blk->nverts && !colours; v++)
        colours = vs[v].col[0] != 1 || vs[v].col[1] != 1 || vs[v].col[2] != 1 ||
                  vs[v].col[3] != 1;
    blk->vertex_flags = (normals ? LIMEN__VERT_NORMALS : 0) | (colours ? LIMEN__VERT_COLOURS : 0);
    if (b->uv0)
        blk->vertex_flags |= LIMEN__VERT_UV0;
    for (unsigned i = 0; b->sc && i < b->sc->mNumMeshes; i++) {
        if (b->sc->mMeshes[i]->mTextureCoords[0])
            blk->vertex_flags |= LIMEN__VERT_UV0;
        if (b->sc->mMeshes[i]->mTextureCoords[1])
            blk->vertex_flags |= LIMEN__VERT_UV1;
    }
    return blk;
}

static void builder_free(builder *b)
{
    arr *all[] = { &b->verts, &b->tris, &b->parts, &b->mats, &b->texs, &b->nodes,
                   &b->node_parts, &b->cams, &b->lights, &b->warns, &b->texels, &b->strs };
    for (size_t i = 0; i < sizeof all / sizeof all[0]; i++)
        free(all[i]->p);
    free(b->mtl);
}

static void builder_elems(builder *b)
{
    b->verts.elem = sizeof(limen__import_vertex);
    b->tris.elem = sizeof(uint32_t);
    b->parts.elem = sizeof(limen__import_part);
    b->mats.elem = sizeof(limen__import_material);
    b->texs.elem = sizeof(limen__import_texture);
    b->texels.elem = 1;
    b->nodes.elem = sizeof(limen__import_node);
    b->node_parts.elem = sizeof(uint32_t);
    b->cams.elem = sizeof(limen__import_camera);
    b->lights.elem = sizeof(limen__import_light);
    b->warns.elem = sizeof(uint32_t);
    b->strs.elem = 1;
    const char *slash = strrchr(b->path, '/');
    snprintf(b->dir, sizeof b->dir, "%.*s", slash ? (int)(slash - b->path + 1) : 0, b->path);
}

/* The material of a file that names none: white, untextured, opaque. */
static limen__import_material white_material(void)
{
    return (limen__import_material){ .name = NONE, .base = { 1, 1, 1, 1 }, .base_tex = NONE,
                                     .base_xform = { 1, 0, 0, 1, 0, 0 }, .alpha_cutoff = 0.5f,
                                     .emissive_tex = NONE, .metal_rough_tex = NONE,
                                     .normal_tex = NONE, .occlusion_tex = NONE, .metallic = 1,
                                     .roughness = 1, .normal_scale = 1,
                                     .occlusion_strength = 1 };
}

static limen_status convert(builder *b, limen__import **out, char *why, size_t why_size)
{
    const struct aiScene *sc = b->sc;
    for (unsigned i = 0; i < sc->mNumMaterials && !b->nomem && !b->toobig; i++) {
        limen__import_material *m = arr_push(&b->mats, 1);
        if (!m) {
            b->nomem = true;
            break;
        }
        limen__import_material tmp = { 0 };
        material(b, sc->mMaterials[i], &tmp);
        ((limen__import_material *)b->mats.p)[i] = tmp;
    }
    if (!b->mats.n && arr_push(&b->mats, 1)) {     /* a default: white */
        limen__import_material *m = (limen__import_material *)b->mats.p;
        *m = white_material();
    }
    for (unsigned i = 0; i < sc->mNumMeshes && !b->nomem && !b->toobig; i++) {
        limen__import_part *p = arr_push(&b->parts, 1);
        if (!p) {
            b->nomem = true;
            break;
        }
        limen__import_part tmp = { 0 };
        mesh(b, sc->mMeshes[i], &tmp);
        ((limen__import_part *)b->parts.p)[i] = tmp;
    }
    if (sc->mRootNode && !b->nomem && !b->toobig)
        node(b, sc->mRootNode, NONE, 0);
    if (!b->nomem && !b->toobig)
        cameras_lights(b);
    if (b->toobig) {
        snprintf(why, why_size, "%s: needs more than the %.1f MiB allowed", b->path,
                 b->max_bytes / 1048576.0);
        return LIMEN_ERR_NOMEM;
    }
    if (!b->nomem && !(*out = pack(b)))
        b->nomem = true;
    if (b->nomem) {
        snprintf(why, why_size, "%s: out of memory", b->path);
        return LIMEN_ERR_NOMEM;
    }
    return LIMEN_OK;
}

/* ------------------------------------------------------------------ PLY triangle strips */

/* assimp reads a PLY's `tristrips` element as one triangle; such a file is read here
 * instead: its vertices (position, normal, colour, texture coordinates) and its strips
 * (-1 restarts one; every other triangle turned to keep the winding) and faces (fans). */
enum { PLY_PROPS = 32, PLY_ELEMS = 16 };

typedef struct ply_prop {
    char name[32];
    int type, count_type;       /* sizes in bytes, negative for signed ints, 40/80 floats */
    bool list;
} ply_prop;

typedef struct ply_elem {
    char name[32];
    uint64_t count;
    int nprops;
    ply_prop props[PLY_PROPS];
} ply_elem;

typedef struct ply_in {
    const unsigned char *p, *end;
    int format;                 /* 0 ascii, 1 little endian, 2 big endian */
    bool bad;
} ply_in;

static int ply_type(const char *t)
{
    static const struct { const char *name; int type; } types[] = {
        { "char", -1 }, { "int8", -1 }, { "uchar", 1 }, { "uint8", 1 }, { "short", -2 },
        { "int16", -2 }, { "ushort", 2 }, { "uint16", 2 }, { "int", -4 }, { "int32", -4 },
        { "uint", 4 }, { "uint32", 4 }, { "float", 40 }, { "float32", 40 }, { "double", 80 },
        { "float64", 80 },
    };
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (strcmp(t, types[i].name) == 0)
            return types[i].type;
    return 0;
}

/* The next size bytes (there are), in the order of a little-endian host (as limen's hosts
 * are): a little-endian file's as they are, a big-endian's turned. */
static inline void ply_take(ply_in *in, unsigned char *b, int size)
{
    if (in->format == 1)
        memcpy(b, in->p, (size_t)size);
    else
        for (int i = 0; i < size; i++)
            b[i] = in->p[size - 1 - i];
    in->p += size;
}

static double ply_value(ply_in *in, int type)
{
    if (in->bad)
        return 0;
    if (in->format == 0) {
        while (in->p < in->end && isspace(*in->p))
            in->p++;
        char tok[64];
        size_t n = 0;
        while (in->p < in->end && !isspace(*in->p) && n < sizeof tok - 1)
            tok[n++] = (char)*in->p++;
        tok[n] = '\0';
        char *e;
        double v = strtod(tok, &e);
        if (!n || *e)
            in->bad = true;
        return v;
    }
    int size = type == 40 ? 4 : type == 80 ? 8 : type < 0 ? -type : type;
    if (in->end - in->p < size) {
        in->bad = true;
        return 0;
    }
    unsigned char b[8];
    switch (type) {
    case -1: ply_take(in, b, 1); return (int8_t)b[0];
    case 1: ply_take(in, b, 1); return b[0];
    case -2: { int16_t v; ply_take(in, b, 2); memcpy(&v, b, 2); return v; }
    case 2: { uint16_t v; ply_take(in, b, 2); memcpy(&v, b, 2); return v; }
    case -4: { int32_t v; ply_take(in, b, 4); memcpy(&v, b, 4); return v; }
    case 4: { uint32_t v; ply_take(in, b, 4); memcpy(&v, b, 4); return v; }
    case 40: { float v; ply_take(in, b, 4); memcpy(&v, b, 4); return v; }
    default: { double v; ply_take(in, b, 8); memcpy(&v, b, 8); return v; }
    }
}

/* The header; false if it is not one read here (then assimp reads the file). */
static int prop_slot(const char *n);

/* Whether the elements are a plain mesh: vertices of positions (x, y, z, as floats) and
 * perhaps normals, then faces of vertex indices alone, nothing else. */
static bool ply_plain(const ply_elem *el, int nel)
{
    if (nel != 2 || strcmp(el[0].name, "vertex") != 0 || strcmp(el[1].name, "face") != 0 ||
        el[1].nprops != 1 || !el[1].props[0].list || el[1].props[0].type == 40 ||
        el[1].props[0].type == 80 ||
        (strcmp(el[1].props[0].name, "vertex_indices") != 0 &&
         strcmp(el[1].props[0].name, "vertex_index") != 0))
        return false;
    unsigned seen = 0;
    for (int k = 0; k < el[0].nprops; k++) {
        const ply_prop *pp = &el[0].props[k];
        int slot = prop_slot(pp->name);
        if (pp->list || slot < 0 || slot >= 6 || (pp->type != 40 && pp->type != 80) ||
            (seen & 1u << slot))
            return false;
        seen |= 1u << slot;
    }
    return (seen & 7u) == 7u && ((seen >> 3) == 0 || (seen >> 3) == 7u);
}

static bool ply_header(const unsigned char *buf, size_t len, ply_in *in, ply_elem *el, int *nel)
{
    const char *end = memmem(buf, len, "end_header", 10);
    if (len < 4 || memcmp(buf, "ply", 3) != 0 || !end)
        return false;
    const char *body = memchr(end, '\n', len - (size_t)((const unsigned char *)end - buf));
    if (!body)
        return false;
    *nel = 0;
    bool strips = false;
    in->format = -1;
    for (const char *line = (const char *)buf; line < end;) {
        const char *nl = memchr(line, '\n', (size_t)(end - line));
        size_t n = nl ? (size_t)(nl - line) : (size_t)(end - line);
        char l[256], a[32], b2[32], c[32], d[32];
        snprintf(l, sizeof l, "%.*s", (int)(n < 255 ? n : 255), line);
        line += n + 1;
        int k = sscanf(l, "%31s %31s %31s %31s %31s", a, b2, c, d, d);
        if (k >= 2 && strcmp(a, "format") == 0)
            in->format = strcmp(b2, "ascii") == 0 ? 0 : strcmp(b2, "binary_little_endian") == 0 ? 1
                         : strcmp(b2, "binary_big_endian") == 0 ? 2 : -1;
        else if (k >= 3 && strcmp(a, "element") == 0) {
            if (*nel == PLY_ELEMS)
                return false;
            ply_elem *e = &el[(*nel)++];
            memset(e, 0, sizeof *e);
            snprintf(e->name, sizeof e->name, "%s", b2);
            e->count = strtoull(c, NULL, 10);
            strips = strips || strcmp(b2, "tristrips") == 0;
        } else if (k >= 3 && strcmp(a, "property") == 0) {
            if (!*nel || el[*nel - 1].nprops == PLY_PROPS)
                return false;
            ply_prop *pp = &el[*nel - 1].props[el[*nel - 1].nprops++];
            memset(pp, 0, sizeof *pp);
            if (strcmp(b2, "list") == 0) {
                char name[32] = "";
                if (sscanf(l, "%*s %*s %31s %31s %31s", c, d, name) != 3)
                    return false;
                pp->list = true;
                pp->count_type = ply_type(c);
                pp->type = ply_type(d);
                snprintf(pp->name, sizeof pp->name, "%s", name);
                if (!pp->count_type || pp->count_type == 40 || pp->count_type == 80)
                    return false;
            } else {
                pp->type = ply_type(b2);
                snprintf(pp->name, sizeof pp->name, "%s", c);
            }
            if (!pp->type)
                return false;
        }
    }
    in->p = (const unsigned char *)body + 1;
    in->end = buf + len;
    return (strips || ply_plain(el, *nel)) && in->format >= 0;
}

static int prop_slot(const char *n)
{
    static const char *const names[] = { "x", "y", "z", "nx", "ny", "nz", "red", "green", "blue",
                                         "alpha", "u", "v", "s", "t", "texture_u", "texture_v" };
    for (int i = 0; i < 16; i++)
        if (strcmp(n, names[i]) == 0)
            return i;
    return -1;
}

static void ply_tri(builder *b, uint64_t nv, int64_t i0, int64_t i1, int64_t i2, bool *oor)
{
    if (i0 == i1 || i1 == i2 || i0 == i2)
        return;     /* a strip's degenerate joins */
    if (i0 < 0 || i1 < 0 || i2 < 0 || (uint64_t)i0 >= nv || (uint64_t)i1 >= nv ||
        (uint64_t)i2 >= nv) {
        *oor = true;
        return;
    }
    uint32_t *t = arr_push(&b->tris, 3);
    if (!t) {
        b->nomem = true;
        return;
    }
    t[0] = (uint32_t)i0;
    t[1] = (uint32_t)i1;
    t[2] = (uint32_t)i2;
}

static limen_status ply_strips(builder *b, ply_in *in, ply_elem *el, int nel, char *why,
                               size_t why_size)
{
    uint64_t nv = 0;
    bool oor = false, colours = false;
    size_t budget = (size_t)(in->end - in->p) + 1;
    for (int e = 0; e < nel && !in->bad && !b->nomem; e++) {
        bool vert = strcmp(el[e].name, "vertex") == 0;
        bool strip = strcmp(el[e].name, "tristrips") == 0, face = strcmp(el[e].name, "face") == 0;
        if (el[e].count > budget) {
            in->bad = true;
            break;
        }
        /* room for what the element says it holds, where the rest of the file could hold
         * it (each element at least a byte a property) */
        uint64_t room = (uint64_t)el[e].nprops * el[e].count;
        if (room <= (uint64_t)(in->end - in->p) &&
            !(vert ? arr_reserve(&b->verts, b->verts.n + el[e].count)
                   : face ? arr_reserve(&b->tris, b->tris.n + 3 * el[e].count) : true)) {
            b->nomem = true;
            break;
        }
        /* per property, once an element: its slot in a vertex, and (a list) whether it
         * holds vertex indices */
        int slot_of[PLY_PROPS];
        bool idx_of[PLY_PROPS];
        for (int k = 0; k < el[e].nprops; k++) {
            const char *name = el[e].props[k].name;
            slot_of[k] = vert ? prop_slot(name) : -1;
            idx_of[k] = strcmp(name, "vertex_indices") == 0 || strcmp(name, "vertex_index") == 0;
        }
        for (uint64_t i = 0; i < el[e].count && !in->bad && !b->nomem; i++) {
            limen__import_vertex *v = NULL;
            if (vert) {
                if (!(v = arr_push(&b->verts, 1))) {
                    b->nomem = true;
                    break;
                }
                v->col[0] = v->col[1] = v->col[2] = v->col[3] = 1;
                nv++;
            }
            for (int k = 0; k < el[e].nprops && !in->bad; k++) {
                const ply_prop *pp = &el[e].props[k];
                if (!pp->list) {
                    double x = ply_value(in, pp->type);
                    int slot = v ? slot_of[k] : -1;
                    float f = (float)x, c = pp->type == 40 || pp->type == 80 ? f : f / 255.0f;
                    if (slot >= 0 && slot < 3)
                        v->pos[slot] = f;
                    else if (slot >= 3 && slot < 6)
                        v->nrm[slot - 3] = f;
                    else if (slot >= 6 && slot < 10) {
                        v->col[slot - 6] = c;
                        colours = true;
                    } else if (slot >= 10) {
                        v->uv[0][(slot - 10) % 2] = f;
                        b->uv0 = true;
                    }
                    continue;
                }
                double cnt = ply_value(in, pp->count_type);
                if (!(cnt >= 0) || cnt > (double)budget) {
                    in->bad = true;
                    break;
                }
                bool idx = idx_of[k];
                int64_t a = -1, bb = -1, first = -1;
                int run = 0;
                for (uint64_t j = 0; j < (uint64_t)cnt && !in->bad; j++) {
                    int64_t ix = (int64_t)ply_value(in, pp->type);
                    if (!idx || (!strip && !face))
                        continue;
                    if (strip) {
                        if (ix < 0) {       /* restart */
                            run = 0;
                            continue;
                        }
                        if (run >= 2)
                            (run % 2) ? ply_tri(b, nv, bb, a, ix, &oor)
                                      : ply_tri(b, nv, a, bb, ix, &oor);
                        a = bb;
                        bb = ix;
                        if (run == 0)
                            a = -1, bb = ix;
                        run++;
                    } else {
                        if (j == 0)
                            first = ix;
                        else if (j >= 2)
                            ply_tri(b, nv, first, bb, ix, &oor);
                        bb = ix;
                    }
                }
            }
        }
    }
    if (in->bad) {
        snprintf(why, why_size, "%s: its PLY data ends early or does not match its header",
                 b->path);
        return LIMEN_ERR_IO;
    }
    if (oor)
        warn(b, "triangles with a vertex out of range skipped");
    (void)colours;
    return LIMEN_OK;
}

/* A block from a PLY of strips: one part, one white material, one node. */
static limen_status ply_block(builder *b, const unsigned char *buf, size_t len,
                              limen__import **out, char *why, size_t why_size, bool *handled)
{
    ply_in in = { 0 };
    ply_elem el[PLY_ELEMS];
    int nel = 0;
    *handled = ply_header(buf, len, &in, el, &nel);
    if (!*handled)
        return LIMEN_OK;
    limen_status st = ply_strips(b, &in, el, nel, why, why_size);
    if (st)
        return st;
    limen__import_material *m = arr_push(&b->mats, 1);
    limen__import_part *p = m ? arr_push(&b->parts, 1) : NULL;
    limen__import_node *n = p ? arr_push(&b->nodes, 1) : NULL;
    uint32_t *np = n ? arr_push(&b->node_parts, 1) : NULL;
    if (!np || b->nomem) {
        snprintf(why, why_size, "%s: out of memory", b->path);
        return LIMEN_ERR_NOMEM;
    }
    *(limen__import_material *)b->mats.p = white_material();
    bool normals = false;
    for (size_t i = 0; i < b->verts.n && !normals; i++) {
        const float *q = ((limen__import_vertex *)b->verts.p)[i].nrm;
        normals = q[0] != 0 || q[1] != 0 || q[2] != 0;
    }
    *(limen__import_part *)b->parts.p = (limen__import_part){
        .vertex_count = (uint32_t)b->verts.n, .tri_count = (uint32_t)(b->tris.n / 3),
        .has_normals = normals, .name = NONE };
    uint32_t root = str_add(b, "root");
    limen__import_node *nd = (limen__import_node *)b->nodes.p;
    *nd = (limen__import_node){ .name = root, .parent = NONE, .part_count = 1, .extras = NONE };
    for (int i = 0; i < 4; i++)
        nd->matrix[i * 5] = 1;
    *(uint32_t *)b->node_parts.p = 0;
    if (b->nomem || !(*out = pack(b))) {
        snprintf(why, why_size, "%s: out of memory", b->path);
        return LIMEN_ERR_NOMEM;
    }
    return LIMEN_OK;
}

limen_status limen__import_file(const char *path, unsigned flags, size_t max_bytes,
                                limen__import **out, char *why, size_t why_size)
{
    *out = NULL;
    {
        /* a PLY of triangle strips: read here (assimp takes it for one triangle); and a
         * plain one (positions, perhaps normals, and faces), whose reading by assimp held
         * 450 MB of temporaries at 1.6M triangles (its vertices one per corner, then joined)
         * where this holds the vertices and triangles once */
        /* read through the same way in as the rest (never opened by name here) */
        size_t len = 0, plen = strlen(path);
        unsigned char *buf = plen >= 4 && strcasecmp(path + plen - 4, ".ply") == 0
                                 ? read_whole(path, max_bytes, &len) : NULL;
        if (buf && len >= 3 && memcmp(buf, "ply", 3) == 0) {
            builder b = { .path = path, .flags = flags, .max_bytes = max_bytes };
            builder_elems(&b);
            bool handled = false;
            limen_status st = ply_block(&b, buf, len, out, why, why_size, &handled);
            builder_free(&b);
            free(buf);
            if (handled || st)
                return st;
        } else {
            free(buf);
        }
    }
    /* assimp's C interface keeps the last error in one string for the whole process: an
     * import and the reading of its error go together, one thread at a time, so that
     * scenes on different threads stay independent (limen.h, THREADS) */
    static pthread_mutex_t importing = PTHREAD_MUTEX_INITIALIZER;
    char err[301] = "";
    const limen__import_files *hook = limen__import_files_hook;
    bool lock = !hook || !hook->inside;     /* (a child's copy of the lock may be held) */
    if (lock)
        pthread_mutex_lock(&importing);
    const struct aiScene *sc =
        aiImportFileEx(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                                 aiProcess_SortByPType | aiProcess_ValidateDataStructure,
                       hook ? hook->io : NULL);
    if (!sc) {
        const char *e = aiGetErrorString();
        snprintf(err, sizeof err, "%s", e ? e : "");
    }
    if (lock)
        pthread_mutex_unlock(&importing);
    if (!sc) {
        snprintf(why, why_size, "%s: cannot read it as a mesh: %s", path,
                 err[0] ? err : "unknown format");
        return LIMEN_ERR_IO;
    }
    if (sc->mFlags & AI_SCENE_FLAGS_INCOMPLETE) {
        aiReleaseImport(sc);
        snprintf(why, why_size, "%s: incomplete (no meshes in it)", path);
        return LIMEN_ERR_IO;
    }
    builder b = { .path = path, .sc = sc, .flags = flags, .max_bytes = max_bytes };
    builder_elems(&b);
    mtl_read(&b);
    limen_status st = convert(&b, out, why, why_size);
    builder_free(&b);
    aiReleaseImport(sc);
    return st;
}

/* ------------------------------------------------------------------ reading a block */

const char *limen__import_string(const limen__import *b, uint32_t off)
{
    if (off == NONE || off >= b->strings_size)
        return "";
    return (const char *)b + b->strings + off;
}

static bool span_ok(const limen__import *b, uint64_t off, uint64_t n, uint64_t elem)
{
    return off % 4 == 0 && off <= b->size && (elem == 0 || n <= (b->size - off) / elem);
}

static bool str_ok(const limen__import *b, uint32_t off)
{
    return off == NONE || off < b->strings_size;
}

bool limen__import_valid(const limen__import *b, size_t size)
{
    if (!b || size < sizeof *b || b->magic != LIMEN__IMPORT_MAGIC ||
        b->version != LIMEN__IMPORT_VERSION || b->size != size)
        return false;
    if (!span_ok(b, b->verts, b->nverts, sizeof(limen__import_vertex)) ||
        !span_ok(b, b->tris, (uint64_t)b->ntris * 3, 4) ||
        !span_ok(b, b->parts, b->nparts, sizeof(limen__import_part)) ||
        !span_ok(b, b->materials, b->nmaterials, sizeof(limen__import_material)) ||
        !span_ok(b, b->textures, b->ntextures, sizeof(limen__import_texture)) ||
        !span_ok(b, b->nodes, b->nnodes, sizeof(limen__import_node)) ||
        !span_ok(b, b->node_parts, b->nnode_parts, 4) ||
        !span_ok(b, b->cameras, b->ncameras, sizeof(limen__import_camera)) ||
        !span_ok(b, b->lights, b->nlights, sizeof(limen__import_light)) ||
        !span_ok(b, b->warnings, b->nwarnings, 4) || !span_ok(b, b->strings, b->strings_size, 1))
        return false;
    const char *strs = (const char *)b + b->strings;
    if (b->strings_size && strs[b->strings_size - 1] != '\0')
        return false;
    if (b->nmaterials < 1)
        return false;
    const limen__import_part *ps = LIMEN__IMP(b, parts, limen__import_part);
    for (uint32_t i = 0; i < b->nparts; i++) {
        const limen__import_part *p = &ps[i];
        if (p->material >= b->nmaterials || !str_ok(b, p->name) ||
            p->first_vertex > b->nverts || p->vertex_count > b->nverts - p->first_vertex ||
            p->first_tri > b->ntris || p->tri_count > b->ntris - p->first_tri)
            return false;
        const uint32_t *t = LIMEN__IMP(b, tris, uint32_t) + (size_t)p->first_tri * 3;
        for (size_t k = 0; k < (size_t)p->tri_count * 3; k++)
            if (t[k] >= p->vertex_count)
                return false;
    }
    const limen__import_material *ms = LIMEN__IMP(b, materials, limen__import_material);
    for (uint32_t i = 0; i < b->nmaterials; i++) {
        const limen__import_material *m = &ms[i];
        uint32_t tex[] = { m->base_tex, m->emissive_tex, m->metal_rough_tex, m->normal_tex,
                           m->occlusion_tex };
        for (size_t k = 0; k < sizeof tex / sizeof tex[0]; k++)
            if (tex[k] != NONE && tex[k] >= b->ntextures)
                return false;
        if (!str_ok(b, m->name) || m->base_uv > 1 || m->emissive_uv > 1)
            return false;
    }
    const limen__import_texture *ts = LIMEN__IMP(b, textures, limen__import_texture);
    for (uint32_t i = 0; i < b->ntextures; i++)
        if (!str_ok(b, ts[i].name) || ts[i].width > MAX_SIDE || ts[i].height > MAX_SIDE ||
            (ts[i].width && !span_ok(b, ts[i].texels, (uint64_t)ts[i].width * ts[i].height, 4)))
            return false;
    const limen__import_node *ns = LIMEN__IMP(b, nodes, limen__import_node);
    for (uint32_t i = 0; i < b->nnodes; i++)
        if (!str_ok(b, ns[i].name) || !str_ok(b, ns[i].extras) ||
            (ns[i].parent != NONE && ns[i].parent >= i) || ns[i].first_part > b->nnode_parts ||
            ns[i].part_count > b->nnode_parts - ns[i].first_part)
            return false;
    const uint32_t *np = LIMEN__IMP(b, node_parts, uint32_t);
    for (uint32_t i = 0; i < b->nnode_parts; i++)
        if (np[i] >= b->nparts)
            return false;
    const uint32_t *ws = LIMEN__IMP(b, warnings, uint32_t);
    for (uint32_t i = 0; i < b->nwarnings; i++)
        if (!str_ok(b, ws[i]))
            return false;
    for (uint32_t i = 0; i < b->ncameras; i++)
        if (!str_ok(b, LIMEN__IMP(b, cameras, limen__import_camera)[i].name))
            return false;
    for (uint32_t i = 0; i < b->nlights; i++)
        if (!str_ok(b, LIMEN__IMP(b, lights, limen__import_light)[i].name))
            return false;
    return true;
}
