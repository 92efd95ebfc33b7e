/* json.c - the small JSON reader of json.h: recursive descent over a length-bounded text,
 * nesting at most MAX_DEPTH deep, values appended to one growing array. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core/json.h"
#include "core/reserve.h"

#define MAX_DEPTH 64

typedef struct reader {
    const char *p, *end;
    limen__json *j;
    int max_values;
} reader;

static void skip_space(reader *r)
{
    while (r->p < r->end && (*r->p == ' ' || *r->p == '\t' || *r->p == '\n' || *r->p == '\r'))
        r->p++;
}

static int new_value(reader *r, int type)
{
    limen__json *j = r->j;
    if (j->n >= r->max_values)
        return -1;
    if (!limen__reserve((void **)&j->v, &j->cap, j->n + 1, sizeof *j->v))
        return -1;
    j->v[j->n] = (limen__json_value){ .type = type, .child = -1, .next = -1 };
    return j->n++;
}

/* A string from the opening quote on: *s, *len its insides. */
static bool read_string(reader *r, const char **s, size_t *len)
{
    if (r->p >= r->end || *r->p != '"')
        return false;
    const char *start = ++r->p;
    while (r->p < r->end && *r->p != '"') {
        if ((unsigned char)*r->p < 0x20)
            return false;
        if (*r->p == '\\') {
            if (++r->p >= r->end)
                return false;
        }
        r->p++;
    }
    if (r->p >= r->end)
        return false;
    *s = start;
    *len = (size_t)(r->p - start);
    r->p++;
    return true;
}

static bool literal(reader *r, const char *word)
{
    size_t n = strlen(word);
    if ((size_t)(r->end - r->p) < n || memcmp(r->p, word, n) != 0)
        return false;
    r->p += n;
    return true;
}

static int read_value(reader *r, int depth);

/* The members or elements of the container at index c, up to its closing `close`. */
static bool read_items(reader *r, int c, char close, int depth)
{
    int last = -1;
    skip_space(r);
    if (r->p < r->end && *r->p == close) {
        r->p++;
        return true;
    }
    for (;;) {
        const char *key = NULL;
        size_t klen = 0;
        skip_space(r);
        if (close == '}') {
            if (!read_string(r, &key, &klen))
                return false;
            skip_space(r);
            if (r->p >= r->end || *r->p != ':')
                return false;
            r->p++;
        }
        int v = read_value(r, depth + 1);
        if (v < 0)
            return false;
        r->j->v[v].key = key;
        r->j->v[v].klen = klen;
        if (last < 0)
            r->j->v[c].child = v;
        else
            r->j->v[last].next = v;
        last = v;
        skip_space(r);
        if (r->p >= r->end)
            return false;
        if (*r->p == close) {
            r->p++;
            return true;
        }
        if (*r->p != ',')
            return false;
        r->p++;
    }
}

static int read_value(reader *r, int depth)
{
    skip_space(r);
    if (depth > MAX_DEPTH || r->p >= r->end)
        return -1;
    char c = *r->p;
    int v;
    if (c == '{' || c == '[') {
        if ((v = new_value(r, c == '{' ? LIMEN__JSON_OBJECT : LIMEN__JSON_ARRAY)) < 0)
            return -1;
        r->p++;
        return read_items(r, v, c == '{' ? '}' : ']', depth) ? v : -1;
    }
    if (c == '"') {
        const char *s;
        size_t len;
        if ((v = new_value(r, LIMEN__JSON_STRING)) < 0 || !read_string(r, &s, &len))
            return -1;
        r->j->v[v].str = s;
        r->j->v[v].len = len;
        return v;
    }
    if (literal(r, "true") || literal(r, "false")) {
        if ((v = new_value(r, LIMEN__JSON_BOOL)) >= 0)
            r->j->v[v].number = r->p[-1] == 'e' && r->p[-2] == 'u';
        return v;
    }
    if (literal(r, "null"))
        return new_value(r, LIMEN__JSON_NULL);
    /* a number: strtod on a copy (the text need not end in a zero), of the whole number
     * however many digits it has (a file may write pi to 100 places) */
    size_t n = 0;
    while (r->p + n < r->end && r->p[n] && strchr("+-0123456789.eE", r->p[n]))
        n++;
    if (n == 0)
        return -1;
    char buf[64], *text = n < sizeof buf ? buf : malloc(n + 1), *stop;
    if (!text)
        return -1;
    memcpy(text, r->p, n);
    text[n] = '\0';
    double d = strtod(text, &stop);
    bool whole = stop == text + n;
    if (text != buf)
        free(text);
    /* JSON has no infinities: a number too large for a double is refused, not made one */
    if (!whole || !isfinite(d) || (v = new_value(r, LIMEN__JSON_NUMBER)) < 0)
        return -1;
    r->j->v[v].number = d;
    r->p += n;
    return v;
}

bool limen__json_parse(limen__json *json, const char *text, size_t len, int max_values)
{
    memset(json, 0, sizeof *json);
    reader r = { .p = text, .end = text + len, .j = json, .max_values = max_values };
    if (read_value(&r, 0) != 0)
        return false;
    skip_space(&r);
    return r.p == r.end;
}

int limen__json_get(const limen__json *json, int i, const char *key)
{
    if (i < 0 || i >= json->n || json->v[i].type != LIMEN__JSON_OBJECT)
        return -1;
    size_t n = strlen(key);
    for (int c = json->v[i].child; c >= 0; c = json->v[c].next)
        if (json->v[c].klen == n && memcmp(json->v[c].key, key, n) == 0)
            return c;
    return -1;
}

int limen__json_at(const limen__json *json, int i, int k)
{
    if (i < 0 || i >= json->n || json->v[i].type != LIMEN__JSON_ARRAY || k < 0)
        return -1;
    int c = json->v[i].child;
    while (c >= 0 && k-- > 0)
        c = json->v[c].next;
    return c;
}

bool limen__json_is(const limen__json *json, int i, const char *s)
{
    return i >= 0 && i < json->n && json->v[i].type == LIMEN__JSON_STRING &&
           json->v[i].len == strlen(s) && memcmp(json->v[i].str, s, json->v[i].len) == 0;
}
