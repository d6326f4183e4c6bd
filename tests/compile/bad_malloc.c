/* Must NOT compile: CLOTH_MALLOC without CLOTH_FREE. */
#define CLOTH_MALLOC(sz) malloc(sz)
#define CLOTH_IMPLEMENTATION
#include "../../cloth.h"
int main(void) { return 0; }
