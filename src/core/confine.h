/* confine.h - the one way in for every file a scene reads (scripts, modules, meshes, the files
 * a mesh file names, images): beneath one folder, without following links out of it, regular
 * files only, never blocking, and what is read counted. Not part of the public API. */
#ifndef LIMEN_CORE_CONFINE_H
#define LIMEN_CORE_CONFINE_H

#include <stdbool.h>
#include <stdint.h>
#include <stddef.h>
#include <sys/stat.h>

#include "limen.h"

/* A folder files are read beneath. Paths name files as "prefix/rest" (prefix the folder as the
 * script's path named it: "scenes", "/tmp/x", "."); rest is resolved beneath the folder's
 * descriptor, decided on the descriptors opened, never by a check before the open. */
typedef struct limen__confine {
    bool on;                    /* false: any path, as given (trusted) */
    int dir;                    /* O_PATH descriptor of the folder, -1 if it could not open */
    char prefix[1024];
} limen__confine;

/* What a load made on behalf of a script may do and spend; a scene points at one (s->load)
 * while a script loads a file into it, NULL otherwise (the C API: trusted, no limits). */
typedef struct limen__load {
    const limen__confine *box;  /* where files may be read; NULL: anywhere */
    bool safe;                  /* safe scene: allowed formats only, import in a child */
    size_t max_bytes;           /* memory the script has left */
    double cpu_left;            /* seconds of processor time left; 0: no limit */
    double cpu_spent;           /* out: processor time spent by contained imports */
    size_t read_bytes;          /* bytes read so far by this load */
    bool inside;                /* running in the child already: contain nothing more */
} limen__load;

/* Whether decoding and importing for s runs in a child (a safe load, not already in one). */
bool limen__load_contained(const limen_scene *s);

/* Fixes box to the folder of the script at script_path (its prefix as the path names it). */
void limen__confine_init(limen__confine *box, const char *script_path);
void limen__confine_close(limen__confine *box);

/* Opens path for reading through box (NULL or off: as given): a regular file only, opened
 * without blocking (a FIFO or a device is refused, not waited on). Returns the descriptor, or
 * -1 with why ("not found", "... only under its own folder ...", ...): the reasons never tell whether
 * a file outside exists or how large it is. st gets the file's status. */
int limen__confine_open(const limen__confine *box, const char *path, struct stat *st,
                        char *why, size_t why_size);

/* What limen__confine_read refused, beside 0: the file did not open, was larger than max
 * (or no memory held it), or could not be read to its end. */
enum { LIMEN__CONFINE_NO_OPEN = -1, LIMEN__CONFINE_TOO_LARGE = -2, LIMEN__CONFINE_NO_READ = -3 };
/* Reads the whole file at path through box, refusing one of more than max bytes (a file
 * inside the folder: its size may be told). *data (malloc'd) and *len; returns 0, or one of
 * LIMEN__CONFINE_* with why. */
int limen__confine_read(const limen__confine *box, const char *path, size_t max,
                        unsigned char **data, size_t *len, struct stat *st, char *why,
                        size_t why_size);

/* The same for a scene: through s->load's box and limits when a script loads, charging the
 * bytes read to it; a failure is the scene's message, naming path. */
limen_status limen__file_read(limen_scene *s, const char *path, unsigned char **data,
                              size_t *len, struct stat *st);

/* Reads n bytes at off from fd (pread, again where interrupted); false where the file ends
 * first (errno EIO) or cannot be read. */
bool limen__read_at(int fd, void *buf, size_t n, uint64_t off);

/* tests only: walk the path with O_NOFOLLOW as where openat2 is missing */
extern int limen__confine_walk_only;

#endif
