/* scratch.h - scene scripts written to a scratch directory for the script tests: script(name,
 * text) writes one and returns its path; scratch_main runs the cases there and removes it.
 * Include after check.h. */
#ifndef LIMEN_TESTS_SCRATCH_H
#define LIMEN_TESTS_SCRATCH_H

#include <stdlib.h>
#include <unistd.h>

static char dir[64];
static char files[128][128];
static int nfiles;

/* Writes text to dir/name and returns the path (valid until the end of the run). */
static const char *script(const char *name, const char *text)
{
    char *path = files[nfiles < 128 ? nfiles++ : 127];
    snprintf(path, sizeof files[0], "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    if (f) {
        fputs(text, f);
        fclose(f);
    }
    return path;
}

#define HEAD "local limen = require \"limen\"\nlocal s = limen.scene {}\n"   /* lines 1-2 */

static int scratch_main(int argc, char **argv, const check_case *cases)
{
    snprintf(dir, sizeof dir, "/tmp/limen-script.XXXXXX");
    if (!mkdtemp(dir)) {
        perror("mkdtemp");
        return 1;
    }
    int rc = check_run(argc, argv, cases);
    for (int i = 0; i < nfiles; i++)
        unlink(files[i]);
    rmdir(dir);
    return rc;
}

#endif
