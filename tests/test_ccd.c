#include "runner.h"
#include "../cloth.h"

const test_case ccd_tests[] = {
    { NULL, NULL }
};
