/* lod_cache.c - levels of detail kept between runs: once a mesh's levels are made (core/lod.c)
 * they are stored under a hash of what they were made from, in the user's cache folder, so
 * that the next load of the same mesh reads them instead of making them again.
 *
 * An entry is one file, lod-<key>.bin: a header (magic, version, the key, the mesh's counts,
 * the number of levels), per level its triangle count and error, the coarse levels' indices,
 * and a checksum of all of it. It is written whole or not at all (core/file.c). Reading
 * trusts nothing: the file must be a regular file of exactly the size its header implies,
 * every field in range, every index below the vertex count, and the checksum must match;
 * otherwise it is ignored and the levels are made (and stored) again. The folder is kept
 * under a size limit by removing the entries used least recently (a hit touches its
 * entry). */
#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/pages.h"
#include "core/internal.h"
#include "core/lod_bake.h"
#include "core/lod_cache.h"

#define MAGIC "LIMENLOD"
#define FORMAT 1u
#define HEAD_WORDS 10           /* after the magic: format, version... see entry_head */
#define DEFAULT_MB 256
/* the coarse levels' indices of a mesh of n triangles, at most: as many as the full mesh's,
 * twice that where levels are baked (core/lod.c) */
#define MOST_INDICES(n) (6ull * (n))

/* ------------------------------------------------------------------ the key */

typedef struct hasher {
    uint64_t a, b;
} hasher;

static uint64_t mix(uint64_t x)
{
    x ^= x >> 33;
    x *= 0xff51afd7ed558ccdull;
    x ^= x >> 33;
    x *= 0xc4ceb9fe1a85ec53ull;
    x ^= x >> 33;
    return x;
}

/* Two lanes over 8-byte words (the tail zero-padded), each a multiply and a rotate per word,
 * with different constants: 128 bits in all. */
static void hash_bytes(hasher *h, const void *data, size_t len)
{
    const unsigned char *p = data;
    uint64_t a = h->a ^ len, b = h->b + len;
    size_t i = 0;
    for (; i + 8 <= len; i += 8) {
        uint64_t w;
        memcpy(&w, p + i, 8);
        a = ((a ^ w) * 0x9e3779b97f4a7c15ull);
        a = a << 31 | a >> 33;
        b = ((b + w) * 0xc2b2ae3d27d4eb4full);
        b = b << 27 | b >> 37;
    }
    uint64_t w = 0;
    memcpy(&w, p + i, len - i);
    h->a = mix(a ^ w);
    h->b = mix(b + w + 0x165667b19e3779f9ull);
}

void limen__lod_cache_key(const limen__mesh *m, uint32_t version, limen__lod_key *key)
{
    hasher h = { 0x243f6a8885a308d3ull, 0x13198a2e03707344ull };
    /* whether its coarse levels are baked: its materials' textures and alpha modes */
    uint32_t head[7] = { version, m->nverts, m->ntris, (m->uv ? 1u : 0u), (m->col ? 1u : 0u),
                         m->nparts, limen__lod_bakeable(m) ? 1u : 0u };
    hash_bytes(&h, head, sizeof head);
    hash_bytes(&h, m->pos, sizeof(float) * 3 * m->nverts);
    hash_bytes(&h, m->idx, sizeof(uint32_t) * 3 * m->ntris);
    if (m->nrm)
        hash_bytes(&h, m->nrm, sizeof(float) * 3 * m->nverts);
    if (m->uv)
        hash_bytes(&h, m->uv, sizeof(float) * 2 * m->nverts);
    if (m->col)
        hash_bytes(&h, m->col, sizeof(float) * 4 * m->nverts);
    if (m->nparts > 1 && m->tri_part)
        hash_bytes(&h, m->tri_part, sizeof(uint32_t) * m->ntris);
    key->h[0] = h.a;
    key->h[1] = h.b;
}

/* ------------------------------------------------------------------ the folder */

static bool cache_off(void)
{
    const char *v = getenv("LIMEN_CACHE");
    return v && (!strcasecmp(v, "off") || !strcmp(v, "0") || !strcasecmp(v, "no"));
}

/* mkdir -p for the last two components at most (the cache folder and limen's below it). */
static bool make_dir(const char *dir)
{
    struct stat st;
    if (stat(dir, &st) == 0)
        return S_ISDIR(st.st_mode);
    char parent[4096];
    snprintf(parent, sizeof parent, "%s", dir);
    char *slash = strrchr(parent, '/');
    if (slash && slash != parent) {
        *slash = 0;
        if (stat(parent, &st) != 0 && mkdir(parent, 0700) != 0 && errno != EEXIST)
            return false;
    }
    return (mkdir(dir, 0700) == 0 || errno == EEXIST) && stat(dir, &st) == 0 &&
           S_ISDIR(st.st_mode);
}

static uint64_t limit_bytes(void)
{
    const char *v = getenv("LIMEN_CACHE_MB");
    char *end = NULL;
    double mb = v && v[0] ? strtod(v, &end) : DEFAULT_MB;
    if ((end && *end) || !(mb >= 0) || mb > 1e9)
        mb = DEFAULT_MB;
    return (uint64_t)(mb * 1048576.0);
}

void limen__lod_cache_where(limen__lod_where *w)
{
    memset(w, 0, sizeof *w);
    if (cache_off())
        return;
    const char *own = getenv("LIMEN_CACHE_DIR"), *xdg = getenv("XDG_CACHE_HOME"),
               *home = getenv("HOME");
    int n;
    if (own && own[0] == '/')
        n = snprintf(w->dir, sizeof w->dir, "%s", own);
    else if (xdg && xdg[0] == '/')
        n = snprintf(w->dir, sizeof w->dir, "%s/limen", xdg);
    else if (home && home[0] == '/')
        n = snprintf(w->dir, sizeof w->dir, "%s/.cache/limen", home);
    else
        return;
    w->on = n > 0 && (size_t)n < sizeof w->dir - 64;
    w->limit = limit_bytes();
}

static bool entry_path(const limen__lod_where *w, const limen__lod_key *key, char *out,
                       size_t size)
{
    if (!w->on)
        return false;
    int n = snprintf(out, size, "%s/lod-%016llx%016llx.bin", w->dir,
                     (unsigned long long)key->h[0], (unsigned long long)key->h[1]);
    return n > 0 && (size_t)n < size;
}

/* ------------------------------------------------------------------ entries */

/* The words after the magic: format, the key's four halves, nverts, ntris, nlods, the coarse
 * levels' indices in all, the baked levels (bit k: level k). */
static void entry_head(uint32_t w[HEAD_WORDS], const limen__lod_key *key, uint32_t nverts,
                       uint32_t ntris, uint32_t nlods, uint64_t nidx, uint32_t baked)
{
    w[0] = FORMAT;
    w[1] = (uint32_t)key->h[0];
    w[2] = (uint32_t)(key->h[0] >> 32);
    w[3] = (uint32_t)key->h[1];
    w[4] = (uint32_t)(key->h[1] >> 32);
    w[5] = nverts;
    w[6] = ntris;
    w[7] = nlods;
    w[8] = (uint32_t)nidx;
    w[9] = baked;
}

uint64_t limen__lod_cache_checksum(const void *data, size_t len)
{
    hasher h = { 0x452821e638d01377ull, 0xbe5466cf34e90c6cull };
    hash_bytes(&h, data, len);
    return h.a ^ h.b;
}

bool limen__lod_cache_load(const limen__lod_where *w, const limen__lod_key *key,
                           uint32_t nverts, uint32_t ntris,
                           limen_mesh_lod *lods, uint32_t max_levels, uint32_t *nlods,
                           uint32_t *baked, size_t room, unsigned char **block)
{
    *nlods = 0;
    *baked = 0;
    *block = NULL;
    char path[4200];
    if (!entry_path(w, key, path, sizeof path))
        return false;
    /* no link followed, and nothing that could block (a pipe, a device) */
    int fd = open(path, O_RDONLY | O_NOFOLLOW | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0)
        return false;
    struct stat st;
    unsigned char *whole = NULL, *buf = NULL;
    bool ok = fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > 0;
    size_t len = ok ? (size_t)st.st_size : 0;
    /* the largest entry a mesh of this size makes: its levels hold at most MOST_INDICES
     * indices, each level 8 bytes of header */
    uint64_t most = 8 + 4 * HEAD_WORDS + 8ull * max_levels + 4ull * MOST_INDICES(ntris) + 8;
    ok = ok && (uint64_t)st.st_size <= most && len >= 8 + 4 * HEAD_WORDS + 8;
    /* read in after `room` bytes, where the indices will be moved down to: one copy of them
     * at a time (a 1.6M-triangle mesh's are 19 MB) */
    if (ok)
        ok = (whole = limen__malloc_populated(room + len)) != NULL;
    buf = whole ? whole + room : NULL;
    size_t got = 0;
    while (ok && got < len) {
        ssize_t r = read(fd, buf + got, len - got);
        if (r < 0 && errno == EINTR)
            continue;
        ok = r > 0;
        got += ok ? (size_t)r : 0;
    }
    close(fd);
    uint32_t head[HEAD_WORDS], want[HEAD_WORDS], n = 0;
    if (ok) {
        memcpy(head, buf + 8, sizeof head);
        n = head[7];
        entry_head(want, key, nverts, ntris, n, head[8], head[9]);
        ok = !memcmp(buf, MAGIC, 8) && !memcmp(head, want, sizeof head) && n >= 1 &&
             n <= max_levels && n < 32 && !(head[9] & 1u) && !(head[9] >> n) &&
             (uint64_t)head[8] <= MOST_INDICES(ntris) &&
             len == 8 + 4 * HEAD_WORDS + 8ull * n + 4ull * head[8] + 8;
    }
    if (ok) {
        uint64_t sum;
        memcpy(&sum, buf + len - 8, 8);
        ok = sum == limen__lod_cache_checksum(buf, len - 8);
    }
    /* the levels: the first the full mesh; then falling counts, errors finite and growing
     * (a baked level's is kept before its texture's reach, which is found again: not
     * compared), their indices adding up to the total */
    const unsigned char *lv = buf + 8 + 4 * HEAD_WORDS;
    uint64_t total = 0;
    for (uint32_t k = 0; ok && k < n; k++) {
        uint32_t count;
        float err;
        memcpy(&count, lv + 8 * k, 4);
        memcpy(&err, lv + 8 * k + 4, 4);
        if (k == 0)
            ok = count == ntris && err == 0;
        else
            ok = count >= 1 && count < (uint32_t)lods[k - 1].triangle_count && isfinite(err) &&
                 err >= 0 && (err >= lods[k - 1].error || (head[9] >> k & 1u) ||
                              (head[9] >> (k - 1) & 1u));
        lods[k] = (limen_mesh_lod){ .triangle_count = (int)count, .error = err };
        total += k ? 3ull * count : 0;
    }
    ok = ok && total == head[8];
    if (ok && total > 0) {
        memmove(whole + room, lv + 8 * n, sizeof(uint32_t) * total);
        const uint32_t *idx = (const uint32_t *)(whole + room);
        for (uint64_t i = 0; ok && i < total; i++)
            ok = idx[i] < nverts;
    }
    if (!ok) {
        free(whole);
        return false;
    }
    unsigned char *fit = realloc(whole, room + sizeof(uint32_t) * total);
    if (fit)
        whole = fit;
    /* used: the last to be trimmed */
    utimensat(AT_FDCWD, path, NULL, AT_SYMLINK_NOFOLLOW);
    *nlods = n;
    *baked = head[9];
    *block = whole;
    return true;
}

/* ------------------------------------------------------------------ trimming */

typedef struct entry {
    char name[64];
    off_t size;
    struct timespec used;
} entry;

static int older_first(const void *pa, const void *pb)
{
    const entry *a = pa, *b = pb;
    if (a->used.tv_sec != b->used.tv_sec)
        return a->used.tv_sec < b->used.tv_sec ? -1 : 1;
    if (a->used.tv_nsec != b->used.tv_nsec)
        return a->used.tv_nsec < b->used.tv_nsec ? -1 : 1;
    return strcmp(a->name, b->name);
}

/* Removes the entries used least recently while the folder's entries exceed limit bytes. */
static void trim(const char *dir, uint64_t limit)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    entry *list = NULL;
    size_t n = 0, cap = 0;
    uint64_t total = 0;
    int dfd = dirfd(d);
    for (struct dirent *e; (e = readdir(d));) {
        size_t len = strlen(e->d_name);
        if (strncmp(e->d_name, "lod-", 4) || len < 8 || len >= sizeof list->name ||
            strcmp(e->d_name + len - 4, ".bin"))
            continue;
        struct stat st;
        if (fstatat(dfd, e->d_name, &st, AT_SYMLINK_NOFOLLOW) != 0 || !S_ISREG(st.st_mode))
            continue;
        if (n == cap) {
            size_t ncap = cap ? cap * 2 : 64;
            entry *grown = realloc(list, sizeof *list * ncap);
            if (!grown)
                break;
            list = grown;
            cap = ncap;
        }
        snprintf(list[n].name, sizeof list[n].name, "%s", e->d_name);
        list[n].size = st.st_size;
        list[n].used = st.st_mtim;
        total += (uint64_t)st.st_size;
        n++;
    }
    if (total > limit) {
        qsort(list, n, sizeof *list, older_first);
        for (size_t i = 0; i < n && total > limit; i++)
            if (unlinkat(dfd, list[i].name, 0) == 0)
                total -= (uint64_t)list[i].size;
    }
    free(list);
    closedir(d);
}

/* ------------------------------------------------------------------ storing */

void limen__lod_cache_store(const limen__lod_where *w, const limen__lod_key *key,
                            uint32_t nverts, uint32_t ntris, const limen_mesh_lod *lods,
                            uint32_t nlods, uint32_t baked)
{
    char path[4200];
    if (nlods < 1 || !entry_path(w, key, path, sizeof path))
        return;
    uint64_t nidx = 0;
    for (uint32_t k = 1; k < nlods; k++)
        nidx += 3ull * (uint32_t)lods[k].triangle_count;
    size_t len = 8 + 4 * HEAD_WORDS + 8 * (size_t)nlods + 4 * (size_t)nidx + 8;
    /* an entry larger than the whole cache may be is not kept */
    if (nidx > MOST_INDICES(ntris) || len > w->limit || nlods >= 32 || !make_dir(w->dir))
        return;
    /* what is there already and is not a plain file (a link, a pipe) is left alone */
    struct stat st;
    if (lstat(path, &st) == 0 && !S_ISREG(st.st_mode))
        return;
    unsigned char *buf = malloc(len);
    if (!buf)
        return;
    uint32_t head[HEAD_WORDS];
    entry_head(head, key, nverts, ntris, nlods, nidx, baked);
    memcpy(buf, MAGIC, 8);
    memcpy(buf + 8, head, sizeof head);
    unsigned char *lv = buf + 8 + 4 * HEAD_WORDS, *ix = lv + 8 * nlods;
    for (uint32_t k = 0; k < nlods; k++) {
        uint32_t count = (uint32_t)lods[k].triangle_count;
        memcpy(lv + 8 * k, &count, 4);
        memcpy(lv + 8 * k + 4, &lods[k].error, 4);
        if (k > 0) {
            memcpy(ix, lods[k].indices, 12 * (size_t)count);
            ix += 12 * (size_t)count;
        }
    }
    uint64_t sum = limen__lod_cache_checksum(buf, len - 8);
    memcpy(buf + len - 8, &sum, 8);
    limen__out o;
    if (limen__out_open(&o, path) == LIMEN_OK) {
        if (fwrite(buf, 1, len, o.f) == len)
            limen__out_close(&o);
        else
            limen__out_abort(&o);
    }
    free(buf);
    trim(w->dir, w->limit);
}
