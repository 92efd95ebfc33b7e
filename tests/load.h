/* load.h - how the test programs read what they check: a scene script (one that fails to
 * load is a failed check, with its message, and NULL), a text file limen wrote. Include
 * after check.h and limen.h. */
#ifndef LIMEN_TESTS_LOAD_H
#define LIMEN_TESTS_LOAD_H

#include <stdbool.h>
#include <stdio.h>

__attribute__((unused)) static limen_script *check_load_script(const char *path)
{
    limen_script *sc = NULL;
    limen_status st = limen_script_load(path, NULL, &sc);
    CHECK_MSG(st == LIMEN_OK, "%s: %s", path, sc ? limen_script_error(sc) : "");
    if (st) {
        limen_script_destroy(sc);
        return NULL;
    }
    return sc;
}

/* The file at path as text (at most size - 1 bytes, NUL-terminated; "" where it cannot be
 * read); whether all of it fit. */
__attribute__((unused)) static bool read_text(const char *path, char *text, size_t size)
{
    FILE *f = fopen(path, "rb");
    size_t n = f ? fread(text, 1, size - 1, f) : 0;
    text[n] = 0;
    if (f)
        fclose(f);
    return f && n < size - 1;
}

#endif
