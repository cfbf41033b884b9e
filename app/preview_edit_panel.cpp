#include "app/preview_edit_panel.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace brume::app {
namespace {

// The widget for one value; true when the user changed it this frame.
bool edit_value(EditableValue& v, const char* label) {
    switch (v.kind) {
    case EditableValue::Kind::Number: {
        const double speed = std::max(1e-3, std::abs(v.numbers[0]) * 0.01);
        return ImGui::DragScalar(label, ImGuiDataType_Double, v.numbers.data(), float(speed), nullptr, nullptr, "%.4g");
    }
    case EditableValue::Kind::Integer: {
        long long n = std::llround(v.numbers[0]);
        const bool changed = ImGui::InputScalar(label, ImGuiDataType_S64, &n, nullptr, nullptr, "%lld",
                                                ImGuiInputTextFlags_EnterReturnsTrue);
        v.numbers[0] = double(n);
        return changed;
    }
    case EditableValue::Kind::Bool: return ImGui::Checkbox(label, &v.flag);
    case EditableValue::Kind::String: {
        char buf[256];
        std::snprintf(buf, sizeof buf, "%s", v.text.c_str());
        if (!ImGui::InputText(label, buf, sizeof buf, ImGuiInputTextFlags_EnterReturnsTrue)) return false;
        v.text = buf;
        return true;
    }
    case EditableValue::Kind::Numbers: {
        if (v.integers) {
            long long n[4];
            for (std::size_t i = 0; i < v.numbers.size(); ++i) n[i] = std::llround(v.numbers[i]);
            if (!ImGui::InputScalarN(label, ImGuiDataType_S64, n, int(v.numbers.size()), nullptr, nullptr, "%lld",
                                     ImGuiInputTextFlags_EnterReturnsTrue))
                return false;
            for (std::size_t i = 0; i < v.numbers.size(); ++i) v.numbers[i] = double(n[i]);
            return true;
        }
        double largest = 0.0;
        for (double x : v.numbers) largest = std::max(largest, std::abs(x));
        return ImGui::DragScalarN(label, ImGuiDataType_Double, v.numbers.data(), int(v.numbers.size()),
                                  float(std::max(1e-3, largest * 0.01)), nullptr, nullptr, "%.3g");
    }
    }
    return false;
}

}  // namespace

void draw_preset_editor(PresetEditPanel& panel) {
    if (panel.stale && panel.read) {
        panel.values = panel.read();
        panel.stale = false;
    }
    if (panel.preparing && panel.preparing())
        ImGui::TextDisabled("preparing the edit on a worker (converting density grids)...");
    if (!panel.error.empty()) {
        ImGui::PushTextWrapPos(0.0f);
        ImGui::TextColored(ImVec4(1.0f, 0.4f, 0.3f, 1.0f), "%s", panel.error.c_str());
        ImGui::PopTextWrapPos();
    }
    if (panel.save && ImGui::Button(("Save " + panel.save_path).c_str())) {
        panel.error = panel.save();
        panel.saved = panel.error.empty() ? "saved " + panel.save_path : "";
    }
    if (!panel.saved.empty()) ImGui::TextDisabled("%s", panel.saved.c_str());
    std::string open_section;
    bool open = false;
    for (EditableValue& v : panel.values) {
        const std::size_t cut = v.path.find_first_of(".[");
        const std::string section = v.path.substr(0, cut);
        if (section != open_section) {
            if (open) ImGui::TreePop();
            open_section = section;
            open = ImGui::TreeNode(section.c_str());
        }
        if (!open) continue;
        const std::string label = cut == std::string::npos ? v.path : v.path.substr(cut + (v.path[cut] == '.'));
        ImGui::PushID(v.path.c_str());
        ImGui::SetNextItemWidth(150);
        if (edit_value(v, label.c_str()) && panel.set) {
            panel.error = panel.set(v.path, toml_value_text(v));
            // An accepted edit can change other values' meaning (a shape): read them all again.
            // A refused one is put back as the preset has it.
            panel.stale = true;
        }
        ImGui::PopID();
    }
    if (open) ImGui::TreePop();
}

}  // namespace brume::app
