/* The test runner: runs every listed test whose "module.name" contains the filter given as the
   first argument (all tests without one). Its last line is exactly "N passed, N failed". */
#include "runner.h"
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#ifdef TEST_ONLY_SUITE /* for building one module's tests alone */
#define SUITES_EXPAND(X, s) X(s)
#define SUITES(X) SUITES_EXPAND(X, TEST_ONLY_SUITE)
#else
#define SUITES(X) X(core) X(mesh) X(io) X(meshio) X(material) X(forces) X(linsolve) X(bvh) X(ccd) X(qp) X(contact) X(integrate) X(physics) X(checker) X(stress)
#endif
#define DECLARE(m) extern const test_case m##_tests[];
SUITES(DECLARE)
typedef struct suite { const char *name; const test_case *tests; } suite;
#define ENTRY(m) { #m, m##_tests },
static const suite suites[] = { SUITES(ENTRY) };

static int current_failed;

void test_fail(const char *file, int line, const char *what)
{
    printf("    FAILED %s:%d: %s\n", file, line, what);
    current_failed = 1;
}

const char *test_root(void)
{
    const char *r = getenv("CLOTH_ROOT");
    return r && *r ? r : ".";
}

const char *test_tmpdir(void)
{
    static char dir[256];
    if (!dir[0]) {
        snprintf(dir, sizeof dir, "/tmp/cloth-test-%ld", (long)getpid());
        mkdir(dir, 0700);
    }
    return dir;
}

int main(int argc, char **argv)
{
    const char *filter = argc > 1 ? argv[1] : "";
    int passed = 0, failed = 0;
    size_t s;
    setvbuf(stdout, NULL, _IONBF, 0);
    for (s = 0; s < sizeof suites / sizeof suites[0]; ++s) {
        const test_case *t;
        for (t = suites[s].tests; t->name; ++t) {
            char full[256];
            snprintf(full, sizeof full, "%s.%s", suites[s].name, t->name);
            if (!strstr(full, filter)) continue;
            current_failed = 0;
            t->run();
            if (current_failed) { ++failed; printf("FAIL %s\n", full); }
            else { ++passed; printf("ok   %s\n", full); }
        }
    }
    printf("%d passed, %d failed\n", passed, failed);
    return failed ? 1 : 0;
}
