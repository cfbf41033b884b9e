#include "sim/simulator.h"

#include "sim/emitters.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

namespace brume {
namespace {

// Particles are advanced in chunks small enough that positions, velocities and accelerations stay in
// L1 while every noise mode sweeps them (256 * 9 floats = 9 KiB).
constexpr std::size_t kChunk = 256;

}  // namespace

Simulator::Simulator(const Preset& preset, const std::atomic<bool>* stop) : preset_(preset), stop_(stop) {
    const Timeline& tl = preset_.timeline;
    if (!(tl.fps > 0.0) || !std::isfinite(tl.fps)) throw std::invalid_argument("simulator: fps must be positive");
    if (tl.substeps < 1) throw std::invalid_argument("simulator: substeps must be at least 1");
    if (!(tl.preroll >= 0.0) || !std::isfinite(tl.preroll))
        throw std::invalid_argument("simulator: preroll must be finite and non-negative");
    if (preset_.emitters.size() > (std::size_t(1) << (64 - kParticleIdCounterBits)))
        throw std::invalid_argument("simulator: at most 65536 emitters");
    for (const EmitterDesc& e : preset_.emitters) require_density_loaded(e);
    substeps_ = std::uint64_t(tl.substeps);
    steps_per_second_ = tl.fps * double(tl.substeps);
    preroll_steps_ = std::uint64_t(std::llround(tl.preroll * steps_per_second_));
    forces_ = ForceField(preset_.forces, tl.seed);
    obstacles_ = BoxObstacles(preset_.scene.boxes);
    phases_.assign(forces_.phase_count(), 0.0f);
    reset();
}

void Simulator::reset() {
    particles_.clear();
    emitters_.assign(preset_.emitters.size(), EmitterState{});
    for (std::size_t e = 0; e < emitters_.size(); ++e) {
        emitters_[e].bursts = preset_.emitters[e].bursts;
        std::stable_sort(emitters_[e].bursts.begin(), emitters_[e].bursts.end(),
                         [](const EmitterDesc::Burst& a, const EmitterDesc::Burst& b) { return a.time < b.time; });
    }
    step_ = 0;
    skipped_ = 0;
    forces_.phases(0.0, phases_.data());
    add_births(0.0, 0.0, true);
    advance_new(0);  // age 0: only pushed out of boxes
    while (step_ < preroll_steps_) {
        check_stop();
        substep();
    }
}

bool Simulator::can_adopt_emitter(const Preset& next, std::size_t e) const {
    if (e >= emitters_.size() || next.emitters.size() != emitters_.size()) return false;
    if (emitters_[e].counter != 0) return false;  // the current emitter has had births (or budget skips)
    const double now = time_at(step_);
    const EmitterDesc& d = next.emitters[e];
    for (const EmitterDesc::Burst& b : d.bursts)
        if (b.time <= now && b.count > 0) return false;
    return continuous_count(d, now) == 0;
}

void Simulator::adopt_emitter(const Preset& next, std::size_t e) {
    if (!can_adopt_emitter(next, e)) throw std::logic_error("simulator: the emitter has emitted; it cannot be swapped");
    preset_.emitters[e] = next.emitters[e];
    require_density_loaded(preset_.emitters[e]);
    EmitterState& st = emitters_[e];
    st = EmitterState{};
    st.bursts = preset_.emitters[e].bursts;
    std::stable_sort(st.bursts.begin(), st.bursts.end(),
                     [](const EmitterDesc::Burst& a, const EmitterDesc::Burst& b) { return a.time < b.time; });
}

void Simulator::step_frame() {
    for (std::uint64_t s = 0; s < substeps_; ++s) {
        check_stop();
        substep();
    }
}

void Simulator::advance_to_frame(int frame) {
    if (frame < 0) throw std::invalid_argument("simulator: frame must be non-negative, got " + std::to_string(frame));
    const std::uint64_t target = preroll_steps_ + std::uint64_t(frame) * substeps_;
    if (step_ > target) reset();
    while (step_ < target) {
        check_stop();
        substep();
    }
}

int Simulator::frame() const { return int((step_ - preroll_steps_) / substeps_); }

double Simulator::time() const { return time_at(step_); }

void Simulator::substep() {
    const double t0 = time_at(step_), t1 = time_at(step_ + 1);
    const double dt = 1.0 / steps_per_second_;
    forces_.phases(t0, phases_.data());
    const LinearStep ls = forces_.linear_step(dt);

    Particles& p = particles_;
    const std::size_t n = p.size();
    const bool obstacles = !obstacles_.empty();
    bool any_dead = false;
    alignas(64) float ax[kChunk], ay[kChunk], az[kChunk];
    alignas(64) float ox[kChunk], oy[kChunk], oz[kChunk];
    for (std::size_t i0 = 0; i0 < n; i0 += kChunk) {
        const std::size_t m = std::min(kChunk, n - i0);
        float* x = p.x.data() + i0;
        float* y = p.y.data() + i0;
        float* z = p.z.data() + i0;
        forces_.accelerations(x, y, z, m, phases_.data(), ax, ay, az);
        if (obstacles) {
            std::copy(x, x + m, ox);
            std::copy(y, y + m, oy);
            std::copy(z, z + m, oz);
        }
        integrate(ls, ax, ay, az, m, x, y, z, p.x_lo.data() + i0, p.y_lo.data() + i0, p.z_lo.data() + i0,
                  p.vx.data() + i0, p.vy.data() + i0, p.vz.data() + i0);
        if (obstacles) {
            for (std::size_t j = 0; j < m; ++j) {
                const std::size_t i = i0 + j;
                if (!obstacles_.inside(x[j], y[j], z[j])) continue;
                p.drop_rounding(i);  // pushed out, or put back: the floats hold the position whole
                if (!obstacles_.push_out(x[j], y[j], z[j], p.vx[i], p.vy[i], p.vz[i])) {
                    // Wedged between overlapping boxes: stay where it was (outside, by induction).
                    x[j] = ox[j], y[j] = oy[j], z[j] = oz[j];
                    p.vx[i] = p.vy[i] = p.vz[i] = 0.0f;
                }
            }
        }
        double* age = p.age.data() + i0;
        const double* life = p.lifetime.data() + i0;
        int dead = 0;
        for (std::size_t j = 0; j < m; ++j) {
            age[j] += dt;
            dead |= age[j] >= life[j];
        }
        any_dead |= dead != 0;
    }
    if (any_dead) remove_dead(0);

    const std::size_t first_new = p.size();
    add_births(t0, t1, false);
    advance_new(first_new);
    ++step_;
}

void Simulator::remove_dead(std::size_t first) {
    Particles& p = particles_;
    for (std::size_t i = first; i < p.size();) {
        if (p.age[i] >= p.lifetime[i])
            p.swap_remove(i);
        else
            ++i;
    }
}

void Simulator::add_births(double t_begin, double t_end, bool initial) {
    new_ages_.clear();
    for (std::uint32_t e = 0; e < emitters_.size(); ++e) {
        const EmitterDesc& desc = preset_.emitters[e];
        EmitterState& st = emitters_[e];
        for (const EmitterDesc::Burst& b : st.bursts) {
            const bool now = initial ? b.time <= 0.0 : (b.time > t_begin && b.time <= t_end);
            if (!now) continue;
            for (std::uint32_t c = 0; c < b.count; ++c) {
                if (budget_full()) {  // the rest are skipped, counted at once: 1e10 of them took seconds one by one
                    skip_births(e, b.count - c);
                    break;
                }
                birth(e, b.time, t_end, initial);
            }
        }
        const std::uint64_t total = continuous_count(desc, t_end);
        for (; st.continuous < total; ++st.continuous) {
            if (budget_full()) {
                skip_births(e, total - st.continuous);
                st.continuous = total;
                break;
            }
            birth(e, continuous_birth_time(desc, st.continuous), t_end, initial);
        }
    }
}

void Simulator::skip_births(std::uint32_t emitter, std::uint64_t count) {
    emitters_[emitter].counter += count;  // as birth() counts each: the later births' draws stay theirs
    skipped_ += count;
}

void Simulator::birth(std::uint32_t emitter, double birth_time, double t_end, bool initial) {
    const std::uint64_t counter = emitters_[emitter].counter++;
    if (particles_.size() >= preset_.timeline.max_particles) {
        ++skipped_;
        return;
    }
    Particle q = sample_particle(preset_.emitters[emitter], preset_.timeline.seed, emitter, counter);
    // Its share of the step; births counted at t_end by the rounding allowance of continuous_count
    // may lie a hair after it, hence the clamp.
    const double age = initial ? 0.0 : std::clamp(t_end - birth_time, 0.0, 1.0 / steps_per_second_);
    q.age = age;
    if (q.age >= q.lifetime) return;  // born and dead within the step
    particles_.push_back(q);
    new_ages_.push_back(age);
}

// Births of this step: the field is evaluated for all of them at once (their positions are contiguous
// at the end of the arrays), then each is integrated over its own age.
void Simulator::advance_new(std::size_t first) {
    Particles& p = particles_;
    const std::size_t n = p.size() - first;
    if (n == 0) return;
    alignas(64) float ax[kChunk], ay[kChunk], az[kChunk];
    bool any_dead = false;
    for (std::size_t j0 = 0; j0 < n; j0 += kChunk) {
        const std::size_t m = std::min(kChunk, n - j0);
        const std::size_t i0 = first + j0;
        forces_.accelerations(p.x.data() + i0, p.y.data() + i0, p.z.data() + i0, m, phases_.data(), ax, ay, az);
        for (std::size_t j = 0; j < m; ++j) {
            const std::size_t i = i0 + j;
            const float bx = p.x[i], by = p.y[i], bz = p.z[i];
            const double age = new_ages_[j0 + j];
            if (age > 0.0) {
                const LinearStep ls = forces_.linear_step(age);
                integrate(ls, ax + j, ay + j, az + j, 1, &p.x[i], &p.y[i], &p.z[i], &p.x_lo[i], &p.y_lo[i], &p.z_lo[i],
                          &p.vx[i], &p.vy[i], &p.vz[i]);
            }
            if (!obstacles_.inside(p.x[i], p.y[i], p.z[i])) continue;
            p.drop_rounding(i);  // pushed out, or put back: the floats hold the position whole
            if (!obstacles_.push_out(p.x[i], p.y[i], p.z[i], p.vx[i], p.vy[i], p.vz[i])) {
                if (obstacles_.inside(bx, by, bz)) {
                    // Born inside geometry it cannot leave: it dies unseen.
                    p.lifetime[i] = 0.0;
                    any_dead = true;
                } else {
                    p.x[i] = bx, p.y[i] = by, p.z[i] = bz;
                    p.vx[i] = p.vy[i] = p.vz[i] = 0.0f;
                }
            }
        }
    }
    if (any_dead) remove_dead(first);
    new_ages_.clear();
}

void Simulator::append_spheres(std::vector<Sphere>& out) const {
    const Particles& p = particles_;
    out.reserve(out.size() + p.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
        const EmitterDesc& emitter = preset_.emitters[p.emitter[i]];
        const AgeCurves& curves = emitter.curves;
        const double a = p.lifetime[i] > 0.0 ? p.age[i] / p.lifetime[i] : 1.0;
        const AgeCurveFactors f = evaluate_age_curves(curves, a);
        Sphere s;
        s.radius = double(p.radius[i]) * f.radius;
        s.extinction = double(p.extinction[i]) * f.extinction;
        if (!(s.radius > 0.0) || !(s.extinction > 0.0)) continue;
        s.center = p.position(i);
        s.albedo = glm::dvec3{p.albedo_r[i], p.albedo_g[i], p.albedo_b[i]} * f.albedo;
        // Emission adds tau * e: it fades with the extinction, so the fades need not touch it.
        s.emission = emitter.emission * f.emission;
        out.push_back(s);
    }
}

double benchmark_step_ms(std::size_t particles, int steps) {
    Preset preset;
    preset.timeline.fps = 48.0;
    preset.timeline.substeps = 1;  // one step_frame() = one step
    preset.timeline.seed = 7;
    preset.timeline.max_particles = std::uint32_t(std::min<std::size_t>(particles, 0xffffffffu));
    preset.scene.boxes.push_back(Box{{-50.0, -1.0, -50.0}, {50.0, 0.0, 50.0}, {0.2, 0.2, 0.2}});

    EmitterDesc e;
    e.name = "bench";
    e.shape = EmitterShape::Disc;
    e.center = {0.0, 0.1, 0.0};
    e.radius = 0.5;
    e.bursts.push_back({0.0, std::uint32_t(preset.timeline.max_particles)});
    e.speed = {0.5, 1.0};
    e.cone_deg = 20.0;
    e.jitter = 0.1;
    e.lifetime = {1000.0, 1000.0};  // no deaths during the run: the count stays at `particles`
    e.radius_range = {0.05, 0.1};
    e.extinction = {2.0, 4.0};
    e.curves.radius_growth = 3.0;
    e.curves.fade_in = 0.1;
    e.curves.fade_out = 0.3;
    e.curves.albedo_ramp = {{0.0, {1.0, 0.9, 0.8}}, {1.0, {0.6, 0.6, 0.6}}};
    preset.emitters.push_back(e);

    auto force = [](ForceKind kind) {
        ForceDesc f;
        f.kind = kind;
        return f;
    };
    ForceDesc gravity = force(ForceKind::Gravity);
    gravity.vector = {0.0, -9.81, 0.0};
    ForceDesc buoyancy = force(ForceKind::Buoyancy);
    buoyancy.strength = 10.8;
    ForceDesc wind = force(ForceKind::Wind);
    wind.vector = {1.0, 0.0, 0.2};
    wind.strength = 0.4;
    ForceDesc drag = force(ForceKind::Drag);
    drag.strength = 0.3;
    ForceDesc turbulence = force(ForceKind::Turbulence);
    turbulence.strength = 1.5;
    turbulence.scale = 0.8;
    turbulence.speed = 0.5;
    turbulence.octaves = 2;
    preset.forces = {gravity, buoyancy, wind, drag, turbulence};

    Simulator sim(preset);
    std::vector<Sphere> spheres;
    sim.step_frame();  // warm the caches and the allocator
    sim.append_spheres(spheres);
    std::vector<double> ms;
    for (int s = 0; s < std::max(steps, 1); ++s) {
        spheres.clear();
        const auto start = std::chrono::steady_clock::now();
        sim.step_frame();
        sim.append_spheres(spheres);
        const auto end = std::chrono::steady_clock::now();
        ms.push_back(std::chrono::duration<double, std::milli>(end - start).count());
    }
    std::nth_element(ms.begin(), ms.begin() + std::ptrdiff_t(ms.size() / 2), ms.end());
    return ms[ms.size() / 2];
}

}  // namespace brume
