// Eight floats or ints in one value (GCC and Clang vector extensions), for loops that carry nothing from
// one item to the next: trace's sun integrals (render/fast_tracer.cpp) and the map reads they need
// (render/sun_depth_map.h optical_depths). Compiled for any x86-64 a value is two SSE registers;
// inlined into code compiled for AVX2 (trace_tile_avx2), one AVX register.
#pragma once

#include <cstdint>
#include <cmath>
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
[[gnu::always_inline]] inline Int8 load8(const std::int32_t* p) {
    Int8 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
// Four floats or ints in one SSE register; four doubles in one AVX register, or two SSE registers.
using Float4 = float __attribute__((vector_size(16)));
using Int4 = std::int32_t __attribute__((vector_size(16)));
using Double4 = double __attribute__((vector_size(32)));
[[gnu::always_inline]] inline Float4 load4(const float* p) {
    Float4 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}
[[gnu::always_inline]] inline Double4 load4(const double* p) {
    Double4 v;
    std::memcpy(&v, p, sizeof v);
    return v;
}

// The square root of each lane (>= 0), correctly rounded as std::sqrt: SSE2's, on any x86-64, a half
// at a time (the halves taken apart and put together in registers: through memory, the 32-byte load
// of two 16-byte stores stalled the store buffer).
[[gnu::always_inline]] inline Double4 sqrt4(const Double4& v) {
#if defined(__x86_64__) && defined(__GNUC__)
    using Double2 = double __attribute__((vector_size(16)));
    const Double2 lo = Double2(_mm_sqrt_pd(__m128d(__builtin_shufflevector(v, v, 0, 1))));
    const Double2 hi = Double2(_mm_sqrt_pd(__m128d(__builtin_shufflevector(v, v, 2, 3))));
    return __builtin_shufflevector(lo, hi, 0, 1, 2, 3);
#else
    Double4 r;
    for (int l = 0; l < 4; ++l) r[l] = std::sqrt(v[l]);
    return r;
#endif
}

// Bit l set where lane l of a Float8 comparison is true: SSE's sign-bit masks of the two halves.
[[gnu::always_inline]] inline int mask8(const Int8& m) {
#if defined(__x86_64__) && defined(__GNUC__)
    const __m128 lo = _mm_castsi128_ps(__m128i(__builtin_shufflevector(m, m, 0, 1, 2, 3)));
    const __m128 hi = _mm_castsi128_ps(__m128i(__builtin_shufflevector(m, m, 4, 5, 6, 7)));
    return _mm_movemask_ps(lo) | (_mm_movemask_ps(hi) << 4);
#else
    int bits = 0;
    for (int l = 0; l < 8; ++l) bits |= (m[l] != 0) << l;
    return bits;
#endif
}

// The eight lanes of a Float8 widened into two Double4 (low_half, high_half), for sums in double that
// to_float8 rounds back.
[[gnu::always_inline]] inline Double4 low_half(const Float8& v) {
    return __builtin_convertvector(Float4{v[0], v[1], v[2], v[3]}, Double4);
}
[[gnu::always_inline]] inline Double4 high_half(const Float8& v) {
    return __builtin_convertvector(Float4{v[4], v[5], v[6], v[7]}, Double4);
}
[[gnu::always_inline]] inline Float8 to_float8(const Double4& lo, const Double4& hi) {
    const Float4 a = __builtin_convertvector(lo, Float4), b = __builtin_convertvector(hi, Float4);
    return Float8{a[0], a[1], a[2], a[3], b[0], b[1], b[2], b[3]};
}

[[gnu::always_inline]] inline void store8(float* p, const Float8& v) { std::memcpy(p, &v, sizeof v); }
[[gnu::always_inline]] inline void store8(std::int32_t* p, const Int8& v) { std::memcpy(p, &v, sizeof v); }

// Reads of a pair of neighbouring floats per lane: base[index[l]] into lo and base[index[l] + 1] into
// hi, in each lane l. One load at a time: for any x86-64.
struct GatherByLanes {
    [[gnu::always_inline]] void pair(const float* base, const Int8& index, Float8& lo, Float8& hi) const {
        for (int l = 0; l < 8; ++l) {
            lo[l] = base[index[l]];
            hi[l] = base[index[l] + 1];
        }
    }
    // base[index[l]] in each lane l.
    [[gnu::always_inline]] Float8 one(const float* base, const Int8& index) const {
        Float8 v;
        for (int l = 0; l < 8; ++l) v[l] = base[index[l]];
        return v;
    }
};

// Whether this CPU runs AVX2 (and FMA): what picks the code compiled for it (trace's tiles, the sun
// map's splat). Asked once.
inline bool cpu_has_avx2() {
#if defined(__x86_64__) && defined(__GNUC__)
    static const bool has = __builtin_cpu_supports("avx2");
    return has;
#else
    return false;
#endif
}
// Whether this CPU runs AVX-512's foundation and its 256-bit forms (VL): the sun map's scatters.
inline bool cpu_has_avx512vl() {
#if defined(__x86_64__) && defined(__GNUC__)
    static const bool has = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("avx512f") &&
                            __builtin_cpu_supports("avx512vl");
    return has;
#else
    return false;
#endif
}
inline bool cpu_has_avx2_fma() {
#if defined(__x86_64__) && defined(__GNUC__)
    static const bool has = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    return has;
#else
    return false;
#endif
}

#if defined(__x86_64__) && defined(__GNUC__)
// The square root of each lane (>= 0), correctly rounded: SSE's, a half at a time, for any x86-64; AVX's
// in one instruction, for code compiled for AVX2. The same values.
struct SqrtSse {
    [[gnu::always_inline]] Float8 operator()(const Float8& v) const {
        const __m128 lo = _mm_sqrt_ps(__m128(__builtin_shufflevector(v, v, 0, 1, 2, 3)));
        const __m128 hi = _mm_sqrt_ps(__m128(__builtin_shufflevector(v, v, 4, 5, 6, 7)));
        return Float8(__builtin_shufflevector(Float4(lo), Float4(hi), 0, 1, 2, 3, 4, 5, 6, 7));
    }
};
struct SqrtAvx {
    [[gnu::target("avx2")]] Float8 operator()(const Float8& v) const { return Float8(_mm256_sqrt_ps(__m256(v))); }
};

// The same by AVX2's gather instruction: only for code compiled for AVX2 (inlined into a function with
// target("avx2")); on fog-bank the loads one lane at a time were a tenth of the frame. The pair is one
// 8-byte read per lane: two gathers of four 8-byte lanes, half the elements of two gathers of eight
// floats (a gather costs about a load per element), then each lane's two floats dealt out to lo and hi.
struct GatherAvx2 {
    [[gnu::target("avx2")]] void pair(const float* base, const Int8& index, Float8& lo, Float8& hi) const {
        const __m256i i = __m256i(index);
        const double* b = reinterpret_cast<const double*>(base);  // read as bits, never as doubles
        // Points 0-3 and 4-7, as floats {lo0, hi0, lo1, hi1 | lo2, hi2, lo3, hi3}.
        // (The masked form: GCC 12's _mm256_i32gather_pd starts from an undefined value it then warns of.)
        const __m256d none = _mm256_setzero_pd(), all = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
        const __m256 first = _mm256_castpd_ps(_mm256_mask_i32gather_pd(none, b, _mm256_castsi256_si128(i), all, 4));
        const __m256 second =
            _mm256_castpd_ps(_mm256_mask_i32gather_pd(none, b, _mm256_extracti128_si256(i, 1), all, 4));
        // {lo0, lo1, lo4, lo5 | lo2, lo3, lo6, lo7}, then its 64-bit quarters in order 0, 2, 1, 3.
        lo = in_order(_mm256_shuffle_ps(first, second, 0x88));
        hi = in_order(_mm256_shuffle_ps(first, second, 0xDD));
    }

    [[gnu::target("avx2")]] Float8 one(const float* base, const Int8& index) const {
        // The masked form, as pair's: the unmasked one starts from an undefined value GCC 12 warns of.
        const __m256 all = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
        return Float8(_mm256_mask_i32gather_ps(_mm256_setzero_ps(), base, __m256i(index), all, 4));
    }

private:
    [[gnu::target("avx2")]] static Float8 in_order(__m256 v) {
        return Float8(_mm256_castpd_ps(_mm256_permute4x64_pd(_mm256_castps_pd(v), 0xD8)));
    }
};
#endif

}  // namespace brume::simd
