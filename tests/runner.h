/* The test runner's interface: each tests/test_<module>.c defines its tests with TEST() and
   lists them, NULL-terminated, in a table named <module>_tests that tests/runner.c knows. */
#ifndef CLOTH_TEST_RUNNER_H
#define CLOTH_TEST_RUNNER_H
#include <math.h>
#include <stdio.h>

typedef struct test_case { const char *name; void (*run)(void); } test_case;

/* Report a failed check; the runner counts the current test as failed. */
void test_fail(const char *file, int line, const char *what);
/* The directory of the repository (for fixtures), from the CLOTH_ROOT environment variable or ".". */
const char *test_root(void);
/* A scratch directory for files a test writes (made once per run). */
const char *test_tmpdir(void);

#define TEST(name) static void name(void)
#define ENSURE(cond) do { if (!(cond)) { test_fail(__FILE__, __LINE__, #cond); return; } } while (0)
#define ENSURE_NEAR(a, b, tol) do { double ensure_a_ = (double)(a), ensure_b_ = (double)(b); \
    if (!(fabs(ensure_a_ - ensure_b_) <= (double)(tol))) { char ensure_msg_[256]; \
        snprintf(ensure_msg_, sizeof ensure_msg_, "%s = %.17g, %s = %.17g, tolerance %s", #a, ensure_a_, #b, ensure_b_, #tol); \
        test_fail(__FILE__, __LINE__, ensure_msg_); return; } } while (0)
#endif
