#include "runner.h"
#include "../cloth.h"

const test_case linsolve_tests[] = {
    { NULL, NULL }
};
