// Function multi-versioning for the hot loops: GCC compiles the marked
// functions twice (x86-64-v3 = AVX2, and baseline SSE2) and picks one at load
// time, so one binary runs everywhere and uses 8-wide floats where it can.
// `flatten` inlines the whole call tree into each clone. The code is plain
// element-wise float arithmetic and the module is compiled with
// -ffp-contract=off (perception/CMakeLists.txt), so both versions give
// bit-identical results.
#pragma once

#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__) && !defined(PERCLOD_NO_CLONES)
#define PERCLOD_SIMD_CLONES __attribute__((flatten, target_clones("arch=x86-64-v3", "default")))
#else
#define PERCLOD_SIMD_CLONES
#endif
