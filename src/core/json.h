/* json.h - a small JSON reader for what a model file says that its importer does not pass
 * on (glTF's KHR_lights_punctual ranges): the text parsed into a flat array of values, each
 * knowing its first child and next sibling. Strings are left as written (escapes not
 * decoded), pointing into the text. Bounded: nesting depth and value count are limited, and
 * bad text is refused, never read past its end. Not part of the public API. */
#ifndef LIMEN_CORE_JSON_H
#define LIMEN_CORE_JSON_H

#include <stdbool.h>
#include <stddef.h>

enum { LIMEN__JSON_NULL, LIMEN__JSON_BOOL, LIMEN__JSON_NUMBER, LIMEN__JSON_STRING,
       LIMEN__JSON_ARRAY, LIMEN__JSON_OBJECT };

typedef struct limen__json_value {
    int type;                   /* LIMEN__JSON_* */
    double number;              /* numbers; booleans 0 or 1 */
    const char *str;            /* strings: the text between the quotes */
    size_t len;
    const char *key;            /* an object's member: its key, as str */
    size_t klen;
    int child, next;            /* first child, next sibling: indices, -1 for none */
} limen__json_value;

typedef struct limen__json {
    limen__json_value *v;       /* v[0] is the document's value */
    int n, cap;
} limen__json;

/* Parses text[0..len) (one value, white space around it); false for bad or too deep text, a
 * number beyond a double's range, more than max_values values, or no memory. free(json->v)
 * after either. */
bool limen__json_parse(limen__json *json, const char *text, size_t len, int max_values);
/* Member `key` of object i (-1 if i is not an object or has none); element k of array i. */
int limen__json_get(const limen__json *json, int i, const char *key);
int limen__json_at(const limen__json *json, int i, int k);
/* Whether string value i is exactly s. */
bool limen__json_is(const limen__json *json, int i, const char *s);

#endif
