/* Compile check with the thread pool (CLOTH_THREADS, linked with -pthread): a world stepped on
   2 threads gives the bits of a single-threaded one. */
#define CLOTH_IMPLEMENTATION
#include "../../cloth.h"
#include <stdio.h>
#include <string.h>

static int run(int32_t threads, cloth_real *out)
{
    cloth_world_def d = cloth_default_world_def();
    cloth_piece_def p = cloth_default_piece_def();
    cloth_world *w = NULL;
    cloth_mesh m;
    int32_t piece, i;
    cloth_result r;
    d.threads = threads;
    if (cloth_mesh_grid(&m, 9, 9, (cloth_real)1, (cloth_real)1, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL) != CLOTH_SUCCESS) return 0;
    r = cloth_world_create(&w, &d);
    if (r == CLOTH_SUCCESS) r = cloth_world_add_piece(w, &m, &p, &piece);
    if (r == CLOTH_SUCCESS) r = cloth_world_pin(w, piece, 0, NULL);
    for (i = 0; i < 5 && r == CLOTH_SUCCESS; ++i) r = cloth_world_step(w, (cloth_real)1 / 60, NULL);
    if (r == CLOTH_SUCCESS) memcpy(out, cloth_world_positions(w, piece), sizeof(cloth_real) * 3 * 81);
    cloth_world_destroy(w);
    cloth_mesh_free(&m);
    return r == CLOTH_SUCCESS;
}

int main(void)
{
    static cloth_real a[3 * 81], b[3 * 81];
    if (!run(0, a) || !run(2, b) || memcmp(a, b, sizeof a) != 0) return 1;
    printf("threads: bit-identical\n");
    return 0;
}
