// `brume preview --script FILE`: one command per line, for tests and pipelines. Blank lines and
// lines starting with '#' are skipped. Commands:
//   frame N            show frame N (0-based)
//   play | pause       start or stop playback (scripted playback advances one frame per shown frame)
//   wait N             let N frames be shown before the next command
//   wait-reload        wait (up to 30 s) until the watched file changed and was read or refused
//   set KEY.PATH VALUE edit a preset value, as in the file (app/preview_edit.h)
//   save PATH          write the edited preset, comments and layout kept (.toml)
//   orbit DEG_X DEG_Y  orbit the camera (app/preview_camera.h); stops following the camera path
//   method SPEC        switch the method (as --method takes it)
//   compare SPEC split|difference, compare off   a second method beside or against the first
//   resize W H         resize the window (the swapchain is recreated)
//   screenshot PATH    save the viewport without the panel: .png (exposed sRGB) or .exr (linear)
//   capture PATH       save the window as it is shown, panel included (.png)
//   panel on|off       show or hide the panel
//   heat-map on|off    the heat map of list length over the view (app/preview_heat_map.h)
//   render-sequence DIR A-B   brume play of frames A-B into DIR, in the background (app/preview_sequence.h);
//                      the script waits until it is done
//   reference-error    compare the frame with the CPU reference (reduced size) and print the error
//   camera             print the camera's position and look_at on stdout
//   quit               close the preview
// A malformed line is refused before the window opens, as "FILE:LINE: what is wrong".
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace brume::app {

class ScriptError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct ScriptCommand {
    enum class Kind { Frame, Play, Pause, Wait, WaitReload, Set, Save, Orbit, Method, Resize, Compare, Screenshot, Capture, Panel, HeatMap, RenderSequence, ReferenceError, Camera, Quit };
    Kind kind = Kind::Quit;
    long long number = 0;      // frame, wait, resize width; panel, heat-map: 1 on, 0 off; compare: 0 off, 1 split, 2 difference
    long long number2 = 0;     // resize height; render-sequence: the first and last frame in number, number2
    double x = 0.0, y = 0.0;   // orbit degrees
    std::string text;          // method spec, screenshot or capture path, set's key path, render-sequence's folder
    std::string value;         // set's value (the rest of the line)
    std::string where;         // "FILE:LINE", for errors found when the command runs
};

// Parses `text` (the file's contents); `file` names it in errors. Throws ScriptError.
std::vector<ScriptCommand> parse_script(const std::string& text, const std::string& file);
// Reads and parses FILE. Throws ScriptError (an unreadable file too).
std::vector<ScriptCommand> load_script(const std::string& file);

}  // namespace brume::app
