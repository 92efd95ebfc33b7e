/* check.h - a tiny test runner: a table of test functions, one summary line.
 *
 *   static void test_thing(void) { CHECK(1 + 1 == 2); CHECK_NEAR(x, 1.0, 1e-6); }
 *   static const check_case cases[] = { {"thing", test_thing}, {0} };
 *   int main(int argc, char **argv) { return check_run(argc, argv, cases); }
 *
 * A failed CHECK prints file:line and the expression and marks the current test failed;
 * the test goes on. The run ends with "N passed, N failed". An argument filters tests by
 * substring.
 */
#ifndef LIMEN_CHECK_H
#define LIMEN_CHECK_H

#include <math.h>
#include <stdio.h>
#include <string.h>

typedef struct check_case { const char *name; void (*fn)(void); } check_case;

static int check__failures;   /* failures in the running test */
static int check__reported;   /* failure lines printed in the running test */

#define CHECK_MSG(cond, ...)                                                         \
    do {                                                                             \
        if (!(cond)) {                                                               \
            check__failures++;                                                       \
            if (check__reported++ < 10) {                                            \
                fprintf(stderr, "  %s:%d: ", __FILE__, __LINE__);                    \
                fprintf(stderr, __VA_ARGS__);                                        \
                fputc('\n', stderr);                                                 \
            }                                                                        \
        }                                                                            \
    } while (0)
#define CHECK(cond) CHECK_MSG(cond, "check failed: %s", #cond)
#define CHECK_NEAR(a, b, tol)                                                        \
    do {                                                                             \
        double check__a = (double)(a), check__b = (double)(b);                       \
        CHECK_MSG(fabs(check__a - check__b) <= (tol),                                \
                  "%s = %.9g, expected %s = %.9g (tol %g)", #a, check__a, #b,        \
                  check__b, (double)(tol));                                          \
    } while (0)
#define CHECK_OK(expr)                                                               \
    do {                                                                             \
        int check__st = (int)(expr);                                                 \
        CHECK_MSG(check__st == 0, "%s returned %d", #expr, check__st);               \
    } while (0)

static int check_run(int argc, char **argv, const check_case *cases)
{
    int passed = 0, failed = 0;
    for (const check_case *c = cases; c->name; c++) {
        if (argc > 1 && !strstr(c->name, argv[1]))
            continue;
        check__failures = 0;
        check__reported = 0;
        c->fn();
        if (check__failures) {
            failed++;
            fprintf(stderr, "FAIL %s (%d checks failed)\n", c->name, check__failures);
        } else {
            passed++;
            printf("ok   %s\n", c->name);
        }
        fflush(stdout);
    }
    printf("%d passed, %d failed\n", passed, failed);
    return failed ? 1 : 0;
}

#endif
