/* cache_dir.h - the level cache's folder as tests see it (core/lod_cache.c's entries). */
#ifndef LIMEN_TESTS_CACHE_DIR_H
#define LIMEN_TESTS_CACHE_DIR_H

#include <dirent.h>
#include <stdio.h>
#include <string.h>

/* The cache folder's entries: how many, and the path of the last found. */
static inline int entries(const char *dir, char *path, size_t size)
{
    DIR *d = opendir(dir);
    int n = 0;
    for (struct dirent *e; d && (e = readdir(d));)
        if (!strncmp(e->d_name, "lod-", 4) && strstr(e->d_name, ".bin") &&
            !strstr(e->d_name, ".tmp")) {
            snprintf(path, size, "%s/%s", dir, e->d_name);
            n++;
        }
    if (d)
        closedir(d);
    return n;
}

#endif
