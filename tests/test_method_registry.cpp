// The method catalogue (render/methods/registry.h): names and settings parse as `--method` takes
// them, options reach the methods that honour them and are refused by the others, and `brume bench`
// sweeps what the entries say.
#include "render/methods/registry.h"
#include "render/reference.h"
#include "test_scenes.h"

#include <gtest/gtest.h>

#include <set>
#include <string>
#include <vector>
#include <stdexcept>

namespace brume {
namespace {

// `spec` is refused by check_method_spec, with a message that names its method.
void expect_refused_naming_its_method(const std::string& spec) {
    try {
        check_method_spec(spec);
        ADD_FAILURE() << spec << " was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find(spec.substr(0, spec.find(':'))), std::string::npos) << e.what();
    }
}

bool same_pixels(const Image& a, const Image& b) { return a.width == b.width && a.height == b.height && a.rgb == b.rgb; }

TEST(MethodRegistry, TheReferenceTakesTheScenesShadowTechnique) {
    // `--method reference --shadows per-sphere` (and crossing, pop) renders the reference's per-sphere mode,
    // what the methods shading by that technique are measured against; `accurate` the exact model.
    Scene s = testing::random_scene(24, 18, 40, 3, true);
    s.lighting.shadows = true;
    s.lighting.sun_direction = {-0.4, -0.8, -0.3};
    ReferenceOptions per_sphere;
    per_sphere.shadows = ReferenceShadows::PerSphere;
    const Image exact = render_reference(s), approximated = render_reference(s, per_sphere);
    ASSERT_FALSE(same_pixels(exact, approximated));  // else the scene tells the modes apart nowhere
    s.render.shadow_technique = ShadowTechnique::PerSphere;
    EXPECT_TRUE(same_pixels(make_method(nullptr, "reference")->render(s), approximated));
    s.render.shadow_technique = ShadowTechnique::Accurate;
    EXPECT_TRUE(same_pixels(make_method(nullptr, "reference")->render(s), exact));
}

TEST(MethodRegistry, NamesAreUniqueAndFindable) {
    std::set<std::string> names;
    for (const MethodEntry& m : method_catalogue()) {
        EXPECT_TRUE(names.insert(m.name).second) << m.name;
        EXPECT_EQ(&find_method(m.name), &m);
        EXPECT_NE(m.make, nullptr) << m.name;
        EXPECT_FALSE(m.summary.empty()) << m.name;
        // A method with a setting says what an empty one means; one without takes none.
        EXPECT_EQ(m.setting.empty(), m.default_setting.empty()) << m.name;
        if (m.setting.empty()) {
            EXPECT_TRUE(m.bench_settings.empty()) << m.name;
        }
    }
    EXPECT_EQ(&find_method("kbuf:16"), &find_method("kbuf"));
    try {
        find_method("kbuff");
        FAIL() << "an unknown name was accepted";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("unknown method 'kbuff'"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("ppll"), std::string::npos) << e.what();  // the known ones listed
    }
}

TEST(MethodRegistry, ExactMethodsAreTheOnesThatMatchTheReference) {
    std::set<std::string> exact;
    for (const MethodEntry& m : method_catalogue())
        if (m.exact) exact.insert(m.name);
    EXPECT_EQ(exact, (std::set<std::string>{"ppll", "ppll-general", "tiles", "trace", "reference", "auto"}));
}

TEST(MethodRegistry, OptionsReachEveryMethodThatHonoursThem) {
    // --max-memory (and --pool-nodes) reach both methods that keep per-pixel lists.
    EXPECT_NO_THROW(check_method_options("ppll", kHonoursMaxMemory));
    EXPECT_NO_THROW(check_method_options("auto", kHonoursMaxMemory));
    EXPECT_NO_THROW(check_method_options("sorted", 0));
    // Given to a method that would ignore it, an option is refused, naming who honours it.
    try {
        check_method_options("kbuf:4", kHonoursMaxMemory);
        FAIL() << "--max-memory was accepted for kbuf";
    } catch (const std::invalid_argument& e) {
        const std::string what = e.what();
        EXPECT_NE(what.find("--max-memory"), std::string::npos) << what;
        EXPECT_NE(what.find("ppll, ppll-general, tiles, auto"), std::string::npos) << what;
        EXPECT_NE(what.find("'kbuf'"), std::string::npos) << what;
    }
    // --pool-nodes sizes a node pool: ppll's and auto's. tiles has none (its lists are sized per frame,
    // bounded by --max-memory): it refuses --pool-nodes, which it had taken and ignored.
    EXPECT_NO_THROW(check_method_options("ppll-general", kHonoursMaxMemory | kHonoursPoolNodes));
    EXPECT_NO_THROW(check_method_options("auto", kHonoursMaxMemory | kHonoursPoolNodes));
    EXPECT_NO_THROW(check_method_options("tiles", kHonoursMaxMemory));
    try {
        check_method_options("tiles", kHonoursPoolNodes);
        FAIL() << "--pool-nodes was accepted for tiles";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("--pool-nodes applies to ppll, ppll-general, auto, not to method 'tiles'"),
                  std::string::npos)
            << e.what();
    }
    // Each refusal names only the options given: play, which has no --pool-nodes, was told
    // "--max-memory/--pool-nodes applies to ...".
    for (const unsigned given : {unsigned(kHonoursMaxMemory), unsigned(kHonoursPoolNodes)}) {
        try {
            check_method_options("trace", given);
            FAIL() << "a list-pool option was accepted for trace";
        } catch (const std::invalid_argument& e) {
            const std::string what = e.what();
            const bool pool = given == kHonoursPoolNodes;
            EXPECT_EQ(what.find("--pool-nodes") != std::string::npos, pool) << what;
            EXPECT_EQ(what.find("--max-memory") != std::string::npos, !pool) << what;
            EXPECT_NE(what.find(pool ? "ppll, ppll-general, auto" : "ppll, ppll-general, tiles, auto"), std::string::npos)
                << what;
        }
    }
}

TEST(MethodRegistry, SettingsAreCheckedBeforeAnyDeviceIsNeeded) {
    EXPECT_THROW(make_method(nullptr, "ppll:4"), std::invalid_argument);       // takes no setting
    EXPECT_THROW(make_method(nullptr, "ppll"), std::invalid_argument);         // needs a device
    EXPECT_THROW(make_method(nullptr, "nonsense:1"), std::invalid_argument);
    auto reference = make_method(nullptr, "reference");
    ASSERT_NE(reference, nullptr);
    EXPECT_EQ(reference->name(), "reference");
    EXPECT_EQ(reference->gpu(), nullptr);  // runs on the CPU, not through the frame path
}

// check_method_spec refuses what the factories would, without a device: every method with a setting
// has its check, every setting brume bench sweeps passes it, and bad ones name their method.
TEST(MethodRegistry, ASpecsSettingIsCheckedWithoutADevice) {
    for (const MethodEntry& m : method_catalogue()) {
        EXPECT_EQ(m.setting.empty(), m.check_setting == nullptr) << m.name;
        EXPECT_NO_THROW(check_method_spec(m.name)) << m.name;
        for (const std::string& s : m.bench_settings) EXPECT_NO_THROW(check_method_spec(m.name + ":" + s)) << s;
        if (!m.setting.empty()) {
            EXPECT_NO_THROW(check_method_spec(m.name + ":" + m.default_setting)) << m.name;
        }
    }
    for (const char* bad : {"kbuf:0", "kbuf:33", "kbuf:x", "peel:0", "peel:65", "peel:dual:x", "stochastic:3",
                            "stochastic:128", "stochastic:8,foo", "screendoor:0", "screendoor:9", "ppll:4", "magic"})
        expect_refused_naming_its_method(bad);
}

// A ':' with nothing after it ("kbuf:", an unset variable in a script) rendered the default and was named
// "kbuf:" in the stats; "peel:dual" rendered peel:dual:8. Each is refused, naming its method.
TEST(MethodRegistry, AnEmptySettingIsRefused) {
    for (const char* bad : {"kbuf:", "peel:", "peel:dual", "peel:dual:", "stochastic:", "stochastic:8,", "screendoor:",
                            "ppll:", "trace:"})
        expect_refused_naming_its_method(bad);
    EXPECT_NO_THROW(check_method_spec("kbuf"));  // the default, asked for by leaving ':' out
    EXPECT_NO_THROW(check_method_spec("peel:dual:8"));
}

// `--methods` splits on commas, but stochastic's setting holds one (S[,plain|,depth]), and the default
// sweep itself renders stochastic:8,depth: a list naming it was refused as "unknown method 'depth'".
TEST(MethodRegistry, AMethodListKeepsSettingsThatHoldAComma) {
    using List = std::vector<std::string>;
    EXPECT_EQ(split_method_list("stochastic:8,depth"), (List{"stochastic:8,depth"}));
    EXPECT_EQ(split_method_list("ppll,stochastic:8,plain,kbuf:4"), (List{"ppll", "stochastic:8,plain", "kbuf:4"}));
    EXPECT_EQ(split_method_list("stochastic:8,depth,stochastic:4"), (List{"stochastic:8,depth", "stochastic:4"}));
    EXPECT_EQ(split_method_list(",ppll,,trace,"), (List{"ppll", "trace"}));
    EXPECT_EQ(split_method_list(","), List{});
    // A token that completes no spec stays one, and is refused as what it is.
    EXPECT_EQ(split_method_list("ppll,depth"), (List{"ppll", "depth"}));
    EXPECT_EQ(split_method_list("stochastic,depth"), (List{"stochastic", "depth"}));
    EXPECT_EQ(split_method_list("kbuf:4,depth"), (List{"kbuf:4", "depth"}));
    EXPECT_THROW(check_method_spec(split_method_list("ppll,depth")[1]), std::invalid_argument);
    // A joined token that its method refuses is refused by the method's own check.
    const List bad = split_method_list("stochastic:8,magic");
    ASSERT_EQ(bad.size(), 1u);
    EXPECT_THROW(check_method_spec(bad[0]), std::invalid_argument);
    // Every spec of the default sweep survives being written as a list.
    std::string all;
    for (const std::string& spec : bench_method_specs()) all += (all.empty() ? "" : ",") + spec;
    EXPECT_EQ(split_method_list(all), bench_method_specs());
}

// `brume methods`: one line per entry, the summaries starting in one column (stochastic's setting ran
// into its summary), and peel's setting written as the spec that works (peel:dual:N; "dual:6" is no method).
TEST(MethodRegistry, TheListingAlignsItsSummariesAndNamesWorkingSpecs) {
    const std::vector<std::string> lines = method_listing();
    ASSERT_EQ(lines.size(), method_catalogue().size());
    std::size_t column = std::string::npos;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        const MethodEntry& m = method_catalogue()[i];
        const std::size_t at = lines[i].find(m.summary);
        ASSERT_NE(at, std::string::npos) << lines[i];
        if (column == std::string::npos) column = at;
        EXPECT_EQ(at, column) << lines[i];
        EXPECT_EQ(lines[i].rfind(m.name, 0), 0u) << lines[i];
        EXPECT_EQ(lines[i][at - 1], ' ') << lines[i];
        EXPECT_EQ(lines[i][at - 2], ' ') << lines[i];  // at least two spaces after the widest name
    }
    for (const std::string& line : lines)
        if (line.rfind("peel", 0) == 0) {
            EXPECT_EQ(line.find("|dual"), std::string::npos) << line;
            EXPECT_NE(line.find("peel:[dual:]N"), std::string::npos) << line;
        }
    EXPECT_THROW(check_method_spec("dual:6"), std::invalid_argument);
    EXPECT_NO_THROW(check_method_spec("peel:dual:6"));
}

TEST(MethodRegistry, BenchSweepsEveryMethodButTheReference) {
    const std::vector<std::string> specs = bench_method_specs();
    std::size_t expected = 0;
    for (const MethodEntry& m : method_catalogue())
        if (m.name != "reference") expected += 1 + m.bench_settings.size();
    EXPECT_EQ(specs.size(), expected);
    EXPECT_EQ(specs.front(), "ppll");
    const std::set<std::string> set(specs.begin(), specs.end());
    EXPECT_EQ(set.size(), specs.size());
    EXPECT_EQ(set.count("reference"), 0u);
    for (const char* s : {"kbuf:4", "kbuf:16", "peel:dual:8", "stochastic:8,depth", "screendoor:2"})
        EXPECT_EQ(set.count(s), 1u) << s;
}

}  // namespace
}  // namespace brume
