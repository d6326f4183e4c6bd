/* libFuzzer harness for cloth.h's OBJ reader; see fuzz_mesh.h for what it checks.
   Build and run: bash fuzz/run.sh SECONDS. Replay the seeds under gcc: bash fuzz/replay.sh. */
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"

#define FUZZ_FORMAT CLOTH_FORMAT_OBJ
#define FUZZ_WRITE_FORMAT CLOTH_FORMAT_OBJ
#include "fuzz_mesh.h"
