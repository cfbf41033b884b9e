// The scene sections' schema and readers (sim/scene_sections.h): one function per section, each checking
// its keys and values with the toolkit (sim/toml_reader.h) and the limits of sim/scene_file.h.
#include "sim/scene_sections.h"

#include "sim/camera_rays.h"

#include "sim/volume_transform.h"

#include <glm/geometric.hpp>

#include <cstdint>
#include <vector>

namespace brume {

using toml_read::KeyPath;
using toml_read::Reader;
using toml_read::Vec3Field;
using toml_text::shortest;

namespace {

// The schema, in the order keys are checked and written.
constexpr std::array<std::string_view, 7> kCameraKeys{"position", "look_at", "up",         "fov_y_deg",
                                                     "width",    "height",  "supersample"};
constexpr std::array<std::string_view, 5> kLightingKeys{"ambient", "sun", "sun_direction", "background", "shadows"};
constexpr std::array<std::string_view, 2> kRenderKeys{"min_transmittance", "shadow_technique"};
constexpr std::array<std::string_view, 2> kShadowTechniques{kShadowTechniqueNames[0], kShadowTechniqueNames[1]};
constexpr std::array<std::string_view, 4> kBoxKeys{"min", "max", "radiance", "diffuse"};
// Required in every [[box]]; the rest are optional.
constexpr std::array<std::string_view, 3> kBoxRequiredKeys{"min", "max", "radiance"};
constexpr std::array<std::string_view, 5> kSphereKeys{"center", "radius", "extinction", "albedo", "emission"};
constexpr std::array<std::string_view, 4> kSphereRequiredKeys{"center", "radius", "extinction", "albedo"};
constexpr std::array<std::string_view, 11> kVdbKeys{"file",        "grid",        "albedo_grid", "extinction_scale",
                                                    "albedo",      "tolerance",   "max_spheres", "fit",
                                                    "translate",   "scale",       "rotate"};

void read_camera(const Reader& in, const toml::node& node, const KeyPath& path, Camera& c) {
    const toml::table& t = in.table(node, path, kCameraKeys);
    const toml::node* position = t.get("position");
    const toml::node* look_at = t.get("look_at");
    const toml::node* up = t.get("up");
    if (position) c.position = in.coordinates(*position, path / "position");
    if (look_at) c.look_at = in.coordinates(*look_at, path / "look_at");
    if (up) c.up = in.coordinates(*up, path / "up");
    if (const toml::node* n = t.get("fov_y_deg")) {
        const KeyPath p = path / "fov_y_deg";
        c.fov_y_deg = in.number(*n, p);
        if (!(c.fov_y_deg > 0.0 && c.fov_y_deg <= kMaxFovYDeg))
            in.fail(*n, p, "must be in (0, 179] degrees (got " + shortest(c.fov_y_deg) + ")");
    }
    if (const toml::node* n = t.get("width")) c.width = int(in.integer_in(*n, path / "width", 1, kMaxImageSide));
    if (const toml::node* n = t.get("height")) c.height = int(in.integer_in(*n, path / "height", 1, kMaxImageSide));
    if (const toml::node* n = t.get("supersample"))
        c.supersample = int(in.integer_in(*n, path / "supersample", 1, kMaxSupersample));

    // make_camera_rays normalises look_at - position and cross(forward, up): both must be well defined.
    const glm::dvec3 view = c.look_at - c.position;
    const double view_length = glm::length(view);
    if (!(view_length > 0.0))
        in.fail(toml_read::where(t, {position, look_at}), path / (look_at ? "look_at" : "position"),
                "position and look_at must differ (they are the same point)");
    const double up_length = glm::length(c.up);
    if (!(up_length > 0.0)) in.fail(toml_read::where(t, {up}), path / "up", "must not be zero");
    if (!view_has_roll(view, c.up))
        in.fail(toml_read::where(t, {position, look_at, up}), path / "up",
                std::string("must not be parallel to the view direction (look_at - position)") +
                    (up ? "" : "; up is [0, 1, 0] unless given: a camera looking straight down or up needs its own, e.g. up = [0, 0, -1]"));
}

void read_lighting(const Reader& in, const toml::node& node, const KeyPath& path, Lighting& l) {
    const toml::table& t = in.table(node, path, kLightingKeys);
    if (const toml::node* n = t.get("ambient")) l.ambient = in.radiance(*n, path / "ambient");
    if (const toml::node* n = t.get("sun")) l.sun = in.radiance(*n, path / "sun");
    if (const toml::node* n = t.get("sun_direction")) l.sun_direction = in.direction(*n, path / "sun_direction");
    if (const toml::node* n = t.get("background")) l.background = in.radiance(*n, path / "background");
    if (const toml::node* n = t.get("shadows")) l.shadows = in.boolean(*n, path / "shadows");
}

void read_render(const Reader& in, const toml::node& node, const KeyPath& path, RenderSettings& r) {
    const toml::table& t = in.table(node, path, kRenderKeys);
    if (const toml::node* n = t.get("min_transmittance")) {
        const KeyPath p = path / "min_transmittance";
        r.min_transmittance = in.number(*n, p);
        if (!(r.min_transmittance >= 0.0 && r.min_transmittance < 1.0))
            in.fail(*n, p, "must be in [0, 1) (got " + shortest(r.min_transmittance) + ")");
    }
    if (const toml::node* n = t.get("shadow_technique"))
        r.shadow_technique = ShadowTechnique(in.choice(*n, path / "shadow_technique", kShadowTechniques));
}

Box read_box(const Reader& in, const toml::table& t, const KeyPath& path) {
    in.check_keys(t, path, kBoxKeys);
    Box b;
    b.min = in.coordinates(in.required(t, "min", path, kBoxRequiredKeys), path / "min");
    const toml::node& max = in.required(t, "max", path, kBoxRequiredKeys);
    b.max = in.coordinates(max, path / "max");
    b.radiance = in.radiance(in.required(t, "radiance", path, kBoxRequiredKeys), path / "radiance");
    if (const toml::node* n = t.get("diffuse")) b.diffuse = in.albedo(*n, path / "diffuse").v;
    for (int c = 0; c < 3; ++c) {
        if (!(b.min[c] < b.max[c])) {
            const char axis = "xyz"[c];
            in.fail(max, path / "max",
                    std::string("must exceed min on every axis (max.") + axis + " = " + shortest(b.max[c]) + ", min." +
                        axis + " = " + shortest(b.min[c]) + ")");
        }
    }
    return b;
}

Sphere read_sphere(const Reader& in, const toml::table& t, const KeyPath& path) {
    in.check_keys(t, path, kSphereKeys);
    Sphere s;
    s.center = in.coordinates(in.required(t, "center", path, kSphereRequiredKeys), path / "center");
    {
        const toml::node& n = in.required(t, "radius", path, kSphereRequiredKeys);
        const KeyPath p = path / "radius";
        s.radius = in.number(n, p);
        if (!(s.radius > 0.0)) in.fail(n, p, "must be positive and finite (got " + shortest(s.radius) + ")");
        in.at_most(n, p, s.radius, kMaxCoordinate);
    }
    {
        const toml::node& n = in.required(t, "extinction", path, kSphereRequiredKeys);
        s.extinction = in.non_negative(n, path / "extinction", kMaxExtinction);
    }
    s.albedo = in.albedo(in.required(t, "albedo", path, kSphereRequiredKeys), path / "albedo").v;
    if (const toml::node* n = t.get("emission")) s.emission = in.radiance(*n, path / "emission");
    return s;
}

// A grid's name, as OpenVDB files store it: any non-empty line of text.
std::string grid_name(const Reader& in, const toml::node& n, const KeyPath& path) {
    std::string name = in.one_line(n, path);
    if (name.empty()) in.fail(n, path, "must not be empty (it names a grid in the file)");
    return name;
}

// One number for grey, or [r, g, b]; each in [0, 1].
glm::dvec3 uniform_albedo(const Reader& in, const toml::node& n, const KeyPath& path) {
    if (n.is_integer() || n.is_floating_point()) return glm::dvec3(in.in_interval(n, path, 0.0, 1.0, false));
    if (!n.is_array()) in.fail(n, path, "must be a number or [r, g, b] (got " + toml_read::describe(n) + ")");
    return in.albedo(n, path).v;
}

VdbVolume read_volume(const Reader& in, const toml::table& t, const KeyPath& path) {
    in.check_keys(t, path, kVdbKeys);
    VdbVolume v;
    read_density_source(in, t, path, "each [[vdb]] needs file", v.source);
    // "" turns off the default (the file's "albedo" grid when it has one).
    if (const toml::node* n = t.get("albedo_grid")) v.albedo_grid = in.one_line(*n, path / "albedo_grid");
    if (const toml::node* n = t.get("extinction_scale"))
        v.extinction_scale = in.positive(*n, path / "extinction_scale", kMaxExtinction);
    if (const toml::node* n = t.get("albedo")) v.albedo = uniform_albedo(in, *n, path / "albedo");
    // Fitted spheres (sim/vdb/sphere_fit.h) instead of a tiling: the fit stops at the tolerance, or at
    // max_spheres when that comes first, so a fitted volume may give both.
    if (const toml::node* n = t.get("fit")) v.fit = in.boolean(*n, path / "fit");
    // Two ways to say how fine a tiling is: meeting both at once is not generally possible.
    const toml::node* tolerance = t.get("tolerance");
    const toml::node* max_spheres = t.get("max_spheres");
    if (tolerance && max_spheres && !v.fit) {
        const toml::node* last = toml_read::last_of({tolerance, max_spheres});
        in.fail(*last, path / (last == tolerance ? "tolerance" : "max_spheres"),
                "give tolerance or max_spheres, not both (tolerance: the accuracy to meet; max_spheres: the "
                "most spheres to spend; with fit = true, both: the fit stops at whichever comes first)");
    }
    if (tolerance) v.tolerance = in.in_interval(*tolerance, path / "tolerance", 0.0, 1.0, true);
    if (max_spheres)
        v.max_spheres = std::size_t(in.integer_in(*max_spheres, path / "max_spheres", 1, std::int64_t(kMaxSpheres)));
    v.transform = read_volume_transform(in, t, path);
    v.defined_at = in.location(t);
    return v;
}

}  // namespace

const std::array<toml_read::SectionHint, 6> kSceneSectionHints{{
    {kCameraKeys, "it belongs under [camera]"},
    {kLightingKeys, "it belongs under [lighting]"},
    {kRenderKeys, "it belongs under [render]"},
    {kBoxKeys, "it belongs in a [[box]] section"},
    {kSphereKeys, "it belongs in a [[sphere]] section"},
    {kVdbKeys, "it belongs in a [[vdb]] section"},
}};

void check_scene_root_keys(const Reader& in) {
    in.check_root_keys(kSceneSections, {kSceneSectionHints}, kPresetSections,
                       "a preset section: not allowed in a static scene file (read the file as a preset)");
}

Scene read_scene(const Reader& in, const std::string& source_name) {
    check_scene_root_keys(in);
    Scene scene;
    read_scene_sections(in, scene);
    scene.source = source_name;
    return scene;
}

void read_scene_sections(const Reader& in, Scene& s) {
    const toml::table& root = in.root();
    const KeyPath top;
    if (const toml::node* n = root.get("camera")) read_camera(in, *n, top / "camera", s.camera);
    if (const toml::node* n = root.get("lighting")) read_lighting(in, *n, top / "lighting", s.lighting);
    if (const toml::node* n = root.get("render")) read_render(in, *n, top / "render", s.render);
    if (const toml::node* n = root.get("box")) in.read_each(*n, top / "box", kMaxBoxes, "boxes", s.boxes, read_box);
    if (const toml::node* n = root.get("sphere"))
        in.read_each(*n, top / "sphere", kMaxSpheres, "spheres", s.spheres, read_sphere);
    if (const toml::node* n = root.get("vdb"))
        in.read_each(*n, top / "vdb", kMaxVolumes, "[[vdb]] volumes", s.volumes, read_volume);
    // Four lines of TOML render a .vdb: with no camera placement given, the loader frames the volumes.
    const toml::table* camera_table = root.get("camera") ? root.get("camera")->as_table() : nullptr;
    const bool placed = camera_table && (camera_table->get("position") || camera_table->get("look_at"));
    s.frame_volumes = !s.volumes.empty() && !placed;
}

void read_density_source(const Reader& in, const toml::table& t, const KeyPath& path, std::string_view needs,
                         DensitySource& s) {
    const KeyPath file_path = path / "file";
    const toml::node& file = in.required(t, "file", path, std::string(needs) + ": a .vdb path or builtin:NAME");
    s.file = in.one_line(file, file_path);
    if (s.file.empty()) in.fail(file, file_path, "must not be empty (a .vdb path or builtin:NAME)");
    if (const toml::node* n = t.get("grid")) s.grid = grid_name(in, *n, path / "grid");
}

VolumeTransform read_volume_transform(const Reader& in, const toml::table& t, const KeyPath& path) {
    VolumeTransform result;
    const auto check = [&](const toml::node& n, std::string_view key, const VolumeTransform& alone) {
        const std::string problem = volume_transform_problem(alone);
        if (!problem.empty()) in.fail(n, path / key, problem);
    };
    if (const toml::node* n = t.get("translate")) {
        VolumeTransform alone;
        alone.translate = in.vec3(*n, path / "translate").v;
        check(*n, "translate", alone);
        result.translate = alone.translate;
    }
    if (const toml::node* n = t.get("scale")) {
        VolumeTransform alone;
        alone.scale = in.number(*n, path / "scale");
        check(*n, "scale", alone);
        result.scale = alone.scale;
    }
    if (const toml::node* n = t.get("rotate")) {
        VolumeTransform alone;
        alone.rotate_deg = in.vec3(*n, path / "rotate").v;
        check(*n, "rotate", alone);
        result.rotate_deg = alone.rotate_deg;
    }
    return result;
}

}  // namespace brume
