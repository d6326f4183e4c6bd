#include "runner.h"
#include "../cloth.h"

const test_case mesh_tests[] = {
    { NULL, NULL }
};
