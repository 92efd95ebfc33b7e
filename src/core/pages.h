/* pages.h - big arrays' pages faulted in at once. */
#ifndef LIMEN_PAGES_H
#define LIMEN_PAGES_H

#include <stddef.h>
#include <stdint.h>

/* Makes the whole pages of [p, p + bytes) resident and writable in one call (Linux 5.14's
 * MADV_POPULATE_WRITE), where bytes is at least LIMEN__POPULATE_MIN: for an array about to be
 * written through, whose pages would otherwise come one fault at a time. On a virtual
 * machine a fault costs several microseconds (here 11 us a 4 kB page, 2.7 ms a megabyte,
 * against 0.6 us populated): a 1.6M-triangle mesh's levels touch half a gigabyte. Never for
 * an array written sparsely (its untouched pages would become resident). Does nothing where
 * the system cannot; the contents are kept. */
void limen__populate(void *p, size_t bytes);

#define LIMEN__POPULATE_MIN ((size_t)256 << 10)

/* malloc(bytes), populated (limen__populate). */
void *limen__malloc_populated(size_t bytes);
/* calloc(n, size), populated: zeros read or written through. */
void *limen__calloc_populated(size_t n, size_t size);

/* Gives the heap's free pages back to the system (glibc's malloc_trim) after a step that
 * freed about `freed` bytes of temporaries, where that is at least LIMEN__GIVE_BACK_MIN:
 * a big mesh's import or level leaves hundreds of megabytes that glibc would otherwise keep
 * resident. Not after a small step: what would go back is mostly the heap's free room, which
 * the next load faults in again (assimp's OBJ reader takes and fills a 16 MiB buffer for any
 * file: 4,096 faults, 45 ms here; a four-vertex OBJ's load 54 ms against 1.3 ms with the
 * heap kept). */
void limen__heap_give_back(uint64_t freed);

#define LIMEN__GIVE_BACK_MIN ((uint64_t)16 << 20)

#endif
