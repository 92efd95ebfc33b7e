/* pages.c - big arrays' pages faulted in at once (pages.h). */
#include "core/pages.h"

#include <stdint.h>
#include <stdlib.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif
#ifdef __linux__
#include <sys/mman.h>
#include <unistd.h>
#endif

void limen__populate(void *p, size_t bytes)
{
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
    if (!p || bytes < LIMEN__POPULATE_MIN)
        return;
    long size = sysconf(_SC_PAGESIZE);
    uintptr_t page = size > 0 ? (uintptr_t)size : 4096;
    uintptr_t lo = ((uintptr_t)p + page - 1) & ~(page - 1),
              hi = ((uintptr_t)p + bytes) & ~(page - 1);
    /* an older kernel says EINVAL: the pages then come as they are touched */
    if (hi > lo)
        (void)madvise((void *)lo, hi - lo, MADV_POPULATE_WRITE);
#else
    (void)p;
    (void)bytes;
#endif
}

void *limen__malloc_populated(size_t bytes)
{
    void *p = malloc(bytes);
    limen__populate(p, bytes);
    return p;
}

void *limen__calloc_populated(size_t n, size_t size)
{
    void *p = calloc(n, size);
    if (p)
        limen__populate(p, n * size);
    return p;
}

void limen__heap_give_back(uint64_t freed)
{
#ifdef __GLIBC__
    if (freed >= LIMEN__GIVE_BACK_MIN)
        malloc_trim(0);
#else
    (void)freed;
#endif
}
