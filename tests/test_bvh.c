#include "runner.h"
#include "../cloth.h"

const test_case bvh_tests[] = {
    { NULL, NULL }
};
