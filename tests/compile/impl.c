/* Compile check: the translation unit that holds the implementation. */
#define CLOTH_IMPLEMENTATION
#include "../../cloth.h"
