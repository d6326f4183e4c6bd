/* The one translation unit of the test program that compiles cloth.h's implementation; every
   test_<module>.c includes the header alone, so the tests also check two translation units. */
#define CLOTH_IMPLEMENTATION
/* every re-solve that keeps parts of the solve before it checks them against a fresh make
   (cloth.h, cloth__pcg_check_reuse) */
#define CLOTH__CHECK_REUSE 1
#include "../cloth.h"
