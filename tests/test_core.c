#include "runner.h"
#include "../cloth.h"

const test_case core_tests[] = {
    { NULL, NULL }
};
