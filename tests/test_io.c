#include "runner.h"
#include "../cloth.h"

const test_case io_tests[] = {
    { NULL, NULL }
};
