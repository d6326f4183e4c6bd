#include "runner.h"
#include "../cloth.h"

const test_case physics_tests[] = {
    { NULL, NULL }
};
