#include "app/preview_script.h"

#include "app/cli_util.h"
#include "sim/scene_file.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

namespace brume::app {
namespace {

std::vector<std::string> words_of(const std::string& line) {
    std::istringstream in(line);
    std::vector<std::string> words;
    for (std::string w; in >> w;) words.push_back(w);
    return words;
}

long long whole(const std::string& word, const std::string& what, long long min, const std::string& where) {
    const std::optional<long long> n = parse_whole_number(word);
    if (!n) throw ScriptError(where + ": " + what + " must be a whole number, got '" + word + "'");
    if (*n < min) throw ScriptError(where + ": " + what + " must be at least " + std::to_string(min) + ", got " + word);
    return *n;
}

double degrees(const std::string& word, const std::string& what, const std::string& where) {
    double v = 0.0;
    const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), v);
    if (ec != std::errc() || end != word.data() + word.size() || !std::isfinite(v))
        throw ScriptError(where + ": " + what + " must be a number of degrees, got '" + word + "'");
    return v;
}

}  // namespace

std::vector<ScriptCommand> parse_script(const std::string& text, const std::string& file) {
    std::vector<ScriptCommand> commands;
    std::istringstream in(text);
    int line_number = 0;
    for (std::string line; std::getline(in, line);) {
        ++line_number;
        const std::vector<std::string> w = words_of(line);
        if (w.empty() || w[0][0] == '#') continue;
        ScriptCommand c;
        c.where = file + ":" + std::to_string(line_number);
        const std::string& name = w[0];
        auto expect = [&](std::size_t args, const char* usage) {
            if (w.size() != args + 1)
                throw ScriptError(c.where + ": '" + name + "' takes " + std::to_string(args) + " argument" +
                                  (args == 1 ? "" : "s") + ": " + usage);
        };
        if (name == "frame") {
            expect(1, "frame N");
            c.kind = ScriptCommand::Kind::Frame;
            c.number = whole(w[1], "the frame", 0, c.where);
        } else if (name == "reference-error") {
            expect(0, "reference-error");
            c.kind = ScriptCommand::Kind::ReferenceError;
        } else if (name == "play" || name == "pause" || name == "quit" || name == "camera") {
            expect(0, name.c_str());
            c.kind = name == "play"    ? ScriptCommand::Kind::Play
                     : name == "pause" ? ScriptCommand::Kind::Pause
                     : name == "quit"  ? ScriptCommand::Kind::Quit
                                       : ScriptCommand::Kind::Camera;
        } else if (name == "wait") {
            expect(1, "wait N (frames)");
            c.kind = ScriptCommand::Kind::Wait;
            c.number = whole(w[1], "the number of frames", 1, c.where);
        } else if (name == "wait-reload") {
            expect(0, "wait-reload");
            c.kind = ScriptCommand::Kind::WaitReload;
        } else if (name == "set") {
            if (w.size() < 3) throw ScriptError(c.where + ": 'set' takes KEY.PATH VALUE, e.g. set emitter[0].rate 400");
            c.kind = ScriptCommand::Kind::Set;
            c.text = w[1];
            // The value is the rest of the line: arrays and strings may hold spaces.
            const std::size_t key_at = line.find(w[1], line.find("set") + 3);
            c.value = line.substr(key_at + w[1].size());
            c.value.erase(0, c.value.find_first_not_of(" \t"));
            c.value.erase(c.value.find_last_not_of(" \t\r") + 1);
        } else if (name == "save") {
            expect(1, "save PATH (.toml)");
            c.kind = ScriptCommand::Kind::Save;
            c.text = w[1];
            if (!c.text.ends_with(".toml")) throw ScriptError(c.where + ": save '" + c.text + "': the name must end in .toml");
        } else if (name == "orbit") {
            expect(2, "orbit DEG_X DEG_Y");
            c.kind = ScriptCommand::Kind::Orbit;
            c.x = degrees(w[1], "DEG_X", c.where);
            c.y = degrees(w[2], "DEG_Y", c.where);
        } else if (name == "method") {
            expect(1, "method SPEC (see brume methods)");
            c.kind = ScriptCommand::Kind::Method;
            c.text = w[1];
        } else if (name == "compare") {
            if (w.size() == 2 && w[1] == "off") {
                c.kind = ScriptCommand::Kind::Compare;
                c.number = 0;
            } else {
                expect(2, "compare SPEC split|difference, or compare off");
                c.kind = ScriptCommand::Kind::Compare;
                c.text = w[1];
                if (w[2] != "split" && w[2] != "difference")
                    throw ScriptError(c.where + ": compare: the view is split or difference, got '" + w[2] + "'");
                c.number = w[2] == "split" ? 1 : 2;
            }
        } else if (name == "resize") {
            expect(2, "resize W H");
            c.kind = ScriptCommand::Kind::Resize;
            c.number = whole(w[1], "the width", 16, c.where);
            c.number2 = whole(w[2], "the height", 16, c.where);
            if (c.number > 8192 || c.number2 > 8192) throw ScriptError(c.where + ": resize: at most 8192x8192");
        } else if (name == "screenshot") {
            expect(1, "screenshot PATH (.png or .exr)");
            c.kind = ScriptCommand::Kind::Screenshot;
            c.text = w[1];
            const std::string ext = c.text.size() >= 4 ? c.text.substr(c.text.size() - 4) : "";
            if (ext != ".png" && ext != ".exr")
                throw ScriptError(c.where + ": screenshot '" + c.text + "': the name must end in .png or .exr");
        } else if (name == "capture") {
            expect(1, "capture PATH (.png)");
            c.kind = ScriptCommand::Kind::Capture;
            c.text = w[1];
            if (!c.text.ends_with(".png"))
                throw ScriptError(c.where + ": capture '" + c.text + "': the name must end in .png");
        } else if (name == "panel") {
            expect(1, "panel on|off");
            c.kind = ScriptCommand::Kind::Panel;
            if (w[1] != "on" && w[1] != "off") throw ScriptError(c.where + ": panel takes on or off, got '" + w[1] + "'");
            c.number = w[1] == "on";
        } else if (name == "render-sequence") {
            expect(2, "render-sequence DIR A-B (frames, 0-based, inclusive)");
            c.kind = ScriptCommand::Kind::RenderSequence;
            c.text = w[1];
            const std::size_t dash = w[2].find('-', 1);
            if (dash == std::string::npos)
                throw ScriptError(c.where + ": render-sequence: the frames are A-B, got '" + w[2] + "'");
            c.number = whole(w[2].substr(0, dash), "the first frame", 0, c.where);
            c.number2 = whole(w[2].substr(dash + 1), "the last frame", 0, c.where);
            if (c.number2 < c.number) throw ScriptError(c.where + ": render-sequence: " + w[2] + " is a reversed range");
        } else if (name == "heat-map") {
            expect(1, "heat-map on|off");
            c.kind = ScriptCommand::Kind::HeatMap;
            if (w[1] != "on" && w[1] != "off") throw ScriptError(c.where + ": heat-map takes on or off, got '" + w[1] + "'");
            c.number = w[1] == "on";
        } else {
            throw ScriptError(c.where + ": unknown command '" + name +
                              "'; known: frame, play, pause, wait, wait-reload, set, save, orbit, method, compare, resize, screenshot, capture, panel, heat-map, render-sequence, "
                              "reference-error, camera, quit");
        }
        commands.push_back(std::move(c));
    }
    return commands;
}

std::vector<ScriptCommand> load_script(const std::string& file) {
    std::string text;
    try {
        text = toml_text::read_file(file);  // a folder or a device is refused by name (an ifstream opens a folder)
    } catch (const SceneFileError& e) {
        throw ScriptError("the script " + file + ": " + e.problem());
    }
    // An editor's UTF-8 byte-order mark would make the first command unknown, invisibly.
    if (text.starts_with("\xEF\xBB\xBF")) text.erase(0, 3);
    return parse_script(text, file);
}

}  // namespace brume::app
