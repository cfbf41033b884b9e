// The CPU reference renderer: the light model of docs/accuracy.md, computed in double precision:
// exact chords, running sums of extinction, scattering and emission, -expm1 for the segment opacity.
// With shadows, the sun term of a segment is integrated by adaptive quadrature between the closed-form
// points where T_sun along the ray is not smooth (render/sun_light.h), unless the per-sphere technique is
// asked for, which is closed form again.
//
// Speed comes from binning spheres into 16x16 screen tiles by angular cones seen from the eye. The bins are
// conservative (they may hold spheres a pixel misses, never the reverse), and a pixel's answer depends only
// on the multiset of its events, so binning, sphere order and thread count cannot change a single bit.
#include "render/reference.h"

#include "render/opaque_surfaces.h"
#include "render/sun_light.h"
#include "sim/camera_rays.h"
#include "sim/parallel_for.h"
#include "sim/scene_file.h"

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

namespace brume {
namespace {

using glm::dvec3;

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kTile = 16;
// Angular slack for the tile bins: far above double rounding in the directions and the chord test.
constexpr double kConeMargin = 1e-6;

// A sphere as the integrator sees it: entry adds (tau, tau * albedo, ...), exit subtracts the same numbers.
struct Medium {
    dvec3 center;
    double radius;
    double radius2;
    double tau;
    dvec3 scatter;      // tau * albedo
    dvec3 emission;     // tau * emission
    dvec3 sun_scatter;  // tau * albedo * T_sun at the centre (per-sphere shadows); scatter otherwise
};

struct Event {
    double t;
    bool entry;
    double tau;
    dvec3 scatter;
    dvec3 emission;
    dvec3 sun_scatter;
};

bool vec_before(const dvec3& a, const dvec3& b, bool& decided) {
    for (int c = 0; c < 3; ++c) {
        if (a[c] != b[c]) {
            decided = true;
            return a[c] < b[c];
        }
    }
    decided = false;
    return false;
}

// A total order on event contents: equal distances are ordered by what the events carry, so the running
// sums are accumulated in the same order whatever order the spheres were listed or binned in.
bool event_before(const Event& a, const Event& b) {
    if (a.t != b.t) return a.t < b.t;
    if (a.entry != b.entry) return !a.entry;  // exits first: the sums return to exactly 0 sooner
    if (a.tau != b.tau) return a.tau < b.tau;
    bool decided = false;
    bool before = vec_before(a.scatter, b.scatter, decided);
    if (decided) return before;
    before = vec_before(a.emission, b.emission, decided);
    if (decided) return before;
    return vec_before(a.sun_scatter, b.sun_scatter, decided);
}
bool event_after(const Event& a, const Event& b) { return event_before(b, a); }

// (1 - exp(-x)) / x without cancellation for small x; 1 at x = 0.
double phi(double x) { return x == 0.0 ? 1.0 : -std::expm1(-x) / x; }

// Chord [t0, t1] of the line o + t d (d unit) through a sphere; false on a miss or a tangent (a zero-length
// chord adds nothing). The discriminant from the perpendicular offset avoids b^2 - c cancellation far from
// the sphere; the q-form avoids it in the near root.
bool sphere_chord(const Medium& m, const dvec3& o, const dvec3& d, double& t0, double& t1) {
    const dvec3 oc = o - m.center;
    const double b = glm::dot(oc, d);
    const dvec3 perp = oc - b * d;
    const double disc = m.radius2 - glm::dot(perp, perp);
    if (!(disc > 0.0)) return false;
    const double s = std::sqrt(disc);
    const double c = glm::dot(oc, oc) - m.radius2;
    const double q = b >= 0.0 ? -(b + s) : s - b;  // |q| >= s > 0
    const double ta = q;
    const double tb = c / q;
    t0 = std::min(ta, tb);
    t1 = std::max(ta, tb);
    return true;
}

// A cache line or more each (alignas): the vectors' ends move at every push_back, and two workers'
// scratch on one line would send it back and forth between their cores.
struct alignas(64) Scratch {
    std::vector<std::uint32_t> candidates;
    std::vector<Event> events;
    std::vector<double> kinks;  // where T_sun along the current ray is not smooth, sorted
    SunLight::ShadowSet shadow_set;  // what T_sun depends on between two of them
};

// Gauss-Kronrod 7-15 on [-1, 1] (the standard nodes and weights): the 15-point Kronrod rule, exact for
// polynomials to degree 22, and inside it the 7-point Gauss rule, exact to degree 13. Their difference
// estimates the 7-point rule's error, far larger than the 15-point rule's, so a panel accepted on it is
// better than asked. Nodes +-kNode[j], j < 7, and 0.
constexpr double kNode[8] = {0.991455371120812639206854697526329, 0.949107912342758524526189684047851,
                             0.864864423359769072789712788640926, 0.741531185599394439863864773280788,
                             0.586087235467691130294144845693013, 0.405845151377397166906606412076961,
                             0.207784955007898467600689403773245, 0.0};
constexpr double kKronrodWeight[8] = {0.022935322010529224963732008058970, 0.063092092629978553290700663189204,
                                      0.104790010322250183839876322541518, 0.140653259715525918745189590510238,
                                      0.169004726639267902826583426598550, 0.190350578064785409913256402421014,
                                      0.204432940075298892414161999234649, 0.209482141084727828012999174891714};
// The Gauss rule's weights, at kNode[1], kNode[3], kNode[5] and 0.
constexpr double kGaussWeight[4] = {0.129484966168869693270611432679082, 0.279705391489276667901467771423780,
                                    0.381830050505118944950369775488975, 0.417959183673469387755102040816327};

// The 15-point rule's integral of f over [a, b]; `error`, its difference from the 7-point rule's.
template <class F>
double gauss_kronrod15(const F& f, double a, double b, double& error) {
    const double h = 0.5 * (b - a), m = 0.5 * (a + b);
    const double centre = f(m);
    double kronrod = kKronrodWeight[7] * centre, gauss = kGaussWeight[3] * centre;
    for (int j = 0; j < 7; ++j) {
        const double pair = f(m - h * kNode[j]) + f(m + h * kNode[j]);
        kronrod += kKronrodWeight[j] * pair;
        if (j % 2 == 1) gauss += kGaussWeight[j / 2] * pair;
    }
    error = std::abs((kronrod - gauss) * h);
    return kronrod * h;
}

// Adaptive Gauss-Kronrod: a panel is accepted when its two rules agree to `tol`, else halved. It took
// 0.69x the integrand's evaluations of the adaptive 5-point Gauss-Legendre it replaced (a panel against
// its two halves), and the same images at float (vdb-cloud, 160x90: 2.8 s to 2.2 s a frame).
template <class F>
double adaptive_gauss_kronrod(const F& f, double a, double b, double tol, int depth) {
    double error;
    const double whole = gauss_kronrod15(f, a, b, error);
    if (depth <= 0 || error <= tol) return whole;
    const double m = 0.5 * (a + b);
    return adaptive_gauss_kronrod(f, a, m, 0.5 * tol, depth - 1) + adaptive_gauss_kronrod(f, m, b, 0.5 * tol, depth - 1);
}

// The scene reduced to what a ray needs.
class Tracer {
public:
    Tracer(const Scene& scene, ReferenceShadows technique)
        : lighting_(scene.lighting),
          min_transmittance_(scene.render.min_transmittance),
          sun_light_(scene),
          opaque_(scene, sun_light_),
          exact_shadows_(sun_light_.shadows() && technique == ReferenceShadows::Exact) {
        const std::vector<double> centre_sun = technique == ReferenceShadows::PerSphere
                                                   ? sun_transmittance_at_centres(scene)
                                                   : std::vector<double>(scene.spheres.size(), 1.0);
        media_.reserve(scene.spheres.size());
        for (std::size_t k = 0; k < scene.spheres.size(); ++k) {
            const Sphere& s = scene.spheres[k];
            const dvec3 scatter = s.extinction * s.albedo;
            media_.push_back({s.center, s.radius, s.radius * s.radius, s.extinction, scatter, s.extinction * s.emission,
                              scatter * centre_sun[k]});
        }
        const double sun_len = glm::length(lighting_.sun_direction);
        // A zero sun direction has no angle to the view; treat it as perpendicular rather than return NaN.
        sun_unit_ = sun_len > 0.0 ? lighting_.sun_direction / sun_len : dvec3(0.0);
    }

    const std::vector<Medium>& media() const { return media_; }

    // The opaque hit along o + t d (distance, +inf if none) and the radiance behind the media.
    double opaque_hit(const dvec3& o, const dvec3& d, dvec3& behind) const { return opaque_.hit(o, d, behind); }

    // Entry and exit events of the candidate spheres' clipped intervals, unsorted.
    void collect_events(const dvec3& o, const dvec3& d, double t_opaque, const std::vector<std::uint32_t>& candidates,
                        std::vector<Event>& events) const {
        events.clear();
        for (const std::uint32_t k : candidates) {
            const Medium& m = media_[k];
            double t0, t1;
            if (!sphere_chord(m, o, d, t0, t1)) continue;
            const double start = t0 > 0.0 ? t0 : 0.0;  // media containing the eye count from the eye
            const double end = std::min(t1, t_opaque);
            if (!(end > start)) continue;
            events.push_back({start, true, m.tau, m.scatter, m.emission, m.sun_scatter});
            events.push_back({end, false, m.tau, m.scatter, m.emission, m.sun_scatter});
        }
    }

    // Radiance toward o along unit direction d, from the spheres listed in candidates (indices into media()).
    dvec3 radiance(const dvec3& o, const dvec3& d, const std::vector<std::uint32_t>& candidates, Scratch& scratch) const {
        std::vector<Event>& events = scratch.events;
        dvec3 behind;
        const double t_opaque = opaque_hit(o, d, behind);
        collect_events(o, d, t_opaque, candidates, events);

        const double cos_theta = glm::dot(sun_unit_, d);
        const dvec3 sun_phase = lighting_.sun * (3.0 / (16.0 * kPi) * (1.0 + cos_theta * cos_theta));
        const dvec3 ls = lighting_.ambient + sun_phase;
        bool kinks_found = false;

        // A min-heap rather than a full sort: dense media usually stop early on transmittance.
        std::make_heap(events.begin(), events.end(), event_after);
        dvec3 radiance(0.0);
        double transmittance = 1.0;
        double sigma_t = 0.0;
        dvec3 sigma_s(0.0);
        dvec3 sigma_e(0.0);
        dvec3 sigma_sun(0.0);
        int active = 0;
        double t_prev = 0.0;
        for (auto last = events.end(); last != events.begin(); --last) {
            std::pop_heap(events.begin(), last, event_after);
            const Event& e = *(last - 1);
            const double l = e.t - t_prev;
            if (l > 0.0) {
                const double x = sigma_t * l;
                dvec3 c;
                if (exact_shadows_ && active > 0) {
                    if (!kinks_found) {
                        find_kinks(o, d, t_opaque, scratch.kinks);
                        kinks_found = true;
                    }
                    c = (sigma_s * lighting_.ambient + sigma_e) * l * phi(x) +
                        sigma_s * sun_phase * sun_integral(o, d, t_prev, e.t, sigma_t, scratch.kinks, scratch.shadow_set);
                } else {
                    // Without shadows sigma_sun == sigma_s bit for bit, and this is sigma_s * ls exactly.
                    c = (sigma_s * ls - (sigma_s - sigma_sun) * sun_phase + sigma_e) * l * phi(x);
                }
                radiance += transmittance * c;
                transmittance *= std::exp(-x);
                if (transmittance < min_transmittance_) return radiance;
            }
            if (e.entry) {
                sigma_t += e.tau;
                sigma_s += e.scatter;
                sigma_e += e.emission;
                sigma_sun += e.sun_scatter;
                ++active;
            } else {
                sigma_t -= e.tau;
                sigma_s -= e.scatter;
                sigma_e -= e.emission;
                sigma_sun -= e.sun_scatter;
                --active;
                if (active == 0) {
                    sigma_t = 0.0;
                    sigma_s = dvec3(0.0);
                    sigma_e = dvec3(0.0);
                    sigma_sun = dvec3(0.0);
                } else {
                    sigma_t = std::max(sigma_t, 0.0);
                    sigma_s = glm::max(sigma_s, dvec3(0.0));
                    sigma_e = glm::max(sigma_e, dvec3(0.0));
                    sigma_sun = glm::max(sigma_sun, dvec3(0.0));
                }
            }
            t_prev = e.t;
        }
        return radiance + transmittance * behind;
    }

private:
    void find_kinks(const dvec3& o, const dvec3& d, double t_end, std::vector<double>& kinks) const {
        kinks.clear();
        sun_light_.kinks(o, d, 0.0, t_end, kinks);
        std::sort(kinks.begin(), kinks.end());
    }

    // integral over [a, b] of exp(-sigma_t (t - a)) T_sun(o + t d) dt. Between kinks the integrand is smooth
    // except for square-root behaviour at the ends (a chord through a shadow cylinder starts as sqrt), which
    // the substitution t = p + (q - p)(3 s^2 - 2 s^3) makes smooth before the adaptive quadrature.
    double sun_integral(const dvec3& o, const dvec3& d, double a, double b, double sigma_t,
                        const std::vector<double>& kinks, SunLight::ShadowSet& shadow_set) const {
        double total = 0.0;
        double p = a;
        auto it = std::upper_bound(kinks.begin(), kinks.end(), a);
        for (;; ++it) {
            const double q = (it != kinks.end() && *it < b) ? *it : b;
            if (q > p) {
                const double width = q - p;
                // What T_sun depends on cannot change between two kinks: taken once, at the middle.
                sun_light_.shadow_set(o, d, p + 0.5 * width, shadow_set);
                if (!shadow_set.box_blocked) {  // else T_sun is 0 throughout
                    const auto f = [&](double s) {
                        const double t = p + width * (s * s * (3.0 - 2.0 * s));
                        // exp(-sigma_t (t - a)) T_sun in one exponential.
                        return std::exp(-(sigma_t * (t - a) + SunLight::optical_depth(shadow_set, t))) *
                               (width * 6.0 * s * (1.0 - s));
                    };
                    // The integral is at most width and at most about 1 / sigma_t; ask for 1e-10 of the
                    // smaller.
                    const double scale = sigma_t > 0.0 ? std::min(width, 1.0 / sigma_t) : width;
                    total += adaptive_gauss_kronrod(f, 0.0, 1.0, 1e-10 * scale, 24);
                }
            }
            if (q >= b) break;
            p = q;
        }
        return total;
    }

    std::vector<Medium> media_;
    Lighting lighting_;
    dvec3 sun_unit_;
    double min_transmittance_;
    SunLight sun_light_;
    OpaqueSurfaces opaque_;  // after sun_light_, which it reads
    bool exact_shadows_;
};

// A screen tile and the cone (around axis, half angle beta) holding all its pixel-centre directions.
struct Tile {
    int i0, j0, i1, j1;  // pixel range [i0, i1) x [j0, j1)
    dvec3 axis;
    double beta;
    double cos_beta, sin_beta;
    bool everything;  // so wide that the cone test is not worth trusting
};

double angle_between(const dvec3& a, const dvec3& b) {
    return std::atan2(glm::length(glm::cross(a, b)), glm::dot(a, b));
}

// `k`: the supersampling factor. The cone must hold every sub-pixel ray, the outermost of which lie 0.5 / k
// from the corner pixels' edges (at k = 1, the corner pixels' centres).
std::vector<Tile> make_tiles(const CameraRays& rays, int k) {
    const double inset = 0.5 / k;
    std::vector<Tile> tiles;
    for (int j0 = 0; j0 < rays.height; j0 += kTile) {
        for (int i0 = 0; i0 < rays.width; i0 += kTile) {
            Tile t{};
            t.i0 = i0;
            t.j0 = j0;
            t.i1 = std::min(i0 + kTile, rays.width);
            t.j1 = std::min(j0 + kTile, rays.height);
            t.axis = rays.direction(0.5 * (t.i0 + t.i1), 0.5 * (t.j0 + t.j1));
            // Pixel directions meet the image plane in a rectangle; a solid cone narrower than a half space
            // meets that plane in a convex set, so covering the four corner pixels covers the tile.
            t.beta = 0.0;
            for (const double x : {t.i0 + inset, t.i1 - inset})
                for (const double y : {t.j0 + inset, t.j1 - inset})
                    t.beta = std::max(t.beta, angle_between(t.axis, rays.direction(x, y)));
            t.cos_beta = std::cos(t.beta);
            t.sin_beta = std::sin(t.beta);
            t.everything = t.beta > 1.0;
            tiles.push_back(t);
        }
    }
    return tiles;
}

// The cone of directions from the eye that can meet a sphere grown by `grow`, widened by `widen` radians.
struct SphereCone {
    dvec3 dir;
    double alpha;
    double cos_alpha, sin_alpha;
    bool everywhere;  // contains (or nearly touches) the eye
};

std::vector<SphereCone> make_sphere_cones(const std::vector<Medium>& media, const dvec3& eye, double grow,
                                          double widen) {
    std::vector<SphereCone> cones;
    cones.reserve(media.size());
    for (const Medium& m : media) {
        SphereCone c{};
        const dvec3 v = m.center - eye;
        const double dist = glm::length(v);
        const double r = m.radius + grow;
        c.everywhere = !(dist > r * (1.0 + 1e-9));
        if (!c.everywhere) {
            c.dir = v / dist;
            c.alpha = std::asin(std::min(1.0, r / dist)) + kConeMargin + widen;
            c.cos_alpha = std::cos(c.alpha);
            c.sin_alpha = std::sin(c.alpha);
        }
        cones.push_back(c);
    }
    return cones;
}

// True when some direction within beta of the tile axis lies within alpha of the sphere direction:
// angle(dir, axis) <= alpha + beta, tested as cos(angle) >= cos(alpha + beta) while alpha + beta < pi.
bool cone_overlaps(const SphereCone& s, const Tile& t) {
    if (s.everywhere || t.everything || s.alpha + t.beta >= kPi) return true;
    return glm::dot(s.dir, t.axis) >= s.cos_alpha * t.cos_beta - s.sin_alpha * t.sin_beta;
}

void gather_candidates(const std::vector<SphereCone>* cones, std::size_t sphere_count, const Tile& tile,
                       std::vector<std::uint32_t>& out) {
    out.clear();
    for (std::size_t k = 0; k < sphere_count; ++k)
        if (!cones || cone_overlaps((*cones)[k], tile)) out.push_back(std::uint32_t(k));
}

// Tiles over parallel_for (sim/parallel_for.h), each worker with its own scratch.
template <class Work>
void parallel_tiles(std::size_t tile_count, int threads, const Work& work) {
    std::vector<Scratch> scratch(std::size_t(worker_count(threads, tile_count)));
    parallel_for(tile_count, threads, [&](std::size_t tile, int worker) { work(tile, scratch[std::size_t(worker)]); });
}

void store(Image& image, int i, int j, const dvec3& v) {
    float* p = image.pixel(i, j);
    p[0] = float(v.x);
    p[1] = float(v.y);
    p[2] = float(v.z);
}

void check_camera(const Scene& scene) {
    if (!scene.volumes.empty())
        throw std::logic_error("reference renderer: the scene's [[vdb]] volumes were not converted to spheres "
                               "(sim/vdb/volume_loader.h convert_scene_volumes)");
    if (scene.camera.width <= 0 || scene.camera.height <= 0)
        throw std::invalid_argument("reference renderer: camera of " + std::to_string(scene.camera.width) + "x" +
                                    std::to_string(scene.camera.height) + " pixels");
}

int supersample_of(const Scene& scene) {
    const int k = scene.camera.supersample;
    if (k < 1 || k > kMaxSupersample)
        throw std::invalid_argument("reference renderer: supersample " + std::to_string(k) + " (must be 1 to " +
                                    std::to_string(kMaxSupersample) + ")");
    return k;
}

// The ray through sub-pixel (a, b) of k x k in pixel (i, j): (i + (a + 0.5) / k, j + (b + 0.5) / k).
dvec3 sub_pixel_direction(const CameraRays& rays, int i, int j, int a, int b, int k) {
    if (k == 1) return rays.pixel_direction(i, j);
    return rays.direction(i + (a + 0.5) / k, j + (b + 0.5) / k);
}

double scene_scale(const Scene& scene) {
    double scale = std::max(1.0, glm::length(scene.camera.position));
    for (const Sphere& s : scene.spheres) scale = std::max(scale, glm::length(s.center) + s.radius);
    for (const Box& b : scene.boxes)
        scale = std::max(scale, glm::length(0.5 * (b.min + b.max)) + 0.5 * glm::length(b.max - b.min));
    return scale;
}

}  // namespace

Image render_reference(const Scene& scene, const ReferenceOptions& options) {
    check_camera(scene);
    const Tracer tracer(scene, options.shadows);
    const CameraRays rays = make_camera_rays(scene.camera);
    const int k = supersample_of(scene);
    const std::vector<Tile> tiles = make_tiles(rays, k);
    const std::vector<SphereCone> cones = make_sphere_cones(tracer.media(), rays.eye, 0.0, 0.0);
    const std::vector<SphereCone>* bins = options.brute_force ? nullptr : &cones;

    Image image(rays.width, rays.height);
    // The tiles in a scattered order (a golden-ratio stride through them): each pixel's answer is its
    // own, so the order changes no bit, and the share of pixels done is then a fair share of the
    // frame's time (options.pixels_done: a progress display's estimate), where in raster order the
    // sky came first and the smoke last.
    const std::size_t count = tiles.size();
    std::size_t stride = std::max<std::size_t>(1, std::size_t(double(count) * 0.6180339887498949));
    while (std::gcd(stride, count) != 1) ++stride;
    parallel_tiles(count, options.threads, [&](std::size_t n, Scratch& s) {
        const Tile& tile = tiles[n * stride % count];
        gather_candidates(bins, tracer.media().size(), tile, s.candidates);
        for (int j = tile.j0; j < tile.j1; ++j) {
            for (int i = tile.i0; i < tile.i1; ++i) {
                // The mean of the k x k sub-pixel rays; at k = 1 the one ray through the centre, bit for bit.
                dvec3 sum(0.0);
                for (int b = 0; b < k; ++b)
                    for (int a = 0; a < k; ++a)
                        sum += tracer.radiance(rays.eye, sub_pixel_direction(rays, i, j, a, b, k), s.candidates, s);
                store(image, i, j, sum / double(k * k));
            }
        }
        if (options.pixels_done)
            options.pixels_done->fetch_add(std::uint64_t(tile.i1 - tile.i0) * std::uint64_t(tile.j1 - tile.j0),
                                           std::memory_order_relaxed);
    });
    return image;
}

glm::dvec3 reference_radiance(const Scene& scene, const glm::dvec3& origin, const glm::dvec3& unit_dir,
                              const ReferenceOptions& options) {
    const Tracer tracer(scene, options.shadows);
    std::vector<std::uint32_t> all(tracer.media().size());
    for (std::size_t k = 0; k < all.size(); ++k) all[k] = std::uint32_t(k);
    Scratch scratch;
    return tracer.radiance(origin, unit_dir, all, scratch);
}

std::vector<std::uint32_t> reference_list_lengths(const Scene& scene, const ReferenceOptions& options) {
    check_camera(scene);
    const Tracer tracer(scene, options.shadows);
    const CameraRays rays = make_camera_rays(scene.camera);
    const std::vector<Tile> tiles = make_tiles(rays, 1);
    const std::vector<SphereCone> cones = make_sphere_cones(tracer.media(), rays.eye, 0.0, 0.0);
    const std::vector<SphereCone>* bins = options.brute_force ? nullptr : &cones;
    std::vector<std::uint32_t> lengths(std::size_t(rays.width) * std::size_t(rays.height), 0);
    parallel_tiles(tiles.size(), options.threads, [&](std::size_t k, Scratch& s) {
        const Tile& tile = tiles[k];
        gather_candidates(bins, tracer.media().size(), tile, s.candidates);
        for (int j = tile.j0; j < tile.j1; ++j) {
            for (int i = tile.i0; i < tile.i1; ++i) {
                const dvec3 d = rays.pixel_direction(i, j);
                dvec3 behind;
                tracer.collect_events(rays.eye, d, tracer.opaque_hit(rays.eye, d, behind), s.candidates, s.events);
                lengths[std::size_t(j) * std::size_t(rays.width) + std::size_t(i)] = std::uint32_t(s.events.size() / 2);
            }
        }
    });
    return lengths;
}

Image reference_tolerance(const Scene& scene, double rel_error, const ReferenceOptions& options) {
    check_camera(scene);
    if (!(rel_error >= 0.0) || !std::isfinite(rel_error))
        throw std::invalid_argument("reference_tolerance: rel_error must be finite and >= 0");
    const Tracer tracer(scene, options.shadows);
    const CameraRays rays = make_camera_rays(scene.camera);
    const int k = supersample_of(scene);
    const std::vector<Tile> tiles = make_tiles(rays, k);
    const double offset = rel_error * scene_scale(scene);
    // A ray from eye + delta (|delta| <= offset) that meets a sphere has a parallel twin from the eye that
    // meets the sphere grown by offset; the tilt widens the cone by rel_error.
    const std::vector<SphereCone> cones = make_sphere_cones(tracer.media(), rays.eye, offset, rel_error);
    const std::vector<SphereCone>* bins = options.brute_force ? nullptr : &cones;
    const dvec3 right = glm::normalize(rays.right);
    const double cos_e = std::cos(rel_error);
    const double sin_e = std::sin(rel_error);

    Image image(rays.width, rays.height);
    parallel_tiles(tiles.size(), options.threads, [&](std::size_t tile_index, Scratch& s) {
        const Tile& tile = tiles[tile_index];
        gather_candidates(bins, tracer.media().size(), tile, s.candidates);
        for (int j = tile.j0; j < tile.j1; ++j) {
            for (int i = tile.i0; i < tile.i1; ++i) {
                // A supersampled pixel is a mean of sub-rays, so its tolerance is the mean of theirs.
                dvec3 sum(0.0);
                for (int sb = 0; sb < k; ++sb) {
                    for (int sa = 0; sa < k; ++sa) {
                        const dvec3 d = sub_pixel_direction(rays, i, j, sa, sb, k);
                        const dvec3 base = tracer.radiance(rays.eye, d, s.candidates, s);
                        // Lateral basis around this ray, aligned with the camera's right and up.
                        const dvec3 r = glm::normalize(right - glm::dot(right, d) * d);
                        const dvec3 u = glm::cross(r, d);
                        dvec3 worst(0.0);
                        for (int n = 0; n < 8; ++n) {
                            const double a = n * (kPi / 4.0);
                            const dvec3 w = std::cos(a) * r + std::sin(a) * u;
                            const dvec3 dp = glm::normalize(cos_e * d + sin_e * w);
                            const dvec3 v = tracer.radiance(rays.eye + offset * w, dp, s.candidates, s);
                            worst = glm::max(worst, glm::abs(v - base));
                        }
                        sum += worst;
                    }
                }
                store(image, i, j, sum / double(k * k));
            }
        }
    });
    return image;
}

}  // namespace brume
