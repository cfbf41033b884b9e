// The preview's live edits (app/preview_edit.*): every value of every shipped preset, written back
// as the panel writes it, reads back to the same preset; a set reaches the preset; bad paths, bad
// values and values the reader refuses are named, and a refused edit is not kept.
#include "app/preview_edit.h"

#include "sim/builtin_presets.h"
#include "sim/preset_file.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

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
        if (v.path == "emitter[0].rate") EXPECT_EQ(v.numbers.at(0), 220.0);
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
    // A key the file does not have cannot be written in place.
    editor.set("lighting.background", "[0.0, 0.0, 0.0]");
    try {
        (void)editor.saved_text();
        ADD_FAILURE() << "saved a key that is not in the file";
    } catch (const std::invalid_argument& e) {
        EXPECT_NE(std::string(e.what()).find("lighting.background is not in t.toml"), std::string::npos);
    }
}

}  // namespace
}  // namespace brume::app
