// Live particles as a structure of arrays: the force and integration loops read a few fields of
// many particles, and separate float arrays let the compiler vectorise them (4 lanes with SSE2).
// Float is ample for smoke (a 1e-7 relative position error is far below a particle's radius) and
// halves the memory traffic; everything that accumulates over a long run is kept in double or
// integers: time and emission counts elsewhere, and here each particle's age and lifetime (a float age
// summed step by step lost 1.7 s of a 100 s life at 15,360 steps a second, and stopped growing at
// 2,048 s, so that such a particle never died). Order is not meaningful: removal swaps in the last one.
#pragma once

#include <glm/vec3.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace brume {

// A particle's unique id: the emitter's index in the high 16 bits, that emitter's emission counter
// (every particle it emitted, including those the budget skipped) in the low 48.
inline constexpr int kParticleIdCounterBits = 48;
constexpr std::uint64_t make_particle_id(std::uint32_t emitter, std::uint64_t counter) {
    return (std::uint64_t(emitter) << kParticleIdCounterBits) |
           (counter & ((std::uint64_t(1) << kParticleIdCounterBits) - 1));
}

// One particle in double precision: what an emitter produces and what tests inspect.
struct Particle {
    glm::dvec3 position{0.0};
    glm::dvec3 velocity{0.0};
    double age = 0.0;       // seconds since emission
    double lifetime = 0.0;  // it dies at age >= lifetime
    double radius = 0.0;       // base values, before the age curves
    double extinction = 0.0;
    glm::dvec3 albedo{1.0};
    std::uint32_t emitter = 0;  // index into Preset::emitters, for its age curves
    std::uint64_t id = 0;
};

struct Particles {
    std::vector<float> x, y, z;     // position, rounded to float: where the forces are evaluated
    // What each step's move left over in the rounding of x, y and z (TwoSum; sim/forces.h integrate):
    // x + x_lo is the position. Plain float positions lost every move shorter than half a float step, so
    // a particle 1,000 units out at 0.5 units a second went 87% too fast at 64 substeps and one 100,000
    // units out did not move at all.
    std::vector<float> x_lo, y_lo, z_lo;
    std::vector<float> vx, vy, vz;  // velocity
    std::vector<double> age, lifetime;
    std::vector<float> radius, extinction;
    std::vector<float> albedo_r, albedo_g, albedo_b;
    std::vector<std::uint32_t> emitter;
    std::vector<std::uint64_t> id;

    std::size_t size() const { return x.size(); }
    bool empty() const { return x.empty(); }

    void push_back(const Particle& p) {
        x.push_back(float(p.position.x));
        y.push_back(float(p.position.y));
        z.push_back(float(p.position.z));
        x_lo.push_back(float(p.position.x - double(x.back())));
        y_lo.push_back(float(p.position.y - double(y.back())));
        z_lo.push_back(float(p.position.z - double(z.back())));
        vx.push_back(float(p.velocity.x));
        vy.push_back(float(p.velocity.y));
        vz.push_back(float(p.velocity.z));
        age.push_back(p.age);
        lifetime.push_back(p.lifetime);
        radius.push_back(float(p.radius));
        extinction.push_back(float(p.extinction));
        albedo_r.push_back(float(p.albedo.x));
        albedo_g.push_back(float(p.albedo.y));
        albedo_b.push_back(float(p.albedo.z));
        emitter.push_back(p.emitter);
        id.push_back(p.id);
    }

    Particle at(std::size_t i) const {
        Particle p;
        p.position = position(i);
        p.velocity = {vx[i], vy[i], vz[i]};
        p.age = age[i];
        p.lifetime = lifetime[i];
        p.radius = radius[i];
        p.extinction = extinction[i];
        p.albedo = {albedo_r[i], albedo_g[i], albedo_b[i]};
        p.emitter = emitter[i];
        p.id = id[i];
        return p;
    }

    glm::dvec3 position(std::size_t i) const {
        return {double(x[i]) + double(x_lo[i]), double(y[i]) + double(y_lo[i]), double(z[i]) + double(z_lo[i])};
    }
    // Particle i moved by something other than a step (pushed out of a box, put back): x, y and z hold
    // its position whole.
    void drop_rounding(std::size_t i) { x_lo[i] = y_lo[i] = z_lo[i] = 0.0f; }

    // Removes particle i by moving the last one into its place: O(1), and deterministic because the
    // simulator always visits particles in index order.
    void swap_remove(std::size_t i) {
        for_each_array([i](auto& a) {
            a[i] = a.back();
            a.pop_back();
        });
    }

    void clear() {
        for_each_array([](auto& a) { a.clear(); });
    }

    void reserve(std::size_t n) {
        for_each_array([n](auto& a) { a.reserve(n); });
    }

    template <class F>
    void for_each_array(F&& f) {
        f(x), f(y), f(z), f(x_lo), f(y_lo), f(z_lo), f(vx), f(vy), f(vz), f(age), f(lifetime), f(radius), f(extinction);
        f(albedo_r), f(albedo_g), f(albedo_b), f(emitter), f(id);
    }
};

}  // namespace brume
