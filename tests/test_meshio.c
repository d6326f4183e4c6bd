#include "runner.h"
#include "../cloth.h"

const test_case meshio_tests[] = {
    { NULL, NULL }
};
