/* The one translation unit of the test program that compiles cloth.h's implementation; every
   test_<module>.c includes the header alone, so the tests also check two translation units. */
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"
