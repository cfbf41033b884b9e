// Eight floats or ints in one value (GCC and Clang vector extensions), for loops that carry nothing from
// one item to the next: trace's sun integrals (render/fast_tracer.cpp) and the map reads they need
// (render/sun_depth_map.h optical_depths). Compiled for any x86-64 a value is two SSE registers;
// inlined into code compiled for AVX2 (trace_tile_avx2), one AVX register.
#pragma once

#include <cstdint>
#include <cstring>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

// A Float8 or Int8 crosses a call differently with and without AVX (GCC's -Wpsabi note); every function
// here and in their users is inlined, so no such call is made.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace brume::simd {

using Float8 = float __attribute__((vector_size(32)));
using Int8 = std::int32_t __attribute__((vector_size(32)));

[[gnu::always_inline]] inline Float8 load8(const float* p) {
    Float8 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
[[gnu::always_inline]] inline void store8(float* p, const Float8& v) { std::memcpy(p, &v, sizeof v); }
[[gnu::always_inline]] inline void store8(std::int32_t* p, const Int8& v) { std::memcpy(p, &v, sizeof v); }

// base[index[l]] in each lane l, one load at a time: for any x86-64.
struct GatherByLanes {
    [[gnu::always_inline]] Float8 operator()(const float* base, const Int8& index) const {
        Float8 v;
        for (int l = 0; l < 8; ++l) v[l] = base[index[l]];
        return v;
    }
};

#if defined(__x86_64__) && defined(__GNUC__)
// The same by AVX2's gather instruction: only for code compiled for AVX2 (inlined into a function with
// target("avx2")); on fog-bank the loads one lane at a time were a tenth of the frame.
struct GatherAvx2 {
    [[gnu::target("avx2")]] Float8 operator()(const float* base, const Int8& index) const {
        return Float8(_mm256_i32gather_ps(base, __m256i(index), 4));
    }
};
#endif

}  // namespace brume::simd
