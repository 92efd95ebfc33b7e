/* confine.c - the one way in for every file a scene reads (core/confine.h).
 *
 * A safe scene reads beneath the folder of its top-level script, fixed once when the script
 * is loaded: a chunk name a script invents or the C function that calls the loader cannot
 * move it. Each path is resolved on descriptors, beneath the folder's own, by the kernel
 * (openat2 with RESOLVE_BENEATH | RESOLVE_NO_MAGICLINKS: "..", an absolute link or a link
 * that climbs out fails with EXDEV, whatever lies outside); where openat2 is missing (ENOSYS:
 * kernels before 5.6, some sandboxes) the walk is done here, one component at a time with
 * O_NOFOLLOW, refusing ".." and every link. Nothing is checked by name before the open, so a
 * file swapped for a link between a check and the open cannot lead out.
 *
 * Files open with O_NONBLOCK and are then checked with fstat: a FIFO or a device is refused
 * at once instead of blocking the script (and the viewer) for ever. */
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <linux/openat2.h>

#include "core/confine.h"
#include "core/internal.h"
#include "core/pages.h"

#ifndef SYS_openat2
#define SYS_openat2 437
#endif

int limen__confine_walk_only;   /* tests: as if openat2 were missing */

void limen__confine_init(limen__confine *box, const char *script_path)
{
    memset(box, 0, sizeof *box);
    box->on = true;
    const char *slash = script_path ? strrchr(script_path, '/') : NULL;
    if (!slash)
        snprintf(box->prefix, sizeof box->prefix, ".");
    else if (slash == script_path)
        snprintf(box->prefix, sizeof box->prefix, "/");
    else if ((size_t)(slash - script_path) < sizeof box->prefix)
        snprintf(box->prefix, sizeof box->prefix, "%.*s", (int)(slash - script_path),
                 script_path);
    else
        box->prefix[0] = '\0';     /* too long: nothing opens */
    box->dir = box->prefix[0] ? open(box->prefix, O_PATH | O_DIRECTORY | O_CLOEXEC) : -1;
}

void limen__confine_close(limen__confine *box)
{
    if (box->on && box->dir >= 0)
        close(box->dir);
    box->dir = -1;
}

/* The part of path beneath box's folder, or NULL if path does not name a file there. */
static const char *beneath(const limen__confine *box, const char *path)
{
    size_t n = strlen(box->prefix);
    const char *rest = NULL;
    if (strcmp(box->prefix, "/") == 0 && path[0] == '/')
        rest = path + 1;
    else if (n && strncmp(path, box->prefix, n) == 0 && path[n] == '/')
        rest = path + n + 1;
    else if (strcmp(box->prefix, ".") == 0 && path[0] != '/')
        rest = path;
    if (!rest)
        return NULL;
    while (*rest == '/')
        rest++;
    return *rest ? rest : NULL;
}

static const char *reason(int err)
{
    switch (err) {
    case ENOENT: return "not found";
    case EXDEV: return "a safe script reads files only under its own folder (it leads out of it)";
    case ELOOP: return "a link (a safe script reads files only under its own folder)";
    case ENOTDIR: return "a folder on the way is not a folder";
    case EACCES: case EPERM: return "not readable";
    case EISDIR: return "a folder, not a file";
    case ENAMETOOLONG: return "name too long";
    default: return strerror(err);
    }
}

/* The walk where openat2 is missing: each component opened beneath the last, no links. */
static int walk(int dir, const char *rest, int *err)
{
    char part[PATH_MAX];
    int at = dir;
    for (;;) {
        size_t n = strcspn(rest, "/");
        if (n >= sizeof part) {
            *err = ENAMETOOLONG;
            break;
        }
        memcpy(part, rest, n);
        part[n] = '\0';
        rest += n;
        while (*rest == '/')
            rest++;
        if (n == 2 && part[0] == '.' && part[1] == '.') {
            *err = EXDEV;
            break;
        }
        bool last = !*rest;
        int fd = openat(at, n == 0 ? "." : part,
                        last ? O_RDONLY | O_NONBLOCK | O_NOFOLLOW | O_NOCTTY | O_CLOEXEC
                             : O_PATH | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
        if (fd < 0)
            *err = errno == ENOTDIR && !last ? ELOOP : errno;   /* a link where a folder was */
        if (at != dir)
            close(at);
        if (fd < 0 || last)
            return fd;
        at = fd;
    }
    if (at != dir)
        close(at);
    return -1;
}

int limen__confine_open(const limen__confine *box, const char *path, struct stat *st,
                        char *why, size_t why_size)
{
    int fd = -1, err = 0;
    if (!path || !path[0]) {
        snprintf(why, why_size, "no file name");
        return -1;
    }
    if (!box || !box->on) {
        fd = open(path, O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
        err = errno;
    } else {
        const char *rest = beneath(box, path);
        if (!rest || box->dir < 0) {
            snprintf(why, why_size, "%s", rest ? "not found" : reason(EXDEV));
            return -1;
        }
        if (!limen__confine_walk_only) {
            struct open_how how = { .flags = O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC,
                                    .resolve = RESOLVE_BENEATH | RESOLVE_NO_MAGICLINKS };
            fd = (int)syscall(SYS_openat2, box->dir, rest, &how, sizeof how);
            err = errno;
        }
        if (limen__confine_walk_only || (fd < 0 && (err == ENOSYS || err == EPERM)))
            fd = walk(box->dir, rest, &err);    /* EPERM: a seccomp filter that refuses it */
    }
    if (fd < 0) {
        snprintf(why, why_size, "%s", reason(err));
        return -1;
    }
    if (fstat(fd, st) != 0 || !S_ISREG(st->st_mode)) {
        close(fd);
        snprintf(why, why_size, "not a regular file");
        return -1;
    }
    return fd;
}

int limen__confine_read(const limen__confine *box, const char *path, size_t max,
                        unsigned char **data, size_t *len, struct stat *st, char *why,
                        size_t why_size)
{
    *data = NULL;
    *len = 0;
    int fd = limen__confine_open(box, path, st, why, why_size);
    if (fd < 0)
        return LIMEN__CONFINE_NO_OPEN;
    if ((uint64_t)st->st_size > max) {
        close(fd);
        snprintf(why, why_size, "a file of %.1f MiB, more than the %.1f MiB allowed",
                 st->st_size / 1048576.0, max / 1048576.0);
        return LIMEN__CONFINE_TOO_LARGE;
    }
    /* what fstat said, and one byte more to see a file that grew meanwhile */
    size_t cap = (size_t)st->st_size + 1, n = 0;
    unsigned char *buf = limen__malloc_populated(cap);   /* read into whole */
    if (!buf) {
        close(fd);
        snprintf(why, why_size, "out of memory");
        return LIMEN__CONFINE_TOO_LARGE;
    }
    for (;;) {
        ssize_t got = read(fd, buf + n, cap - n);
        if (got < 0 && errno == EINTR)
            continue;
        if (got < 0) {
            snprintf(why, why_size, "cannot read: %s", strerror(errno));
            break;
        }
        if (got == 0) {
            close(fd);
            *data = buf;
            *len = n;
            return 0;
        }
        n += (size_t)got;
        if (n == cap) {
            snprintf(why, why_size, "it changed while it was read");
            break;
        }
    }
    close(fd);
    free(buf);
    return LIMEN__CONFINE_NO_READ;
}

bool limen__read_at(int fd, void *buf, size_t n, uint64_t off)
{
    size_t got = 0;
    while (got < n) {
        ssize_t r = pread(fd, (unsigned char *)buf + got, n - got, (off_t)(off + got));
        if (r < 0 && errno == EINTR)
            continue;
        if (r <= 0) {
            errno = r == 0 ? EIO : errno;
            return false;
        }
        got += (size_t)r;
    }
    return true;
}

limen_status limen__file_read(limen_scene *s, const char *path, unsigned char **data,
                              size_t *len, struct stat *st)
{
    limen__load *ld = s->load;
    size_t max = SIZE_MAX;
    if (ld)
        max = ld->read_bytes >= ld->max_bytes ? 0 : ld->max_bytes - ld->read_bytes;
    char why[160];
    int got = limen__confine_read(ld ? ld->box : NULL, path, max, data, len, st, why, sizeof why);
    if (got == LIMEN__CONFINE_TOO_LARGE)
        return limen__fail(s, LIMEN_ERR_NOMEM, "%s: %s", path, why);
    if (got)
        return limen__fail(s, LIMEN_ERR_IO, "%s: %s%s", path,
                           got == LIMEN__CONFINE_NO_OPEN ? "cannot open: " : "", why);
    if (*len == 0) {
        free(*data);
        *data = NULL;
        return limen__fail(s, LIMEN_ERR_IO, "%s: empty file", path);
    }
    if (ld)
        ld->read_bytes += *len;
    return LIMEN_OK;
}

bool limen__load_contained(const limen_scene *s)
{
    return s->load && s->load->safe && !s->load->inside;
}
