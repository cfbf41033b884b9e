// Running sums that add and take away the same values again and again (the media a ray is in, entered
// and left in depth order) keep each step's rounding: leaving a sphere of extinction 3 inside a fog of
// extinction 1e-6 left the fog's sum off by about half a float step of 3, 1.2e-7, an eighth of the fog,
// for the rest of the ray (trace, ppll and tiles alike read 4e-2 of the peak from the reference on such
// a scene, and 0.19 where the atmosphere was thinner). Knuth's TwoSum splits each step into the rounded
// sum and its exact rounding error; the errors are summed beside the sum, and sum + error is the running
// sum to float's rounding of the result, whatever was added and taken away before.
//
// For the SIMD lanes of trace's walks (GCC vector types: Float4, Float8); shaders/exact_integrator.glsl
// steps its sums the same way. Needs IEEE arithmetic as written: no -ffast-math (the build has none, and
// -std=c++20 leaves contraction off; a product here is by +-1, exact anyway).
#pragma once

namespace brume {

// sum + error += d as a compensated step, lane by lane (masks of the same width). Where `leaving` is
// set and the result is below 0, it becomes 0: the model clamps the sums a ray leaves a medium with, as
// the reference does (render/reference.cpp; a scene built in code may hold negative albedos, as the
// layers benchmark's far spheres do). Where `reset` is set (the ray back in free space) both become
// exactly 0.
template <class V, class Mask>
[[gnu::always_inline]] inline void compensated_step(V& sum, V& error, const V& d, const Mask& leaving,
                                                    const Mask& reset) {
    const V s = sum + d;
    const V d_rounded = s - sum;                                   // the part of d that s holds
    const V rounding = (sum - (s - d_rounded)) + (d - d_rounded);  // exactly (sum + d) - s
    const V e = error + rounding;
    const Mask zero = reset | (leaving & (s + e < V{}));
    sum = zero != 0 ? V{} : s;
    error = zero != 0 ? V{} : e;
}

}  // namespace brume
