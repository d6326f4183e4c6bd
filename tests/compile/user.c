/* Compile check: a second translation unit that sees declarations only and calls into the
   implementation compiled elsewhere (or, with CLOTH_STATIC, in this same file). */
#ifdef CLOTH_STATIC
#define CLOTH_IMPLEMENTATION
#endif
#include "../../cloth.h"
#include "../../cloth.h" /* including twice is harmless */
#include <stdio.h>

int main(void)
{
    cloth_mesh m;
    cloth_result r = cloth_mesh_grid(&m, 3, 3, (cloth_real)1, (cloth_real)1, CLOTH_GRID_DIAGONAL_REGULAR, NULL);
    if (r != CLOTH_SUCCESS || cloth_real_size() != sizeof(cloth_real)) return 1;
    r = cloth_mesh_validate(&m, 0, NULL, NULL);
    cloth_mesh_free(&m);
    if (r != CLOTH_SUCCESS) return 1;
    printf("%s %d\n", cloth_result_string(r), cloth_version());
    return 0;
}
