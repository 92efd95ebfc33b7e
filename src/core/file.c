/* file.c - every file limen writes is complete or absent.
 *
 * A file is written under a temporary name in its own folder (so that the rename stays on
 * one file system), flushed, synced and closed, and only then renamed over the target: a
 * failed write (a full disk, an unwritable folder, an I/O error) leaves the old file as it
 * was and no temporary behind. A target that exists and is not a regular file (/dev/null,
 * /dev/full, a pipe) is written in place, since renaming over it would replace the device
 * rather than write to it; its errors are reported all the same. */
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "core/internal.h"

limen_status limen__out_open(limen__out *o, const char *path)
{
    memset(o, 0, sizeof *o);
    if (!path || !path[0])
        return LIMEN_ERR_ARG;
    size_t len = strlen(path);
    if (len + 32 > sizeof o->tmp)
        return LIMEN_ERR_ARG;   /* no room for the temporary name: refuse, never truncate */
    memcpy(o->path, path, len + 1);
    struct stat st;
    if (stat(path, &st) == 0 && !S_ISREG(st.st_mode)) {
        o->f = fopen(path, "w");
        o->direct = true;
        return o->f ? LIMEN_OK : LIMEN_ERR_IO;
    }
    /* a fresh name with O_EXCL: 0666 less the umask, like fopen, and never an existing file */
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    for (unsigned attempt = 0; attempt < 64; attempt++) {
        snprintf(o->tmp, sizeof o->tmp, "%s.tmp%ld.%lx", path, (long)getpid(),
                 (unsigned long)ts.tv_nsec ^ ((unsigned long)attempt * 2654435761u) ^
                     (unsigned long)(uintptr_t)o);
        int fd = open(o->tmp, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd < 0) {
            if (errno == EEXIST)
                continue;
            break;
        }
        o->f = fdopen(fd, "w");
        if (!o->f) {
            close(fd);
            unlink(o->tmp);
            break;
        }
        return LIMEN_OK;
    }
    o->tmp[0] = 0;
    return LIMEN_ERR_IO;
}

void limen__out_abort(limen__out *o)
{
    if (o->f)
        fclose(o->f);
    o->f = NULL;
    if (!o->direct && o->tmp[0])
        unlink(o->tmp);
    o->tmp[0] = 0;
}

limen_status limen__out_close(limen__out *o)
{
    if (!o->f)
        return LIMEN_ERR_IO;
    bool ok = !ferror(o->f) && fflush(o->f) == 0;
    if (ok && !o->direct)
        ok = fsync(fileno(o->f)) == 0;
    ok = fclose(o->f) == 0 && ok;
    o->f = NULL;
    if (o->direct)
        return ok ? LIMEN_OK : LIMEN_ERR_IO;
    if (ok)
        ok = rename(o->tmp, o->path) == 0;
    if (!ok)
        unlink(o->tmp);
    o->tmp[0] = 0;
    return ok ? LIMEN_OK : LIMEN_ERR_IO;
}
