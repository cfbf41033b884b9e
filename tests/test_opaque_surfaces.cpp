// The opaque surfaces' eight-ray test (render/opaque_surfaces.h nearest8) against the one-ray one it
// stands in for, lane by lane, to the bit: distance, box and face, over random boxes and rays,
// directions with components exactly 0 (axis-aligned rays, which the slabs take by the origin), the
// origin inside a box and on its faces, and candidate masks. CPU only.
#include "render/opaque_surfaces.h"
#include "render/simd8.h"

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace brume {
namespace {

Scene boxes_scene(int count, unsigned seed) {
    Scene s;
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> pos(-4.0, 4.0), size(0.05, 3.0);
    for (int k = 0; k < count; ++k) {
        const glm::dvec3 lo(pos(rng), pos(rng), pos(rng));
        s.boxes.push_back(Box{lo, lo + glm::dvec3(size(rng), size(rng), size(rng)), {0.1, 0.2, 0.3}});
    }
    s.boxes.push_back(Box{{-20.0, -2.0, -20.0}, {20.0, -1.5, 20.0}, {0.2, 0.2, 0.2}});  // a ground
    return s;
}

// nearest8 as trace's AVX2 code takes it (inlined into a function compiled for AVX2), where the CPU
// has AVX2; else as the test's own code takes it.
#if defined(__x86_64__) && defined(__GNUC__)
[[gnu::target("avx2"), gnu::flatten]] void nearest8_avx2(const OpaqueSurfaces& opaque, const glm::dvec3& o,
                                                         const double* dx, const double* dy, const double* dz,
                                                         std::uint64_t mask, OpaqueSurfaces::Hit* out) {
    opaque.nearest8(o, dx, dy, dz, mask, out);
}
#endif

void expect_same(const OpaqueSurfaces::Hit& got, const OpaqueSurfaces::Hit& want, const char* what, int ray) {
    ASSERT_EQ(std::bit_cast<std::uint64_t>(got.t), std::bit_cast<std::uint64_t>(want.t))
        << what << " ray " << ray << ": t " << got.t << " against " << want.t;
    ASSERT_EQ(got.box, want.box) << what << " ray " << ray;
    ASSERT_EQ(got.axis, want.axis) << what << " ray " << ray;
}

TEST(OpaqueSurfaces, EightRaysAtOnceHitWhatOneRayAtATimeHits) {
    for (const int count : {0, 1, 5, 70}) {
        const Scene s = boxes_scene(count, unsigned(11 + count));
        const SunLight sun(s);
        const OpaqueSurfaces opaque(s, sun);
        std::mt19937 rng(5);
        std::uniform_real_distribution<double> u(-1.0, 1.0), pos(-6.0, 6.0);
        int hits = 0;
        for (int batch = 0; batch < 400; ++batch) {
            // Origins outside, inside a box (its centre) and on a face (its min corner's x).
            glm::dvec3 o(pos(rng), pos(rng), pos(rng));
            if (count > 0 && batch % 5 == 1) o = 0.5 * (s.boxes[0].min + s.boxes[0].max);
            if (count > 0 && batch % 5 == 2) o = glm::dvec3(s.boxes[0].min.x, o.y, o.z);
            double dx[8], dy[8], dz[8];
            for (int n = 0; n < 8; ++n) {
                glm::dvec3 d(u(rng), u(rng), u(rng));
                // Some components exactly 0, some -0, a few tiny: the slab tests' edge cases.
                if ((batch + n) % 4 == 0) d[n % 3] = 0.0;
                if ((batch + n) % 7 == 0) d[(n + 1) % 3] = -0.0;
                if ((batch + n) % 11 == 0) d[(n + 2) % 3] = 1e-300;
                if (batch % 9 == 3) d = glm::dvec3(0.0, -1.0, 0.0);  // straight down at the ground
                d = glm::normalize(d);
                dx[n] = d.x;
                dy[n] = d.y;
                dz[n] = d.z;
            }
            const std::uint64_t masks[] = {~std::uint64_t(0), std::uint64_t(0x5555555555555555u), 0u};
            for (const std::uint64_t mask : masks) {
                OpaqueSurfaces::Hit got[8], got_avx2[8];
                opaque.nearest8(o, dx, dy, dz, mask, got);
#if defined(__x86_64__) && defined(__GNUC__)
                if (simd::cpu_has_avx2()) nearest8_avx2(opaque, o, dx, dy, dz, mask, got_avx2);
                else std::copy(got, got + 8, got_avx2);
#else
                std::copy(got, got + 8, got_avx2);
#endif
                for (int n = 0; n < 8; ++n) {
                    const OpaqueSurfaces::Hit want = opaque.nearest(o, glm::dvec3(dx[n], dy[n], dz[n]), mask);
                    expect_same(got[n], want, "nearest8", batch * 8 + n);
                    expect_same(got_avx2[n], want, "nearest8 in AVX2", batch * 8 + n);
                    hits += want.box >= 0;
                }
            }
        }
        if (count > 0) {
            EXPECT_GT(hits, 2000) << count << " boxes: the rays should meet boxes, not only the background";
        }
    }
}

}  // namespace
}  // namespace brume
