/* CLOTH_MALLOC, CLOTH_FREE and CLOTH_ASSERT supplied by the user. */
#include <stdlib.h>
static int allocations;
static void *my_malloc(size_t n) { ++allocations; return malloc(n); }
#define CLOTH_MALLOC(sz) my_malloc(sz)
#define CLOTH_FREE(p) free(p)
#define CLOTH_ASSERT(c) do { if (!(c)) abort(); } while (0)
#define CLOTH_STATIC
#define CLOTH_IMPLEMENTATION
#include "../../cloth.h"
int main(void)
{
    cloth_mesh m;
    if (cloth_mesh_icosphere(&m, 1, 1, NULL) != CLOTH_SUCCESS) return 1;
    cloth_mesh_free(&m);
    return allocations > 0 ? 0 : 1;
}
