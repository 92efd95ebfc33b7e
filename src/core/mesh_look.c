/* mesh_look.c - a mesh file looked at before the importer runs (core/mesh.h,
 * limen__mesh_look): whether a safe scene may load its format, whether its header declares
 * more than the file could hold, and the triangles it will hold at least, refused where they
 * would not fit in what the script has left. A refusal costs what each format needs to know
 * its size, never the import and never the whole file held in memory:
 *
 *   PLY, OFF    the counts in its header (the file's first 4 KiB)
 *   binary STL  the triangle count after its 80-byte header
 *   .glb        its JSON chunk (the nodes that place each mesh; not the binary chunk)
 *   .gltf       the JSON, which is the whole file
 *   OBJ, ASCII  no header: their faces counted in one pass over the file, 64 KiB at a time,
 *   STL         only where the file is large enough to hold too many
 *
 * Each is a lower bound on the mesh's own count, the one it is refused for after the import
 * (limen__mesh_bytes): each face a triangle at least, and no vertices counted, since the
 * importer joins identical ones (a glTF primitive without indices holds three a triangle:
 * two triangles' six become four). So no file that would fit is refused here, except one
 * whose faces have fewer than three corners (a PLY's or OFF's declared face is counted as a
 * triangle unread; no exporter writes such faces). */
#include <ctype.h>
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/confine.h"
#include "core/internal.h"
#include "core/mesh.h"
#include "core/pages.h"

#define HEAD 4096               /* what the header checks look at */
#define SCAN_CHUNK (64u << 10)  /* the face count's read */
#define GLTF_DEPTH_MAX 256      /* nodes nested deeper overflow the importer's stack */

/* The file name's extension, lower case, into ext ("" if none). */
static void extension(const char *path, char *ext, size_t size)
{
    const char *slash = strrchr(path, '/'), *dot = strrchr(path, '.');
    ext[0] = '\0';
    if (!dot || (slash && dot < slash))
        return;
    size_t i = 0;
    for (dot++; *dot && i + 1 < size; dot++)
        ext[i++] = (char)tolower((unsigned char)*dot);
    ext[i] = '\0';
}

/* Whether a file of size bytes is a binary STL by its header (the importer's own test: 84
 * bytes, then 50 a triangle, as many as the count after the 80-byte header says); the count. */
static bool binary_stl(const unsigned char *head, size_t n, uint64_t size, uint32_t *count)
{
    *count = 0;
    if (n < 84)
        return false;
    memcpy(count, head + 80, 4);
    return size == 84 + 50 * (uint64_t)*count;
}

/* Formats a safe scene may load, decided by the extension and the content agreeing: those
 * fuzzed (make fuzz). Writes why and returns false for anything else. */
static bool allowed_format(const char *ext, const unsigned char *head, size_t n, uint64_t size,
                           char *why, size_t why_size)
{
    size_t i = 0;
    while (i < n && isspace(head[i]))
        i++;
    bool ok = false;
    uint32_t count;
    if (strcmp(ext, "gltf") == 0)
        ok = i < n && head[i] == '{';
    else if (strcmp(ext, "glb") == 0)
        ok = n >= 4 && memcmp(head, "glTF", 4) == 0;
    else if (strcmp(ext, "obj") == 0)
        ok = !memchr(head, '\0', n);
    else if (strcmp(ext, "ply") == 0)
        ok = n >= 4 && memcmp(head, "ply", 3) == 0 && (head[3] == '\n' || head[3] == '\r');
    else if (strcmp(ext, "stl") == 0)
        ok = (n >= 5 && memcmp(head, "solid", 5) == 0 && !memchr(head, '\0', n)) ||
             binary_stl(head, n, size, &count);
    else {
        snprintf(why, why_size, "a safe scene loads glTF (.gltf, .glb), OBJ (.obj, .mtl), PLY "
                 "(.ply) and STL (.stl) meshes, not .%s files", ext[0] ? ext : "(none)");
        return false;
    }
    if (!ok)
        snprintf(why, why_size, "its content is not a %s file (a safe scene loads glTF, OBJ, "
                 "PLY and STL meshes, each in a file of its own extension)", ext);
    return ok;
}

/* Counts a header declares, checked against the file's size before the importer sees it:
 * every element a format's header declares takes at least a byte of the file (a vertex or
 * face), so a few bytes cannot declare gigabytes. head holds the file's first n bytes (n <=
 * HEAD). *verts and *faces get the vertices and faces it declares (a PLY's `vertex` and
 * `face` elements, an OFF's counts; 0 for any other format). Writes why and returns false
 * if the file is refused. */
static bool header_ok(const unsigned char *data, size_t n, uint64_t size, char *why,
                      size_t why_size, uint64_t *verts, uint64_t *faces)
{
    *verts = *faces = 0;
    char head[HEAD + 1];
    memcpy(head, data, n);
    head[n] = '\0';
    for (size_t i = 0; i < n; i++)
        if (head[i] == '\0')
            head[i] = ' ';
    uint64_t declared = 0;
    if (n >= 3 && memcmp(head, "ply", 3) == 0) {
        /* assimp 5.2 loops for ever on a header that never ends or ends "end_headerX" */
        char *end = strstr(head, "end_header");
        if (!end || (end[10] != '\n' && end[10] != '\r')) {
            snprintf(why, why_size, "a PLY header with no end_header line in its first 4 KiB");
            return false;
        }
        *end = '\0';
        /* words apart by any white space ("element\tvertex 9" is a declaration too) */
        for (char *line = head; line && *line;) {
            char *next = strpbrk(line, "\r\n");
            if (next)
                *next++ = '\0';
            char word[16], name[32];
            unsigned long long count = 0;
            if (sscanf(line, "%15s %31s %llu", word, name, &count) == 3 &&
                strcmp(word, "element") == 0) {
                count = count > size ? size + 1 : count;
                declared += count;
                if (strcmp(name, "vertex") == 0)
                    *verts += count;
                else if (strcmp(name, "face") == 0)
                    *faces += count;
            }
            line = next;
        }
    } else if (n >= 3 && memcmp(head, "OFF", 3) == 0) {
        unsigned long long nv = 0, nf = 0;
        char *p = head + 3;
        while (*p && *p != '\n')
            p++;
        /* OFF, then (after comments) the vertex and face counts */
        while (*p) {
            while (isspace((unsigned char)*p))
                p++;
            if (*p != '#')
                break;
            while (*p && *p != '\n')
                p++;
        }
        if (sscanf(head + 3, "%llu %llu", &nv, &nf) == 2 || sscanf(p, "%llu %llu", &nv, &nf) == 2) {
            *verts = nv > size ? size + 1 : nv;
            *faces = nf > size ? size + 1 : nf;
            declared = *verts + *faces;
        }
    }
    if (declared > size) {
        snprintf(why, why_size, "its header declares more elements than the file has bytes "
                 "(%llu)", (unsigned long long)size);
        return false;
    }
    return true;
}

/* ------------------------------------------------------------------ headerless formats */

/* Triangles an OBJ's face lines or an ASCII STL's facets make at least, counted a byte at a
 * time (the file comes in pieces). An OBJ face is a line that begins "f" and a blank, its
 * corners the words after it up to a comment (k corners make k - 2 triangles); a facet is a
 * line whose first word is "facet". Lines end at \n, \r, \f or a NUL, as the importer's do.
 * Where the two could differ the count is the lower: an "f" after a blank, a corner that is
 * not a number and a continued line are not counted. */
typedef struct scan {
    bool stl;
    enum { S_START, S_WORD, S_CORNERS, S_SKIP } state;
    int at;                     /* S_WORD: letters of the keyword matched */
    bool in_word;               /* S_CORNERS: inside a corner */
    uint64_t corners, tris;
} scan;

static void scan_end_line(scan *sc)
{
    if (sc->state == S_CORNERS && sc->corners >= 3)
        sc->tris += sc->corners - 2;
    sc->state = S_START;
    sc->at = 0;
}

static void scan_bytes(scan *sc, const unsigned char *p, size_t n)
{
    static const char facet[] = "facet";
    for (size_t i = 0; i < n; i++) {
        unsigned char c = p[i];
        bool blank = c == ' ' || c == '\t' || c == '\v';
        if (c == '\n' || c == '\r' || c == '\f' || c == '\0') {
            if (sc->state == S_WORD && sc->stl && sc->at == 5)
                sc->tris++;
            scan_end_line(sc);
            continue;
        }
        switch (sc->state) {
        case S_START:
            if (sc->stl && blank)
                break;                  /* facets are indented */
            sc->state = S_WORD;
            sc->at = 0;
            /* fall through */
        case S_WORD:
            if (!sc->stl) {             /* "f" and a blank, at the line's start */
                if (sc->at == 0 && c == 'f')
                    sc->at = 1;
                else if (sc->at == 1 && blank) {
                    sc->state = S_CORNERS;
                    sc->corners = 0;
                    sc->in_word = false;
                } else
                    sc->state = S_SKIP;
            } else if (sc->at < 5 && c == (unsigned char)facet[sc->at]) {
                sc->at++;
            } else {
                if (sc->at == 5 && blank)
                    sc->tris++;
                sc->state = S_SKIP;
            }
            break;
        case S_CORNERS:
            if (blank) {
                sc->in_word = false;
            } else if (c == '#') {
                sc->state = S_SKIP;
                if (sc->corners >= 3)
                    sc->tris += sc->corners - 2;
            } else if (!sc->in_word) {
                sc->in_word = true;
                if (isdigit(c) || c == '-')
                    sc->corners++;
            }
            break;
        case S_SKIP:
            break;
        }
    }
}

/* Counts the triangles of the whole file through fd (scan_bytes); false where it cannot be
 * read. */
static bool scan_file(int fd, bool stl, uint64_t *tris)
{
    scan sc = { .stl = stl };
    unsigned char *buf = malloc(SCAN_CHUNK);
    if (!buf)
        return false;
    uint64_t off = 0;
    for (;;) {
        ssize_t r = pread(fd, buf, SCAN_CHUNK, (off_t)off);
        if (r < 0 && errno == EINTR)
            continue;
        if (r < 0) {
            free(buf);
            return false;
        }
        if (r == 0)
            break;
        scan_bytes(&sc, buf, (size_t)r);
        off += (uint64_t)r;
    }
    free(buf);
    const unsigned char end = '\n';     /* a last line without its newline */
    scan_bytes(&sc, &end, 1);
    *tris = sc.tris;
    return true;
}

/* ------------------------------------------------------------------ the look */

/* What a file was counted from. */
enum { FROM_NONE, FROM_NODES, FROM_HEADER, FROM_STL_HEADER, FROM_FACES, FROM_FACETS };

/* What the file costs, from what fd holds (size bytes, head its first n). Sets *need to the
 * bytes the mesh will hold at least (0: not known), *tris to the triangles, *from to what
 * they were counted from and *placed to a glTF's vertices as its nodes place them; false
 * with why where the file is refused for its content. */
static bool cost(int fd, const char *ext, const unsigned char *head, size_t n, uint64_t size,
                 size_t max_bytes, size_t *need, uint64_t *tris, int *from, uint64_t *placed,
                 char *why, size_t why_size)
{
    *need = 0;
    *tris = *placed = 0;
    *from = FROM_NONE;
    uint64_t hv, hf;
    if (!header_ok(head, n, size, why, why_size, &hv, &hf))
        return false;
    size_t i = 0;
    while (i < n && isspace(head[i]))
        i++;
    bool text = i < n && head[i] == '{', glb = n >= 4 && memcmp(head, "glTF", 4) == 0;
    uint32_t count;
    if (text || glb) {
        /* what its nodes place, before the importer copies a mesh into each of them: the
         * JSON, which is the whole of a .gltf and a .glb's first chunk */
        char *json;
        size_t jlen;
        if (limen__gltf_json(fd, size, SIZE_MAX, &json, &jlen) < 0) {
            snprintf(why, why_size, "%s", errno == ENOMEM ? "out of memory" : strerror(errno));
            return false;
        }
        uint64_t gv, gt;
        int depth;
        int known = json && limen__gltf_cost((const unsigned char *)json, jlen, max_bytes, &gv,
                                             &gt, &depth);
        free(json);
        if (known && depth == INT32_MAX) {
            snprintf(why, why_size, "its nodes form a cycle");
            return false;
        }
        if (known && depth > GLTF_DEPTH_MAX) {
            snprintf(why, why_size, "its nodes nest %d deep (%d at most)", depth,
                     GLTF_DEPTH_MAX);
            return false;
        }
        if (known) {
            *need = limen__mesh_bytes(0, gt, true);
            *tris = gt;
            *placed = gv;
            *from = FROM_NODES;
        }
        return true;
    }
    if (hf) {       /* a PLY's or OFF's header: each face a triangle at least */
        *need = limen__mesh_bytes(0, hf, false);
        *tris = hf;
        *from = FROM_HEADER;
    } else if (strcmp(ext, "stl") == 0 && binary_stl(head, n, size, &count)) {
        *need = limen__mesh_bytes(0, count, false);
        *tris = count;
        *from = FROM_STL_HEADER;
    } else if (strcmp(ext, "obj") == 0 || strcmp(ext, "stl") == 0) {
        /* no header: counted only where the file could hold too many (a triangle takes two
         * bytes at least, "f 1 2 3\n" then " 4" for each corner more) */
        bool stl = ext[0] == 's';
        if (limen__mesh_bytes(0, size / 2, false) <= max_bytes)
            return true;
        uint64_t t;
        if (!scan_file(fd, stl, &t)) {
            snprintf(why, why_size, "cannot read: %s", strerror(errno));
            return false;
        }
        *need = limen__mesh_bytes(0, t, false);
        *tris = t;
        *from = stl ? FROM_FACETS : FROM_FACES;
    }
    return true;
}

limen_status limen__mesh_look(limen_scene *s, const char *path, size_t max_bytes,
                              uint64_t *counted, size_t *needed)
{
    if (counted)
        *counted = 0;
    if (needed)
        *needed = 0;
    limen__load *ld = s->load;
    char why[300] = "";
    struct stat st;
    int fd = limen__confine_open(ld ? ld->box : NULL, path, &st, why, sizeof why);
    if (fd < 0)
        return limen__fail(s, LIMEN_ERR_IO, "%s: cannot open: %s", path, why);
    uint64_t size = (uint64_t)st.st_size;
    size_t left = !ld ? SIZE_MAX : ld->read_bytes >= ld->max_bytes ? 0
                                                                  : ld->max_bytes - ld->read_bytes;
    unsigned char head[HEAD];
    size_t n = size < HEAD ? (size_t)size : HEAD;
    limen_status rc = LIMEN_OK;
    if (size > left) {      /* the importer will read it whole */
        s->mem_wanted = size;
        rc = limen__fail(s, LIMEN_ERR_NOMEM, "%s: a file of %.1f MiB, more than the %.1f MiB "
                         "allowed", path, size / 1048576.0, left / 1048576.0);
    } else if (size == 0) {
        rc = limen__fail(s, LIMEN_ERR_IO, "%s: empty file", path);
    } else if (!limen__read_at(fd, head, n, 0)) {
        rc = limen__fail(s, LIMEN_ERR_IO, "%s: cannot read: %s", path, strerror(errno));
    }
    if (rc) {
        close(fd);
        return rc;
    }
    char ext[8];
    extension(path, ext, sizeof ext);
    size_t need;
    uint64_t tris, placed;
    int from;
    bool ok = (!ld || !ld->safe || allowed_format(ext, head, n, size, why, sizeof why)) &&
              cost(fd, ext, head, n, size, max_bytes, &need, &tris, &from, &placed, why,
                   sizeof why);
    close(fd);
    if (!ok)
        return limen__fail(s, LIMEN_ERR_IO, "%s: %s", path, why);
    if (counted)
        *counted = tris;
    if (needed)
        *needed = need;
    if (need > max_bytes) {
        s->mem_wanted = need;
        if (from == FROM_NODES)
            return limen__fail(s, LIMEN_ERR_NOMEM, "%s: its nodes place %llu triangles, which "
                               "need %.1f MiB, more than the %.1f MiB allowed", path,
                               (unsigned long long)tris, need / 1048576.0,
                               max_bytes / 1048576.0);
        static const char *const said[] = {
            [FROM_HEADER] = "the faces its header declares, refused before it is imported",
            [FROM_STL_HEADER] = "the triangles its header declares, refused before it is "
                                "imported",
            [FROM_FACES] = "the faces its f lines hold, counted before it is imported",
            [FROM_FACETS] = "the facets it holds, counted before it is imported",
        };
        /* worded as the mesh's own refusal after the import would be */
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: %llu triangles need %.1f MiB, more than the "
                           "%.1f MiB allowed (%s)", path, (unsigned long long)tris,
                           need / 1048576.0, max_bytes / 1048576.0, said[from]);
    }
    /* a glTF's nodes copy their mesh's vertices (a position each, 12 bytes at least) in the
     * importer before it joins them: not the mesh's measure, but what the import would hold */
    uint64_t copied = placed > SIZE_MAX / 12 ? SIZE_MAX : placed * 12;
    if (copied > max_bytes && (s->mem_wanted = copied))
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: its nodes place %llu vertices, which need "
                           "%.1f MiB in the importer, more than the %.1f MiB allowed", path,
                           (unsigned long long)placed, copied / 1048576.0,
                           max_bytes / 1048576.0);
    /* the importer holds at least the file's bytes while it reads */
    if (size > max_bytes && (s->mem_wanted = size))
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: a file of %.1f MiB, more than the %.1f MiB "
                           "allowed", path, size / 1048576.0, max_bytes / 1048576.0);
    return LIMEN_OK;
}
