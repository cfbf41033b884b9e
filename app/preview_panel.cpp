#include "app/preview_panel.h"

#include "app/preview_heat_map.h"
#include "render/methods/registry.h"

#include <imgui.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <vector>

namespace brume::app {
namespace {

std::vector<const MethodEntry*> gpu_methods() {
    std::vector<const MethodEntry*> out;
    for (const MethodEntry& m : method_catalogue())
        if (m.needs_device) out.push_back(&m);
    return out;
}

void timeline_section(PanelState& s) {
    PreviewSession& session = s.session;
    PreviewTimeline& timeline = session.timeline();
    Playback& playback = session.playback();
    const int last = timeline.frame_count() - 1;
    if (ImGui::Button(playback.playing ? "Pause" : "Play")) playback.playing = !playback.playing;
    ImGui::SameLine();
    if (ImGui::Button("<")) {
        playback.playing = false;
        timeline.seek(timeline.frame() - 1);
    }
    ImGui::SameLine();
    if (ImGui::Button(">")) {
        playback.playing = false;
        timeline.seek(timeline.frame() + 1);
    }
    ImGui::SameLine();
    ImGui::Checkbox("loop", &playback.loop);
    ImGui::SameLine();
    float speed = float(playback.speed);
    ImGui::SetNextItemWidth(110);
    if (ImGui::SliderFloat("speed", &speed, 0.1f, 4.0f, "%.2fx")) playback.speed = speed;

    int frame = timeline.frame();
    ImGui::SetNextItemWidth(-1);
    if (ImGui::SliderInt("##frame", &frame, 0, last, "frame %d")) timeline.seek(frame);
    ImGui::Text("frame %d (0-%d), t = %.3f s at %.4g fps", timeline.frame(), last, timeline.time(), timeline.fps());
    // The cached range: frames simulated so far, each at most a few steps from a checkpoint.
    const float simulated = float(timeline.simulated_until() + 1) / float(timeline.frame_count());
    char label[96];
    std::snprintf(label, sizeof label, "simulated 0-%d, %zu checkpoints", timeline.simulated_until(),
                  timeline.checkpoints().size());
    ImGui::ProgressBar(simulated, ImVec2(-1, 0), label);
    ImGui::Text("%zu particles", timeline.particles());
}

void camera_section(PanelState& s) {
    PreviewSession& session = s.session;
    bool follow = session.following_path();
    if (ImGui::Checkbox("follow the camera path", &follow)) session.set_following_path(follow);
    ImGui::SameLine();
    if (ImGui::Button("reset camera")) session.reset_camera();
    float exposure = float(session.exposure());
    if (ImGui::SliderFloat("exposure", &exposure, -4.0f, 4.0f, "%.2f stops")) session.set_exposure(exposure);
    const Camera c = session.camera();
    ImGui::Text("eye (%.2f, %.2f, %.2f)  at (%.2f, %.2f, %.2f)", c.position.x, c.position.y, c.position.z, c.look_at.x,
                c.look_at.y, c.look_at.z);
    ImGui::TextDisabled("drag: orbit; right drag: pan; wheel: zoom");
}

void method_section(PanelState& s) {
    const std::vector<const MethodEntry*> methods = gpu_methods();
    s.method_index = std::clamp(s.method_index, 0, int(methods.size()) - 1);
    const MethodEntry& chosen = *methods[std::size_t(s.method_index)];
    ImGui::SetNextItemWidth(140);
    if (ImGui::BeginCombo("method", chosen.name.c_str())) {
        for (std::size_t i = 0; i < methods.size(); ++i) {
            if (ImGui::Selectable(methods[i]->name.c_str(), int(i) == s.method_index)) {
                s.method_index = int(i);
                std::snprintf(s.method_setting, sizeof s.method_setting, "%s", methods[i]->default_setting.c_str());
            }
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", methods[i]->summary.c_str());
        }
        ImGui::EndCombo();
    }
    const MethodEntry& entry = *methods[std::size_t(s.method_index)];
    if (!entry.setting.empty()) {
        ImGui::SameLine();
        ImGui::SetNextItemWidth(90);
        ImGui::InputText(entry.setting.c_str(), s.method_setting, sizeof s.method_setting);
    }
    ImGui::SameLine();
    if (ImGui::Button("apply")) {
        // Appended, not ":" + std::string(...): GCC 12 warns (-Wrestrict, a false positive) on
        // operator+(const char*, std::string&&) inlined here.
        std::string spec = entry.name;
        if (!entry.setting.empty() && s.method_setting[0]) spec.append(":").append(s.method_setting);
        try {
            s.session.set_method(spec);
            s.method_error.clear();
        } catch (const std::exception& e) {
            s.method_error = e.what();
        }
    }
    ImGui::Text("showing %s (%s)", s.session.method_spec().c_str(),
                find_method(s.session.method_spec()).exact ? "exact" : "approximate");
    // A second method: beside the first (split) or against it (difference, x8).
    // The view as the session has it (a script may have changed it).
    s.compare_mode = int(s.session.compare_mode());
    for (std::size_t i = 0; i < methods.size(); ++i)
        if (!s.session.compare_spec().empty() && methods[i]->name == find_method(s.session.compare_spec()).name)
            s.compare_index = int(i);
    s.compare_index = std::clamp(s.compare_index, 0, int(methods.size()) - 1);
    bool compare_changed = false;
    ImGui::SetNextItemWidth(140);
    if (ImGui::BeginCombo("versus", methods[std::size_t(s.compare_index)]->name.c_str())) {
        for (std::size_t i = 0; i < methods.size(); ++i)
            if (ImGui::Selectable(methods[i]->name.c_str(), int(i) == s.compare_index)) {
                s.compare_index = int(i);
                compare_changed = true;
            }
        ImGui::EndCombo();
    }
    compare_changed |= ImGui::RadioButton("one", &s.compare_mode, 0);
    ImGui::SameLine();
    compare_changed |= ImGui::RadioButton("split", &s.compare_mode, 1);
    ImGui::SameLine();
    compare_changed |= ImGui::RadioButton("difference x8", &s.compare_mode, 2);
    if (compare_changed) {
        try {
            s.session.set_comparison(methods[std::size_t(s.compare_index)]->name,
                                     s.compare_mode == 0   ? CompareMode::Off
                                     : s.compare_mode == 1 ? CompareMode::Split
                                                           : CompareMode::Difference);
            s.method_error.clear();
        } catch (const std::exception& e) {
            s.method_error = e.what();
        }
    }
    if (!s.method_error.empty()) ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.3f, 1.0f), "%s", s.method_error.c_str());
    // Depth complexity over the view: a pass of its own and a readback, so off unless asked.
    bool heat = s.session.heat_map();
    if (ImGui::Checkbox("heat map of list length", &heat)) s.session.set_heat_map(heat);
    if (heat) {
        const ListLengthFigures& f = s.session.heat_figures();
        const std::array<float, 3> lo = heat_colour(0.0), hi = heat_colour(1.0);
        ImGui::TextColored(ImVec4(lo[0], lo[1], lo[2], 1.0f), "1");
        ImGui::SameLine(0, 4);
        ImGui::Text("to");
        ImGui::SameLine(0, 4);
        ImGui::TextColored(ImVec4(hi[0], hi[1], hi[2], 1.0f), "%.0f", std::max(1.0, f.longest));
        ImGui::SameLine();
        ImGui::Text("nodes; mean %.1f over %llu pixels", f.mean, static_cast<unsigned long long>(f.nonempty_pixels));
    }
    if (!s.reference) return;
    if (s.reference->running()) {
        // Its exact shadows take seconds at the reduced size (vdb-cloud at 320x180: 9 s on two cores).
        char label[64];
        std::snprintf(label, sizeof label, "reference on a worker thread: %.0f%%", 100.0 * s.reference->share_done());
        ImGui::ProgressBar(float(s.reference->share_done()), ImVec2(-1, 0), label);
    } else if (ImGui::Button("error against the reference") && s.start_reference) {
        s.start_reference();
    }
    if (const auto& r = s.reference->last())
        ImGui::TextWrapped("frame %d, %s at %dx%d (reduced): max %.3g of peak, rmse %.3g, PSNR %.1f dB; reference %.2f s",
                           r->frame, r->method.c_str(), r->width, r->height, r->max_of_peak, r->rmse_of_peak,
                           r->psnr_db, r->seconds);
    if (!s.reference->error().empty())
        ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.3f, 1.0f), "%s", s.reference->error().c_str());
}

void figures_section(PanelState& s) {
    const PartTimes& t = s.times;
    ImGui::Text("%.1f FPS, %.1f ms a frame", t.frame > 0 ? 1000.0 / t.frame : 0.0, t.frame);
    ImGui::Text("simulate %.1f  upload %.1f  render %.1f  ui %.1f  present %.1f ms", t.simulate, t.upload, t.render,
                t.ui, t.present);
    bool adaptive = s.adaptive.enabled();
    if (ImGui::Checkbox("adaptive resolution", &adaptive)) s.adaptive.set_enabled(adaptive);
    ImGui::SameLine();
    float target = float(s.adaptive.target_fps());
    ImGui::SetNextItemWidth(80);
    if (ImGui::InputFloat("target FPS", &target, 0, 0, "%.0f")) s.adaptive.set_target_fps(target);
    ImGui::Text("internal %ux%u of %ux%u", s.internal.width, s.internal.height, s.viewport.width, s.viewport.height);
    const FrameStats& st = s.session.last_stats();
    ImGui::Text("GPU %.2f ms", st.total_ms);
    for (const PassTime& p : st.passes) ImGui::BulletText("%s %.2f ms", p.name.c_str(), p.ms);
    ImGui::Text("fragments %llu, method memory %.1f MiB", static_cast<unsigned long long>(st.fragments),
                double(st.memory_bytes) / (1 << 20));
    if (st.pool_capacity)
        ImGui::Text("pool %llu nodes (%.1f MiB), regrows %d", static_cast<unsigned long long>(st.pool_capacity),
                    double(st.pool_bytes) / (1 << 20), st.regrows);
    ImGui::Checkbox("list lengths (extra atomics)", &s.list_stats);
    if (st.list_stats)
        ImGui::Text("longest list %u, mean %.2f over %llu pixels", st.max_list_length, st.mean_list_length,
                    static_cast<unsigned long long>(st.nonempty_pixels));
}

// Render sequence: brume play of a range of frames with the view's options, in the background.
void sequence_section(PanelState& s) {
    if (!s.sequence) return;
    const PreviewTimeline& timeline = s.session.timeline();
    const int last = timeline.frame_count() - 1;
    if (!s.sequence_dir[0]) std::snprintf(s.sequence_dir, sizeof s.sequence_dir, "%s", timeline.preset().name.c_str());
    if (s.sequence_last < 0 || s.sequence_last > last) s.sequence_last = last;
    ImGui::SetNextItemWidth(-60);
    ImGui::InputText("folder", s.sequence_dir, sizeof s.sequence_dir);
    ImGui::SetNextItemWidth(80);
    ImGui::InputInt("first", &s.sequence_first, 0);
    ImGui::SameLine();
    ImGui::SetNextItemWidth(80);
    ImGui::InputInt("last", &s.sequence_last, 0);
    s.sequence_first = std::clamp(s.sequence_first, 0, last);
    s.sequence_last = std::clamp(s.sequence_last, s.sequence_first, last);
    ImGui::Checkbox("png", &s.sequence_png);
    ImGui::SameLine();
    ImGui::Checkbox("exr", &s.sequence_exr);
    const SequenceRender& q = *s.sequence;
    if (q.running()) {
        char label[64];
        std::snprintf(label, sizeof label, "%d/%d frames", q.frames_done(), q.frames_total());
        ImGui::ProgressBar(q.frames_total() ? float(q.frames_done()) / float(q.frames_total()) : 0.0f, ImVec2(-1, 0), label);
    } else {
        ImGui::SameLine();
        if (ImGui::Button("render sequence") && (s.sequence_png || s.sequence_exr)) {
            const std::string formats = std::string(s.sequence_png ? "png" : "") +
                                        (s.sequence_png && s.sequence_exr ? "," : "") + (s.sequence_exr ? "exr" : "");
            s.sequence_error = s.start_sequence(s.sequence_dir, s.sequence_first, s.sequence_last, formats);
        }
        if (q.status() >= 0)
            ImGui::TextWrapped("%s: %s", q.status() == 0 ? "done" : "failed", q.last_line().c_str());
    }
    ImGui::TextDisabled("brume play at the viewport's size, method and exposure; the preset's camera path");
    if (!s.sequence_error.empty()) ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.3f, 1.0f), "%s", s.sequence_error.c_str());
}

}  // namespace

void draw_panel(PanelState& s) {
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowSize(ImVec2(340, 0), ImGuiCond_FirstUseEver);
    ImGui::SetNextWindowBgAlpha(0.8f);
    if (!ImGui::Begin(("Brume: " + s.session.timeline().preset().name).c_str())) {
        ImGui::End();
        return;
    }
    if (!s.view_error.empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.3f, 1.0f), "%s", s.view_error.c_str());
        ImGui::PopTextWrapPos();
        ImGui::TextDisabled("showing the last frame rendered");
    }
    if (!s.reload_error.empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.3f, 1.0f), "%s", s.reload_error.c_str());
        ImGui::PopTextWrapPos();
        ImGui::TextDisabled("playing the last good version; fix the file to reload");
    } else if (!s.watched_file.empty()) {
        ImGui::TextDisabled("watching %s", s.watched_file.c_str());
    }
    if (ImGui::CollapsingHeader("Timeline", ImGuiTreeNodeFlags_DefaultOpen)) timeline_section(s);
    if (ImGui::CollapsingHeader("Camera")) camera_section(s);
    if (ImGui::CollapsingHeader("Preset")) draw_preset_editor(s.preset_edit);
    if (ImGui::CollapsingHeader("Method", ImGuiTreeNodeFlags_DefaultOpen)) method_section(s);
    if (ImGui::CollapsingHeader("Figures", ImGuiTreeNodeFlags_DefaultOpen)) figures_section(s);
    if (ImGui::CollapsingHeader("Render sequence")) sequence_section(s);
    ImGui::End();
}

}  // namespace brume::app
