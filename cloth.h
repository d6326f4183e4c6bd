/* cloth.h - v0.1.0 - physically based cloth simulation in one C99 header - MIT or public domain (see end of file)

   Do this:
       #define CLOTH_IMPLEMENTATION
   before you include this file in *one* C or C++ file to create the implementation.
   Every other file includes cloth.h without the define and sees declarations only.

       #include ...
       #define CLOTH_IMPLEMENTATION
       #include "cloth.h"

   cloth.h needs libc and libm (and pthreads once the time-parallel driver is compiled in).

   CONFIGURATION (define before including, in every file that includes cloth.h
   unless the entry says otherwise)

       CLOTH_REAL         the scalar type, double by default; float is allowed. It changes the
                          ABI: define it the same way everywhere and check cloth_real_size().
       CLOTH_STATIC       make every function static to the including file (then define
                          CLOTH_IMPLEMENTATION in that same file).
       CLOTH_API          override the linkage of public functions (default: extern).
       CLOTH_MALLOC(sz)   the default allocator's allocation; define together with
       CLOTH_FREE(p)      the default allocator's release (both or neither: checked by #error).
       CLOTH_ASSERT(c)    how misuse of the API is caught (default: assert from <assert.h>).
       CLOTH_NO_STDIO     leave out everything that opens files by path (reading and writing
                          from memory buffers stays).

   MANUAL

   1. Quick start
        cloth_mesh mesh;
        cloth_result r = cloth_mesh_grid(&mesh, 33, 33, 1.0, 1.0, CLOTH_GRID_DIAGONAL_ALTERNATING, NULL);
        if (r != CLOTH_SUCCESS) { puts(cloth_result_string(r)); return 1; }
        ... mesh.x[3*i+0..2] are positions, mesh.tri[3*t+0..2] are triangles ...
        cloth_mesh_free(&mesh);

   2. Units and conventions
        SI units throughout: metres, kilograms, seconds, newtons. y is up; gravity is
        -9.81 m/s^2 along y by default. Triangles are counter-clockwise seen from the
        front side, so the front normal is (x1 - x0) x (x2 - x0). Material coordinates uv
        are the flat sewing pattern in metres. Arrays are flat: x[3*n], uv[2*n], tri[3*m].
        Indices and counts are int32_t; sizes are checked for overflow before any allocation.

   3. Thread safety
        There is no mutable global state. Different objects (meshes, topologies, worlds)
        may be used from different threads at the same time; one object is used by one
        thread at a time.

   4. Error handling
        Misuse of the API (a NULL pointer where an object is required) trips CLOTH_ASSERT.
        Bad data (a malformed file, a broken mesh, NaN coordinates, impossible parameters)
        never prints, exits or aborts: the call returns a negative cloth_result, named in
        cloth_result_string(). Parsers also say where: the line (text formats) or the byte
        offset (binary data) and the reason, in a cloth_io_error. On failure, output objects
        are left empty (all pointers NULL) and nothing is leaked.

   5. Memory
        Every function that allocates takes a `const cloth_allocator *`; NULL means the
        default (CLOTH_MALLOC/CLOTH_FREE, malloc/free unless overridden). The allocator is
        copied into the object it made, so the object is freed the same way. Every _free
        function accepts an object that is already empty.

   6. What cloth.h does NOT do
        It does not render, open windows, read images or load materials (.mtl); it does
        not remesh adaptively; it is not a rigid-body engine (obstacles are kinematic).

   MODULES (in file order; the implementation follows the same order)
        core       results, allocator, logger, seeded random numbers, version
        math       small vector helpers used inside the library
        mesh       cloth_mesh, topology, validation, generators, subdivision
        io         OBJ, PLY, VTK legacy and OFF reading and writing
        linsolve   3x3 block sparse matrix with a fixed pattern, filtered PCG
        bvh        bounding volume hierarchy over triangles
        ccd        proximity and continuous collision detection
*/
#ifndef CLOTH_H
#define CLOTH_H

/* ===================================================================================== */
/* core: version, configuration, results, allocator, logger, random numbers               */
/*       needs: libc                                                                      */
/* ===================================================================================== */

#define CLOTH_VERSION_MAJOR 0
#define CLOTH_VERSION_MINOR 1
#define CLOTH_VERSION_PATCH 0
#define CLOTH_VERSION_STRING "0.1.0"
/* One number that orders versions: major * 10000 + minor * 100 + patch. */
#define CLOTH_VERSION (CLOTH_VERSION_MAJOR * 10000 + CLOTH_VERSION_MINOR * 100 + CLOTH_VERSION_PATCH)

#include <stddef.h>
#include <stdint.h>

#ifndef CLOTH_REAL
#define CLOTH_REAL double
#endif
typedef CLOTH_REAL cloth_real;

#ifndef CLOTH_API
#ifdef CLOTH_STATIC
#if defined(__GNUC__) || defined(__clang__)
#define CLOTH_API static __attribute__((unused)) /* a caller uses only some of them */
#else
#define CLOTH_API static
#endif
#else
#define CLOTH_API extern
#endif
#endif

#if (defined(CLOTH_MALLOC) && !defined(CLOTH_FREE)) || (!defined(CLOTH_MALLOC) && defined(CLOTH_FREE))
#error "cloth.h: define both CLOTH_MALLOC and CLOTH_FREE, or neither"
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* Every fallible call returns a cloth_result: 0 is success, failures are negative. */
typedef enum cloth_result {
    CLOTH_SUCCESS = 0,
    CLOTH_ERROR_INVALID_ARGUMENT = -1,      /* a parameter is out of its documented range */
    CLOTH_ERROR_OUT_OF_MEMORY = -2,         /* the allocator returned NULL */
    CLOTH_ERROR_SIZE_OVERFLOW = -3,         /* a count or byte size does not fit */
    CLOTH_ERROR_FILE_OPEN = -4,             /* a path could not be opened */
    CLOTH_ERROR_FILE_READ = -5,             /* reading a file failed part way */
    CLOTH_ERROR_FILE_WRITE = -6,            /* writing a file or buffer failed */
    CLOTH_ERROR_PARSE = -7,                 /* a file's content is malformed (see cloth_io_error) */
    CLOTH_ERROR_UNSUPPORTED = -8,           /* well-formed but uses a feature cloth.h does not read */
    CLOTH_ERROR_TRUNCATED = -9,             /* a file ends before the data its header announces */
    CLOTH_ERROR_NOT_FINITE = -10,           /* a NaN or an infinity where a finite number is needed */
    CLOTH_ERROR_INDEX_OUT_OF_RANGE = -11,   /* a triangle names a vertex that does not exist */
    CLOTH_ERROR_DEGENERATE_TRIANGLE = -12,  /* zero or near-zero area (rest or world), or a repeated vertex */
    CLOTH_ERROR_NON_MANIFOLD_EDGE = -13,    /* an edge shared by more than two triangles */
    CLOTH_ERROR_INCONSISTENT_ORIENTATION = -14, /* two neighbours traverse their shared edge the same way */
    CLOTH_ERROR_DUPLICATE_FACE = -15,       /* two triangles over the same three vertices */
    CLOTH_ERROR_EMPTY_MESH = -16,           /* no vertices or no triangles where some are needed */
    CLOTH_ERROR_CG_NOT_CONVERGED = -17,     /* the conjugate gradient solve hit its iteration cap */
    CLOTH_ERROR_NOT_POSITIVE_DEFINITE = -18, /* a matrix that must be positive definite is not */
    CLOTH_ERROR_RESULT_COUNT_ = 19          /* not a result: the number of results, for tables */
} cloth_result;

/* A short English sentence for a result ("success", "index out of range", ...). Never NULL. */
CLOTH_API const char *cloth_result_string(cloth_result result);

/* The version this implementation was compiled as (CLOTH_VERSION) and sizeof(cloth_real) in it:
   compare them with the header a caller compiled against to catch an ABI mismatch. */
CLOTH_API int cloth_version(void);
CLOTH_API size_t cloth_real_size(void);

/* A run-time allocator: alloc(size, user) returns NULL on failure; free(ptr, user) accepts NULL.
   A cloth_allocator with alloc == NULL means the default (CLOTH_MALLOC/CLOTH_FREE). */
typedef struct cloth_allocator {
    void *(*alloc)(size_t size, void *user);
    void (*free)(void *ptr, void *user);
    void *user;
} cloth_allocator;

/* The default allocator, as a value. */
CLOTH_API cloth_allocator cloth_default_allocator(void);

/* An optional logger. cloth.h prints nothing by itself; where an object holds a logger with a
   non-NULL log function, it reports what it would otherwise keep silent about (for example a
   step that needed many CG iterations). */
typedef enum cloth_log_level { CLOTH_LOG_DEBUG = 0, CLOTH_LOG_INFO = 1, CLOTH_LOG_WARNING = 2, CLOTH_LOG_ERROR = 3 } cloth_log_level;
typedef struct cloth_logger {
    void (*log)(cloth_log_level level, const char *message, void *user);
    void *user;
} cloth_logger;

/* A seeded random number generator of the library's own (xoshiro256**, seeded through
   splitmix64), so that the same seed gives the same numbers on every platform. */
typedef struct cloth_rng { uint64_t s[4]; } cloth_rng;
CLOTH_API cloth_rng cloth_rng_make(uint64_t seed);
CLOTH_API uint64_t cloth_rng_next(cloth_rng *rng);
/* Uniform in [0, 1). */
CLOTH_API cloth_real cloth_rng_uniform(cloth_rng *rng);
/* Standard normal (mean 0, deviation 1), Box-Muller. */
CLOTH_API cloth_real cloth_rng_normal(cloth_rng *rng);

#ifdef __cplusplus
}
#endif

#include "wip/mesh_api.h"
#if !defined(CLOTH_WIP_ONLY) || defined(CLOTH_WIP_IO)
#include "wip/io_api.h"
#endif
#if !defined(CLOTH_WIP_ONLY) || defined(CLOTH_WIP_LINSOLVE)
#include "wip/linsolve_api.h"
#endif
#if !defined(CLOTH_WIP_ONLY) || defined(CLOTH_WIP_BVH)
#include "wip/bvh_api.h"
#endif
#if !defined(CLOTH_WIP_ONLY) || defined(CLOTH_WIP_CCD)
#include "wip/ccd_api.h"
#endif

#endif /* CLOTH_H */

/* ===================================================================================== */
/*                                  IMPLEMENTATION                                        */
/* ===================================================================================== */
#ifdef CLOTH_IMPLEMENTATION
#ifndef CLOTH_IMPLEMENTATION_DONE
#define CLOTH_IMPLEMENTATION_DONE

#include <string.h>
#include <math.h>
#include <float.h>
#include <limits.h>
#include <stdarg.h>
#include <stdio.h>

#ifndef CLOTH_MALLOC
#include <stdlib.h>
#define CLOTH_MALLOC(sz) malloc(sz)
#define CLOTH_FREE(p) free(p)
#endif

#ifndef CLOTH_ASSERT
#include <assert.h>
#define CLOTH_ASSERT(c) assert(c)
#endif

/* Private helpers that some configurations do not call are marked so that -Wunused stays quiet. */
#if defined(__GNUC__) || defined(__clang__)
#define CLOTH__MAYBE_UNUSED __attribute__((unused))
#else
#define CLOTH__MAYBE_UNUSED
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* ------------------------------------------------------------------------------------- */
/* core                                                                                  */
/* ------------------------------------------------------------------------------------- */

CLOTH_API const char *cloth_result_string(cloth_result result)
{
    switch (result) {
    case CLOTH_SUCCESS: return "success";
    case CLOTH_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case CLOTH_ERROR_OUT_OF_MEMORY: return "out of memory";
    case CLOTH_ERROR_SIZE_OVERFLOW: return "size overflow";
    case CLOTH_ERROR_FILE_OPEN: return "cannot open file";
    case CLOTH_ERROR_FILE_READ: return "cannot read file";
    case CLOTH_ERROR_FILE_WRITE: return "cannot write file";
    case CLOTH_ERROR_PARSE: return "parse error";
    case CLOTH_ERROR_UNSUPPORTED: return "unsupported feature";
    case CLOTH_ERROR_TRUNCATED: return "truncated data";
    case CLOTH_ERROR_NOT_FINITE: return "not a finite number";
    case CLOTH_ERROR_INDEX_OUT_OF_RANGE: return "index out of range";
    case CLOTH_ERROR_DEGENERATE_TRIANGLE: return "degenerate triangle";
    case CLOTH_ERROR_NON_MANIFOLD_EDGE: return "non-manifold edge";
    case CLOTH_ERROR_INCONSISTENT_ORIENTATION: return "inconsistent orientation";
    case CLOTH_ERROR_DUPLICATE_FACE: return "duplicate face";
    case CLOTH_ERROR_EMPTY_MESH: return "empty mesh";
    case CLOTH_ERROR_CG_NOT_CONVERGED: return "conjugate gradient did not converge";
    case CLOTH_ERROR_NOT_POSITIVE_DEFINITE: return "matrix not positive definite";
    case CLOTH_ERROR_RESULT_COUNT_: break;
    }
    return "unknown result";
}

CLOTH_API int cloth_version(void) { return CLOTH_VERSION; }
CLOTH_API size_t cloth_real_size(void) { return sizeof(cloth_real); }

static void *cloth__default_alloc(size_t size, void *user) { (void)user; return CLOTH_MALLOC(size); }
static void cloth__default_free(void *ptr, void *user) { (void)user; CLOTH_FREE(ptr); }

CLOTH_API cloth_allocator cloth_default_allocator(void)
{
    cloth_allocator a;
    a.alloc = cloth__default_alloc;
    a.free = cloth__default_free;
    a.user = NULL;
    return a;
}

/* The allocator an object keeps: the caller's if it names one, else the default. */
CLOTH__MAYBE_UNUSED static cloth_allocator cloth__allocator_or_default(const cloth_allocator *allocator)
{
    if (allocator && allocator->alloc && allocator->free) return *allocator;
    return cloth_default_allocator();
}

/* a * b + c as a size, or 0 with *ok cleared on overflow. All sizes pass through here. */
CLOTH__MAYBE_UNUSED static size_t cloth__size_mul_add(size_t a, size_t b, size_t c, int *ok)
{
    if (b != 0 && a > (SIZE_MAX - c) / b) { *ok = 0; return 0; }
    return a * b + c;
}

/* Allocation of count elements of elem_size bytes, overflow-checked; NULL on failure.
   A count of zero allocates one byte so that a valid empty array is not NULL. */
CLOTH__MAYBE_UNUSED static void *cloth__alloc_array(const cloth_allocator *a, size_t count, size_t elem_size)
{
    int ok = 1;
    size_t bytes = cloth__size_mul_add(count, elem_size, 0, &ok);
    if (!ok) return NULL;
    return a->alloc(bytes ? bytes : 1, a->user);
}

CLOTH__MAYBE_UNUSED static void cloth__free(const cloth_allocator *a, void *p)
{
    if (p) a->free(p, a->user);
}

/* Report through the logger, if there is one; formatting happens only then. */
CLOTH__MAYBE_UNUSED static void cloth__log(const cloth_logger *logger, cloth_log_level level, const char *format, ...)
{
    char message[512];
    va_list args;
    if (!logger || !logger->log) return;
    va_start(args, format);
    vsnprintf(message, sizeof message, format, args);
    va_end(args);
    logger->log(level, message, logger->user);
}

static uint64_t cloth__splitmix64(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

CLOTH_API cloth_rng cloth_rng_make(uint64_t seed)
{
    cloth_rng rng;
    int i;
    for (i = 0; i < 4; ++i) rng.s[i] = cloth__splitmix64(&seed);
    return rng;
}

static uint64_t cloth__rotl64(uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }

CLOTH_API uint64_t cloth_rng_next(cloth_rng *rng)
{
    uint64_t *s = rng->s;
    uint64_t result = cloth__rotl64(s[1] * 5, 7) * 9;
    uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = cloth__rotl64(s[3], 45);
    return result;
}

CLOTH_API cloth_real cloth_rng_uniform(cloth_rng *rng)
{
    /* 53 random bits into [0, 1) exactly as a double, then rounded to cloth_real; a float
       rounding up to 1 is folded back below 1. */
    double u = (double)(cloth_rng_next(rng) >> 11) * (1.0 / 9007199254740992.0);
    cloth_real r = (cloth_real)u;
    return r < (cloth_real)1 ? r : (cloth_real)0;
}

CLOTH_API cloth_real cloth_rng_normal(cloth_rng *rng)
{
    double u1 = 1.0 - (double)(cloth_rng_next(rng) >> 11) * (1.0 / 9007199254740992.0); /* (0, 1] */
    double u2 = (double)(cloth_rng_next(rng) >> 11) * (1.0 / 9007199254740992.0);
    return (cloth_real)(sqrt(-2.0 * log(u1)) * cos(6.283185307179586 * u2));
}

/* ------------------------------------------------------------------------------------- */
/* math                                                                                  */
/* ------------------------------------------------------------------------------------- */

/* Small vector helpers over cloth_real[3] arrays. They take output pointers last and allow
   the output to alias an input. */
CLOTH__MAYBE_UNUSED static void cloth__v3_sub(const cloth_real *a, const cloth_real *b, cloth_real *out)
{ out[0] = a[0] - b[0]; out[1] = a[1] - b[1]; out[2] = a[2] - b[2]; }
CLOTH__MAYBE_UNUSED static void cloth__v3_add(const cloth_real *a, const cloth_real *b, cloth_real *out)
{ out[0] = a[0] + b[0]; out[1] = a[1] + b[1]; out[2] = a[2] + b[2]; }
CLOTH__MAYBE_UNUSED static void cloth__v3_scale(const cloth_real *a, cloth_real s, cloth_real *out)
{ out[0] = a[0] * s; out[1] = a[1] * s; out[2] = a[2] * s; }
CLOTH__MAYBE_UNUSED static cloth_real cloth__v3_dot(const cloth_real *a, const cloth_real *b)
{ return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
CLOTH__MAYBE_UNUSED static void cloth__v3_cross(const cloth_real *a, const cloth_real *b, cloth_real *out)
{
    cloth_real c0 = a[1] * b[2] - a[2] * b[1];
    cloth_real c1 = a[2] * b[0] - a[0] * b[2];
    cloth_real c2 = a[0] * b[1] - a[1] * b[0];
    out[0] = c0; out[1] = c1; out[2] = c2;
}
CLOTH__MAYBE_UNUSED static cloth_real cloth__v3_norm(const cloth_real *a) { return (cloth_real)sqrt((double)cloth__v3_dot(a, a)); }
CLOTH__MAYBE_UNUSED static int cloth__is_finite(cloth_real v) { return v == v && v - v == 0; }

#include "wip/mesh_impl.h"
#if !defined(CLOTH_WIP_ONLY) || defined(CLOTH_WIP_IO)
#include "wip/io_impl.h"
#endif
#if !defined(CLOTH_WIP_ONLY) || defined(CLOTH_WIP_LINSOLVE)
#include "wip/linsolve_impl.h"
#endif
#if !defined(CLOTH_WIP_ONLY) || defined(CLOTH_WIP_BVH)
#include "wip/bvh_impl.h"
#endif
#if !defined(CLOTH_WIP_ONLY) || defined(CLOTH_WIP_CCD)
#include "wip/ccd_impl.h"
#endif

#ifdef __cplusplus
}
#endif

#endif /* CLOTH_IMPLEMENTATION_DONE */
#endif /* CLOTH_IMPLEMENTATION */

/*
------------------------------------------------------------------------------
This software is available under 2 licenses -- choose whichever you prefer.
------------------------------------------------------------------------------
ALTERNATIVE A - MIT License
Copyright (c) 2026 the cloth.h authors
Permission is hereby granted, free of charge, to any person obtaining a copy of
this software and associated documentation files (the "Software"), to deal in
the Software without restriction, including without limitation the rights to
use, copy, modify, merge, publish, distribute, sublicense, and/or sell copies
of the Software, and to permit persons to whom the Software is furnished to do
so, subject to the following conditions:
The above copyright notice and this permission notice shall be included in all
copies or substantial portions of the Software.
THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR
IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY,
FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE
AUTHORS OR COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER
LIABILITY, WHETHER IN AN ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM,
OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN THE
SOFTWARE.
------------------------------------------------------------------------------
ALTERNATIVE B - Public Domain (www.unlicense.org)
This is free and unencumbered software released into the public domain.
Anyone is free to copy, modify, publish, use, compile, sell, or distribute this
software, either in source code form or as a compiled binary, for any purpose,
commercial or non-commercial, and by any means.
In jurisdictions that recognize copyright laws, the author or authors of this
software dedicate any and all copyright interest in the software to the public
domain. We make this dedication in perpetuity for the benefit of the software
to the public and to the benefit of the community.
------------------------------------------------------------------------------
*/
