// The integrators' functions over eight lanes at once (render/simd8.h's Float8): exp, a segment's
// transmittance and (1 - exp(-x)) / x,
// sqrt and a table lookup by lane. Each lane computes what the scalar form in render/fast_tracer.cpp
// computes for one value, by the same arithmetic, so a lane and the scalar code agree but for how the
// compiler fuses multiply-adds.
#pragma once

#include "render/simd8.h"

#include <cmath>
#include <cstring>

namespace brume::simd {

// e^y for |y| < 87 (float's normal range) but for its factor 2^n: y = n ln2 + r with |r| <= ln2 / 2,
// e^r by its Taylor polynomial to degree 6 (truncation below 2e-7), returned, and n (rounded to
// nearest by the 1.5 * 2^23 trick: |y log2 e| < 2^22 here; no libm call, no SSE4.1). One definition for
// a float (render/fast_tracer.cpp exp_in_range) and for eight lanes, so both round alike.
template <class F>
[[gnu::always_inline]] inline F exp_reduced(F y, F& n) {
    n = (y * 1.44269504088896341f + 12582912.0f) - 12582912.0f;
    const F r = (y - n * 0.693145751953125f) - n * 1.42860682030941723e-6f;  // ln2 split: hi exact in n * hi
    // Estrin's scheme: the same polynomial as Horner's, in a third of the dependent steps.
    const F r2 = r * r, r4 = r2 * r2;
    return ((1.0f + r) + r2 * (0.5f + r * (1.0f / 6.0f))) + r4 * ((1.0f / 24.0f + r * (1.0f / 120.0f)) + r2 * (1.0f / 720.0f));
}

// e^y for |y| < 87 in each lane: 2^n through the exponent bits.
[[gnu::always_inline]] inline Float8 exp_in_range8(Float8 y) {
    Float8 n;
    const Float8 p = exp_reduced(y, n);
    const Int8 bits = (__builtin_convertvector(n, Int8) + 127) << 23;
    return p * Float8(bits);  // a cast between vectors of one size keeps the bits
}

// exp(-x), clamped to float's normal range, in each lane (NaN never reaches here).
[[gnu::always_inline]] inline Float8 exp_minus8(Float8 x) {
    Float8 y = -x;
    y = y > -87.0f ? y : Float8{} - 87.0f;
    y = y < 87.0f ? y : Float8{} + 87.0f;
    return exp_in_range8(y);
}

// exp(y) for y <= 0 in each lane, 0 below float's normal range: the scalar exp_nonpositive's answer,
// which a segment's transmittance takes (exp_minus8 would leave e^-87 there, not 0).
[[gnu::always_inline]] inline Float8 exp_nonpositive8(Float8 y) {
    const Int8 in_range = y > -87.0f;
    return in_range ? exp_in_range8(in_range ? y : Float8{}) : Float8{};
}

// (1 - exp(-x)) / x for 0 <= x < 1/8, by its series to x^5 (what it leaves out is below 1e-9 there):
// nested products with the reciprocals (written as quotients, x / 3, ..., it was five dependent
// divisions: a compiler may not turn x / 3 into x * (1 / 3), they round differently). One definition
// for a float (render/fast_tracer.cpp segment_light) and for eight lanes, so both round alike.
template <class F>
[[gnu::always_inline]] inline F phi_series(F x) {
    return 1.0f - x * 0.5f * (1.0f - x * (1.0f / 3.0f) * (1.0f - x * 0.25f * (1.0f - x * 0.2f * (1.0f - x * (1.0f / 6.0f)))));
}

// A segment of optical depth x >= 0 and length len, in each lane: its transmittance e^-x and its weight
// len (1 - e^-x) / x, as the scalar segment_light (render/fast_tracer.cpp) takes them. Below x = 1/8 both
// come from phi_series, e^-x as 1 - x phi (to float's rounding), and where every lane is that thin no
// exponential is taken; above, e^-x and the quotient (its divisor kept away from 0 in the thin lanes).
[[gnu::always_inline]] inline void segment_transmittance8(Float8 x, Float8 len, Float8& transmittance, Float8& weight) {
    const Int8 thin = x < 0.125f;
    const Float8 series = phi_series(x);
    const Float8 thin_transmittance = 1.0f - x * series;
    if (mask8(thin) == 0xff) {
        transmittance = thin_transmittance;
        weight = len * series;
        return;
    }
    const Float8 e = exp_nonpositive8(-x);
    const Float8 quotient = (1.0f - e) / (thin ? Float8{} + 1.0f : x);
    transmittance = thin ? thin_transmittance : e;
    weight = len * (thin ? series : quotient);
}

// The integral over a piece of length len of exp(-e(t)), its exponent e linear along the piece from
// e(p) to e(q) = e(p) + x, given the integrand's ends at_p = exp(-e(p)) and at_q = exp(-e(q)), in each
// lane: the sun integral's exponent also holds the change of the optical depth toward the sun, which
// may fall along a piece (x < 0). Past |x| = 1/8, len (at_p - at_q) / x, between the two ends times
// len however large |x| is (at_p (1 - exp(-x)) / x overflows where the depth falls by more than
// float's exponent holds: a view ray leaving a very dense sphere's shadow toward the sun); below, at_p
// len times the series of (1 - exp(-x)) / x, which holds for either sign.
[[gnu::always_inline]] inline Float8 linear_exponent_integral8(Float8 x, Float8 at_p, Float8 at_q, Float8 len) {
    const Int8 small = Float8(Int8(x) & 0x7fffffff) < 0.125f;  // |x| by its bits
    const Float8 series =
        1.0f - x * 0.5f * (1.0f - x * (1.0f / 3.0f) * (1.0f - x * 0.25f * (1.0f - x * 0.2f * (1.0f - x * (1.0f / 6.0f)))));
    const Float8 quotient = (at_p - at_q) / (small ? Float8{} + 1.0f : x);
    return len * (small ? at_p * series : quotient);
}

// The square root of each lane, for lanes >= 0 (correctly rounded, as std::sqrt): SSE's on any
// x86-64, a half at a time, the halves taken apart and put together in registers.
[[gnu::always_inline]] inline Float8 sqrt8(const Float8& v) {
#if defined(__x86_64__) && defined(__GNUC__)
    using Float4 = float __attribute__((vector_size(16)));
    const Float4 lo = Float4(_mm_sqrt_ps(__m128(__builtin_shufflevector(v, v, 0, 1, 2, 3))));
    const Float4 hi = Float4(_mm_sqrt_ps(__m128(__builtin_shufflevector(v, v, 4, 5, 6, 7))));
    return __builtin_shufflevector(lo, hi, 0, 1, 2, 3, 4, 5, 6, 7);
#else
    Float8 r;
    for (int l = 0; l < 8; ++l) r[l] = std::sqrt(v[l]);
    return r;
#endif
}

// table[index[l]] in each lane l (index in 0..7): one permute where the target has one (AVX2's vpermps).
[[gnu::always_inline]] inline Float8 lookup8(const Float8& table, const Int8& index) {
#if defined(__clang__)
    Float8 r;
    for (int l = 0; l < 8; ++l) r[l] = table[index[l] & 7];
    return r;
#else
    return __builtin_shuffle(table, index);
#endif
}

}  // namespace brume::simd
