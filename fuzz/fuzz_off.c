/* libFuzzer harness for cloth.h's OFF reader; see fuzz_mesh.h for what it checks.
   Build and run: bash fuzz/run.sh SECONDS. Replay the seeds under gcc: bash fuzz/replay.sh. */
#define CLOTH_IMPLEMENTATION
#include "../cloth.h"

#define FUZZ_FORMAT CLOTH_FORMAT_OFF
#define FUZZ_WRITE_FORMAT CLOTH_FORMAT_OFF
#include "fuzz_mesh.h"
