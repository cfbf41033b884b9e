// The preview's live edits (app/preview_edit.*): every value of every shipped preset, written back
// as the panel writes it, reads back to the same preset; a set reaches the preset; bad paths, bad
// values and values the reader refuses are named, and a refused edit is not kept.
#include "app/preview_edit.h"

#include "sim/builtin_presets.h"
#include "sim/preset_file.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace brume::app {
namespace {

std::string message_of(PresetEditor& editor, const std::string& key, const std::string& value) {
    try {
        editor.set(key, value);
    } catch (const std::invalid_argument& e) {
        return e.what();
    }
    return "(accepted)";
}

TEST(PreviewEdit, EveryValueOfEveryPresetRoundTrips) {
    for (const std::string& name : builtin_preset_names()) {
        SCOPED_TRACE(name);
        const std::string text(*builtin_preset_toml(name));
        const std::string source = "presets/" + name + ".toml";
        const std::string want = preset_to_toml(parse_preset_toml(text, source));
        PresetEditor editor(text, source);
        const std::vector<EditableValue> values = editor.values();
        EXPECT_GT(values.size(), 20u);
        for (const EditableValue& v : values) {
            SCOPED_TRACE(v.path + " = " + toml_value_text(v));
            EXPECT_EQ(preset_to_toml(editor.set(v.path, toml_value_text(v))), want);
        }
    }
}

TEST(PreviewEdit, SetReachesThePresetAndAccumulates) {
    PresetEditor editor(std::string(*builtin_preset_toml("plume")), "presets/plume.toml");
    EXPECT_EQ(editor.set("emitter[0].rate", "600.0").emitters.at(0).rate, 600.0);
    const Preset p = editor.set("lighting.sun", "[3.0, 0.5, 0.25]");
    EXPECT_EQ(p.emitters.at(0).rate, 600.0);  // the first edit stays
    EXPECT_EQ(p.scene.lighting.sun.z, 0.25);
    EXPECT_EQ(editor.set("lighting.sun[1]", "0.75").scene.lighting.sun.y, 0.75);
    bool found = false;
    for (const EditableValue& v : editor.values())
        if (v.path == "emitter[0].rate") found = v.kind == EditableValue::Kind::Number && v.numbers.at(0) == 600.0;
    EXPECT_TRUE(found);
}

TEST(PreviewEdit, RefusalsNameTheKeyAndAreNotKept) {
    PresetEditor editor(std::string(*builtin_preset_toml("plume")), "presets/plume.toml");
    EXPECT_NE(message_of(editor, "emitter[0].rate", "-5.0").find("emitter[0].rate: must not be negative"),
              std::string::npos);
    EXPECT_NE(message_of(editor, "emitter[9].rate", "1.0").find("emitter has 1 entries"), std::string::npos);
    EXPECT_NE(message_of(editor, "lighting.sun", "[1.0, 2.0").find("is not a TOML value"), std::string::npos);
    EXPECT_NE(message_of(editor, "emitter[x].rate", "1.0").find("is not NAME or NAME[INDEX]"), std::string::npos);
    EXPECT_NE(message_of(editor, "lighting.bogus", "1.0").find("lighting.bogus: unknown key"), std::string::npos);
    for (const EditableValue& v : editor.values())
        if (v.path == "emitter[0].rate") {
            EXPECT_EQ(v.numbers.at(0), 220.0);
        }
}

TEST(PreviewEdit, SavedTextChangesOnlyTheEditedValues) {
    const std::string text = "# a comment\n[lighting]\nsun = [1.0, 0.9, 0.8]  # warm\nambient = [0.2, 0.2, 0.2]\n";
    PresetEditor editor(text, "t.toml");
    EXPECT_FALSE(editor.edited());
    editor.set("lighting.sun", "[2.0, 1.0, 0.5]");
    editor.set("lighting.sun[1]", "0.75");  // inside the first edit: it changes that edit's text
    editor.set("lighting.ambient[0]", "0.125");
    EXPECT_EQ(editor.saved_text(),
              "# a comment\n[lighting]\nsun = [2.0, 0.75, 0.5]  # warm\nambient = [0.125, 0.2, 0.2]\n");
    // A key the file does not have is added to its table, after the table's values.
    editor.set("lighting.background", "[0.0, 0.0, 0.0]");
    EXPECT_EQ(editor.saved_text(), "# a comment\n[lighting]\nsun = [2.0, 0.75, 0.5]  # warm\nambient = [0.125, 0.2, 0.2]\n"
                                   "background = [0.0, 0.0, 0.0]\n");
}

// Keys a file leaves out (defaults): each goes into the table it belongs to, before that table's
// sub-tables and the comments of the next section; a missing table is added (after its [[array]]
// entry's values for a sub-table such as emitter[1].curves); every line of the file stays, in order;
// and the saved text reads back as the edited preset.
TEST(PreviewEdit, SaveAddsKeysTheFileLacksToTheirTables) {
    const std::string text =
        "# top\n[timeline]\nfps = 24.0  # frames\n\n# the first jet\n[[emitter]]\nshape = \"point\"\n"
        "center = [0.0, 0.0, 0.0]\nrate = 100.0\n\n[emitter.curves]\nfade_in = 0.1\n\n"
        "[[emitter]]\nshape = \"point\"\ncenter = [1.0, 0.0, 0.0]\n";
    PresetEditor editor(text, "t.toml");
    editor.set("timeline.seed", "7");
    editor.set("emitter[0].speed", "2.5");
    editor.set("emitter[1].curves.fade_out", "0.25");
    editor.set("emitter[1].curves.fade_in", "0.5");  // the same new table: one header
    editor.set("lighting.ambient", "[0.5, 0.5, 0.5]");
    const Preset want = editor.set("emitter[1].rate", "50.0");
    const std::string saved = editor.saved_text();
    EXPECT_EQ(saved,
              "# top\n[timeline]\nfps = 24.0  # frames\nseed = 7\n\n# the first jet\n[[emitter]]\nshape = \"point\"\n"
              "center = [0.0, 0.0, 0.0]\nrate = 100.0\nspeed = 2.5\n\n[emitter.curves]\nfade_in = 0.1\n\n"
              "[[emitter]]\nshape = \"point\"\ncenter = [1.0, 0.0, 0.0]\nrate = 50.0\n"
              "\n[emitter.curves]\nfade_out = 0.25\nfade_in = 0.5\n"
              "\n[lighting]\nambient = [0.5, 0.5, 0.5]\n")
        << saved;
    EXPECT_EQ(preset_to_toml(parse_preset_toml(saved, "t.toml")), preset_to_toml(want));
}

TEST(PreviewEdit, SaveAddsAMissingKeyToEveryShippedPreset) {
    // A [timeline] key each file leaves out (a default): the file gains exactly that line, in its
    // [timeline] table, and reads back as the edited preset.
    const std::vector<std::pair<std::string, std::string>> candidates = {
        {"seed", "99"}, {"preroll", "0.25"}, {"max_particles", "12345"}, {"substeps", "3"}};
    int checked = 0;
    for (const std::string& name : builtin_preset_names()) {
        SCOPED_TRACE(name);
        const std::string text(*builtin_preset_toml(name));
        const std::size_t table = text.find("\n[timeline]\n");
        if (table == std::string::npos) continue;
        const std::size_t table_end = text.find("\n[", table + 1);
        const std::string section = text.substr(table, table_end - table);
        for (const auto& [key, value] : candidates) {
            if (section.find("\n" + key + " =") != std::string::npos) continue;
            SCOPED_TRACE(key);
            PresetEditor editor(text, "presets/" + name + ".toml");
            const Preset want = editor.set("timeline." + key, value);
            const std::string saved = editor.saved_text();
            const std::string line = key + " = " + value + "\n";
            EXPECT_EQ(saved.size(), text.size() + line.size());
            const std::size_t at = saved.find("\n" + line) + 1;
            ASSERT_NE(at, std::string::npos + 1);
            EXPECT_EQ(saved.substr(0, at) + saved.substr(at + line.size()), text);  // every other byte as it was
            EXPECT_GT(at, table);
            EXPECT_LE(at, table_end);  // inside [timeline], before the line break that ends it
            EXPECT_EQ(preset_to_toml(parse_preset_toml(saved, "presets/" + name + ".toml")), preset_to_toml(want));
            ++checked;
            break;
        }
    }
    EXPECT_GE(checked, 3);
}

// An edit the view could not show (its preparation failed, as a [[vdb]] tolerance the grid cannot meet
// fails on the worker) is dropped again with any edit after it: Save writes what the view shows, and
// the panel reads the values shown.
TEST(PreviewEdit, AnEditTheViewRefusedIsDroppedAgain) {
    PresetEditor editor(std::string(*builtin_preset_toml("plume")), "plume.toml");
    editor.set("lighting.sun", "[2.0, 2.0, 2.0]");
    editor.keep_shown();
    const std::string shown = editor.saved_text();
    editor.set("emitter[0].rate", "600.0");
    editor.set("lighting.sun", "[0.5, 0.5, 0.5]");
    EXPECT_NE(editor.saved_text(), shown);
    editor.return_to_shown();
    EXPECT_EQ(editor.saved_text(), shown);
    EXPECT_TRUE(editor.edited());
    for (const EditableValue& v : editor.values()) {
        if (v.path == "emitter[0].rate") {
            EXPECT_EQ(v.numbers, std::vector<double>{220.0});
        }
    }
}

std::string file_text(const std::filesystem::path& p) {
    std::ifstream in(p, std::ios::binary);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

// Save into the file the editor read refuses when that file changed on disk since (an edit whose
// reload the preview refused): the old text plus the preview's edits would overwrite it. The text as
// read, or as this editor last saved it, is no change; another file is written as asked.
TEST(PreviewEdit, SaveRefusesToOverwriteAChangeOnDisk) {
    const std::filesystem::path dir = std::filesystem::path(::testing::TempDir()) / "brume_preview_save";
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const std::filesystem::path file = dir / "mine.toml", other = dir / "other.toml";
    const std::string text(*builtin_preset_toml("plume"));
    std::ofstream(file, std::ios::binary) << text;
    PresetEditor editor(text, file.string());
    editor.set("emitter[0].rate", "600.0");
    editor.save(file);
    EXPECT_EQ(file_text(file), editor.saved_text());
    editor.set("emitter[0].rate", "700.0");
    editor.save(file);  // the disk holds what this editor saved: no change of the user's
    EXPECT_EQ(file_text(file), editor.saved_text());
    std::ofstream(file, std::ios::binary | std::ios::app) << "# my work in progress\n";
    const std::string theirs = file_text(file);
    try {
        editor.save(file);
        ADD_FAILURE() << "saved over a change on disk";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("changed on disk since the preview read it"), std::string::npos) << e.what();
    }
    EXPECT_EQ(file_text(file), theirs);
    editor.save(other);
    EXPECT_EQ(file_text(other), editor.saved_text());
    std::filesystem::remove_all(dir);
}

TEST(PreviewEdit, WhichEditsTheSimulationReads) {
    for (const char* key : {"emitter[0].rate", "force[1].strength", "box[0].min", "timeline.fps", "timeline.seed",
                            "timeline.max_particles", "timeline.substeps"})
        EXPECT_TRUE(edit_affects_simulation(key)) << key;
    for (const char* key : {"lighting.sun", "lighting.sun[1]", "camera.fov_deg", "camera_path.radius", "render.min_transmittance",
                            "render_settings.exposure", "sphere[0].radius", "timeline.duration", "preset.name"})
        EXPECT_FALSE(edit_affects_simulation(key)) << key;
}

}  // namespace
}  // namespace brume::app
