// The editor's panels and keyboard shortcuts. Every control runs a command of the
// editor's table (docs/commands.md); keys go to the editor's key table, and the
// help window lists it with the shell's own keys (kShellShortcuts).

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <GLFW/glfw3.h>
#include <imgui.h>

#include "desktop/app.h"

namespace vfsd::desktop {
namespace {

// The shell's own keys and pointer gestures; the editor's keys are its table's
// (editor::key_bindings()).
struct Shortcut {
    const char* keys;
    const char* what;
};

constexpr Shortcut kShellShortcuts[] = {
    {"F1", "this help"},
    {"Tab", "hide / show the panels"},
    {"left drag", "tool, or orbit"},
    {"right / middle / Shift+left drag", "pan"},
    {"wheel", "zoom toward the cursor"},
};

// The key that chooses `tool`, as the key table names it.
std::string shortcut_for(editor::Tool tool) {
    for (const editor::KeyBinding& k : editor::key_bindings())
        if (k.command == std::string("tool") && nlohmann::json::parse(k.args).value("name", "") == editor::tool_name(tool))
            return k.key;
    return "";
}

// The keys the table binds, by GLFW key code and the name key_name() gives them.
std::vector<std::pair<int, std::string>> glfw_keys() {
    std::vector<std::pair<int, std::string>> keys = {{GLFW_KEY_LEFT_BRACKET, "["}, {GLFW_KEY_RIGHT_BRACKET, "]"},
                                                     {GLFW_KEY_SPACE, "space"},       {GLFW_KEY_ENTER, "enter"}};
    for (int k = 0; k < 26; ++k) keys.push_back({GLFW_KEY_A + k, std::string(1, char('a' + k))});
    for (int k = 0; k < 10; ++k) keys.push_back({GLFW_KEY_0 + k, std::string(1, char('0' + k))});
    return keys;
}

void tooltip(const char* text) {
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", text);
}

// ImGui 1.86's GLFW backend indexes keys by GLFW key code.
bool pressed(int glfw_key) { return ImGui::IsKeyPressed(glfw_key, false); }

}  // namespace

void App::handle_shortcuts() {
    ImGuiIO& io = ImGui::GetIO();
    if (io.WantTextInput) return;
    if (pressed(GLFW_KEY_F1)) show_help_ = !show_help_;
    if (pressed(GLFW_KEY_TAB)) show_ui_ = !show_ui_;
    // Over a panel only Ctrl's keys (undo, redo) reach the editor.
    if (io.WantCaptureKeyboard && !io.KeyCtrl) return;
    static const std::vector<std::pair<int, std::string>> keys = glfw_keys();
    for (const auto& [code, name] : keys) {
        if (!pressed(code)) continue;
        try {
            editor_->key(name, io.KeyCtrl, io.KeyShift);
        } catch (const std::exception& e) {
            editor_->set_status(e.what());
        }
    }
}

// The side panel (file, tools, curve, options) scrolls when the window is short;
// the time bar (play, time, stats, warnings, status) is pinned to the bottom of
// the view, and a load error stands on the view until dismissed.
void App::draw_panels() {
    if (!show_ui_) return;
    constexpr float kMargin = 8.0f, kPanelWidth = 330.0f;
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    ImGui::SetNextWindowPos(ImVec2(kMargin, kMargin), ImGuiCond_Always);
    ImGui::SetNextWindowSizeConstraints(ImVec2(kPanelWidth, 0.0f),
                                        ImVec2(kPanelWidth, std::max(120.0f, display.y - 2.0f * kMargin)));
    ImGui::SetNextWindowBgAlpha(0.92f);
    ImGui::Begin("vfsd", nullptr,
                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_AlwaysAutoResize);
    if (ImGui::CollapsingHeader("File", ImGuiTreeNodeFlags_DefaultOpen)) draw_file_panel();
    if (ImGui::CollapsingHeader("Tools", ImGuiTreeNodeFlags_DefaultOpen)) draw_tools_panel();
    if (ImGui::CollapsingHeader("Curve", ImGuiTreeNodeFlags_DefaultOpen)) draw_curve_panel();
    if (ImGui::CollapsingHeader("Options", ImGuiTreeNodeFlags_DefaultOpen)) draw_options();
    ImGui::End();

    const float left = 2.0f * kMargin + kPanelWidth;
    ImGui::SetNextWindowPos(ImVec2(left, display.y - kMargin), ImGuiCond_Always, ImVec2(0.0f, 1.0f));
    ImGui::SetNextWindowSize(ImVec2(std::max(300.0f, display.x - left - kMargin), 0.0f), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.92f);
    ImGui::Begin("time", nullptr,
                 ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize |
                     ImGuiWindowFlags_NoCollapse | ImGuiWindowFlags_NoScrollbar);
    draw_time_bar();
    draw_stats_line();
    for (const std::string& w : editor_->session().warnings())
        ImGui::TextColored(ImVec4(0.75f, 0.35f, 0.0f, 1), "! %s", w.c_str());
    if (!editor_->status().empty()) ImGui::TextWrapped("%s", editor_->status().c_str());
    ImGui::End();
    draw_load_error();
    if (show_help_) draw_help();
}

void App::draw_load_error() {
    const std::string& error = editor_->load_error();
    if (error.empty()) return;
    const ImVec2 display = ImGui::GetIO().DisplaySize;
    ImGui::SetNextWindowPos(ImVec2(0.5f * display.x, 0.4f * display.y), ImGuiCond_Always, ImVec2(0.5f, 0.5f));
    ImGui::SetNextWindowSize(ImVec2(std::min(520.0f, display.x - 16.0f), 0.0f), ImGuiCond_Always);
    ImGui::Begin("Could not open the file", nullptr,
                 ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);
    ImGui::TextColored(ImVec4(0.8f, 0.1f, 0.1f, 1), "%s", "The session is kept as it was.");
    ImGui::TextWrapped("%s", error.c_str());
    if (ImGui::Button("Dismiss") || pressed(GLFW_KEY_ESCAPE)) editor_->dismiss_load_error();
    tooltip("Esc");
    ImGui::End();
}

void App::draw_file_panel() {
    const editor::EditorSession& s = editor_->session();
    ImGui::TextDisabled("%s", s.mesh_name().c_str());
    ImGui::SetNextItemWidth(230);
    const bool enter = ImGui::InputTextWithHint("##path", "mesh, scene .json or builtin:bar", path_field_,
                                                sizeof path_field_, ImGuiInputTextFlags_EnterReturnsTrue);
    ImGui::SameLine();
    if (ImGui::Button("Open") || enter) open(path_field_);
    tooltip("Open a mesh (.obj .off .ply .stl .gltf .glb, builtin:NAME) or a scene (.json).\n"
            "Files can also be dropped onto the window.");
    if (!recent_.empty()) {
        ImGui::SetNextItemWidth(230);
        if (ImGui::BeginCombo("recent", recent_.front().c_str())) {
            for (const std::string& r : std::deque<std::string>(recent_))
                if (ImGui::Selectable(r.c_str())) open(r);
            ImGui::EndCombo();
        }
    }
    ImGui::SetNextItemWidth(230);
    ImGui::InputText("output", output_field_, sizeof output_field_);
    tooltip("Base name of exports: NAME.obj/.ply/.glb, NAME.json, NAME.png");
    const std::string base = output_field_;
    const auto write = [&](const char* name, const std::string& path, const char* done) {
        if (command(name, {{"path", path}})) editor_->set_status(done + path);
    };
    for (const char* ext : {".obj", ".ply", ".glb"}) {
        if (ImGui::Button((std::string("Export ") + ext).c_str())) write("export", base + ext, "exported ");
        ImGui::SameLine();
    }
    ImGui::NewLine();
    if (ImGui::Button("Save scene")) write("save-scene", base + ".json", "saved ");
    tooltip("A scene file that `vfsd deform` turns into the same result");
    ImGui::SameLine();
    if (ImGui::Button("Screenshot")) command("screenshot", {{"path", base + ".png"}});
}

void App::draw_tools_panel() {
    const editor::EditorSession& s = editor_->session();
    const editor::ToolController& tools = editor_->tools();
    for (const auto tool : editor::kAllTools) {
        if (ImGui::RadioButton(editor::tool_name(tool), tools.tool == tool)) command("tool", {{"name", editor::tool_name(tool)}});
        if (ImGui::IsItemHovered()) ImGui::SetTooltip("shortcut: %s", shortcut_for(tool).c_str());
        if (tool != editor::Tool::paint_inner && tool != editor::Tool::paint_s) ImGui::SameLine();
    }
    ImGui::NewLine();
    const float d = float(s.diagonal());
    float radius = float(tools.brush.radius);
    if (ImGui::SliderFloat("brush radius", &radius, 0.005f * d, 0.5f * d, "%.3f")) command("brush", {{"radius", radius}});
    tooltip("[ and ] change it");
    if (tools.tool == editor::Tool::paint_s) {
        float target = float(tools.brush.s_target), strength = float(tools.brush.strength);
        if (ImGui::SliderFloat("s target", &target, 0.0f, 1.0f)) command("brush", {{"target", target}});
        if (ImGui::SliderFloat("strength", &strength, 0.0f, 1.0f)) command("brush", {{"strength", strength}});
    }
    // g_min / g_max change the geodesic region live; one undo step per drag.
    float g[2] = {float(tools.g_min), float(tools.g_max)};
    if (ImGui::SliderFloat2("g_min, g_max", g, 0.0f, d, "%.3f"))
        command("g-range", {{"g_min", g[0]}, {"g_max", g[1]}, {"gesture", true}});
    if (ImGui::IsItemDeactivated()) command("end-gesture");
    tooltip("Eq. (15): s = 0 within g_min of the picked vertex, 1 beyond g_max");
    // The painted region's transition band; one undo step per drag.
    float band = float(s.region_band());
    ImGui::SetNextItemWidth(150);
    if (ImGui::SliderFloat("band", &band, 0.0f, 0.5f * d, "%.3f")) command("region-band", {{"band", band}, {"gesture", true}});
    if (ImGui::IsItemDeactivated()) command("end-gesture");
    tooltip("Painted regions: an inner region alone blends over this width; where inner and outer meet,\n"
            "the outer side gives it to the blend region. A warning says where the blend is too thin.");
    ImGui::SameLine();
    if (ImGui::Button("New region")) command("new-region");
    tooltip("A clean painted region: nothing inner or outer yet. The curve follows the inner region you paint.");
    if (tools.tool == editor::Tool::loops) {
        ImGui::Text("loops: %zu closed, %zu points", tools.loops().size(), tools.loop_in_progress().size());
        if (ImGui::Button("Close loop")) command("close-loop");
        ImGui::SameLine();
        if (ImGui::Button("Clear loops")) command("clear-loops");
    }
    if (!tools.message.empty()) ImGui::TextWrapped("%s", tools.message.c_str());
    if (!tools.hint.empty()) ImGui::TextWrapped("%s", tools.hint.c_str());
}

void App::draw_curve_panel() {
    const editor::EditorSession& s = editor_->session();
    const char* axes[] = {"free", "x", "y", "z"};
    int axis = editor_->tools().axis + 1;
    ImGui::SetNextItemWidth(120);
    if (ImGui::Combo("drag axis", &axis, axes, 4)) command("axis", {{"name", axes[axis]}});
    tooltip("X, Y, Z toggle the constraint");
    if (!s.curve().curve.is_handle) {
        if (ImGui::Button("Add segment")) command("add-segment");
        ImGui::SameLine();
        if (ImGui::Button("Remove segment")) command("remove-segment");
        ImGui::SameLine();
        if (ImGui::Button("Handle")) command("tool", {{"name", "handle"}});
        tooltip("H: click the surface to place a handle (sec. 6.2) instead of the curve");
    } else {
        ImGui::TextWrapped("Handle: drag the gizmo on the target. Centre: move in the screen plane; "
                           "x / y / z axes (red, green, blue = normal): move along; rings: rotate about.");
    }
    const MotionSpec& c = s.curve();
    int mode = c.inner_motion == InnerMotionMode::Rotation ? 0 : 1;
    if (ImGui::Combo("inner motion", &mode, "rotation\0translation\0"))
        command("inner-motion", {{"mode", mode == 0 ? "rotation" : "translation"}});
    float alpha[2] = {float(c.twist_degrees[0]), float(c.twist_degrees[1])};
    if (ImGui::SliderFloat2("alpha0, alpha1", alpha, -360.0f, 360.0f, "%.0f deg"))
        command("twist", {{"alpha", {alpha[0], alpha[1]}}, {"gesture", true}});
    if (ImGui::IsItemDeactivated()) command("end-gesture");
    tooltip("Twist about the curve's tangent, eq. (14)");
}

// Play, the target time, the current time and the edit buttons, on one row.
void App::draw_time_bar() {
    const editor::EditorSession& s = editor_->session();
    if (ImGui::Button(s.moving() ? "Pause" : "Play ")) command("play-pause");
    tooltip("Space");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(180);
    float target = float(s.target_time());
    if (ImGui::SliderFloat("##target", &target, 0.0f, 1.0f, "target t %.3f")) command("set-time", {{"t", target}});
    tooltip("The dark sphere; the white one is the current time");
    ImGui::SameLine();
    char label[64];
    std::snprintf(label, sizeof label, "%s%s", s.holding_result() ? "" : "t = ", editor::time_stat_text(s).c_str());
    const double span = std::abs(s.target_time() - 0.0);
    ImGui::ProgressBar(span > 0 ? float(s.time() / span) : 0.0f, ImVec2(120, 0), label);
    struct Action {
        const char *label, *command, *tip;
    };
    for (const Action& a : {Action{"Reset", "reset", "R"},
                            Action{"Apply", "apply", "A: the deformed mesh becomes the base of the next deformation"},
                            Action{"Undo", "undo", "Ctrl+Z"}, Action{"Redo", "redo", "Ctrl+Shift+Z"}}) {
        ImGui::SameLine();
        if (ImGui::Button(a.label)) command(a.command);
        tooltip(a.tip);
    }
}

// The numbers a user watches, on one line: size, backend, speed, volume, folds, history.
void App::draw_stats_line() {
    const editor::EditorSession& s = editor_->session();
    const editor::SessionStats& st = s.stats();
    ImGui::Text("%zu vertices | %s", st.vertices, st.backend.c_str());
    if (!st.backend_reason.empty()) {
        ImGui::SameLine();
        ImGui::TextDisabled("(why?)");
        tooltip(st.backend_reason.c_str());
    }
    ImGui::SameLine();
    ImGui::Text("| %.3f ms/step | volume error %s |", st.ms_per_step, editor::volume_stat_text(st).c_str());
    ImGui::SameLine();
    const std::string flipped = "flipped triangles " + editor::flipped_stat_text(st);
    if (st.flipped_since_opened > 0 || st.flipped_triangles > 0)
        ImGui::TextColored(ImVec4(0.85f, 0.3f, 0.0f, 1.0f), "%s", flipped.c_str());
    else
        ImGui::TextUnformatted(flipped.c_str());
    ImGui::SameLine();
    ImGui::TextDisabled("| undo %zu, redo %zu", s.history().undo_count(), s.history().redo_count());
}

void App::draw_options() {
    const char up = editor_->session().up_axis();
    if (ImGui::RadioButton("Z up", up == 'z')) command("up-axis", {{"axis", "z"}});
    ImGui::SameLine();
    if (ImGui::RadioButton("Y up", up == 'y')) command("up-axis", {{"axis", "y"}});
    tooltip("The axis shown up, saved in the scene and remembered for the file type");
    bool cpu = editor_->settings().force_cpu;
    if (ImGui::Checkbox("force CPU", &cpu)) command("force-cpu", {{"on", cpu}});
    ImGui::SameLine();
    bool wireframe = editor_->settings().wireframe;
    if (ImGui::Checkbox("wireframe", &wireframe)) command("wireframe", {{"on", wireframe}});
    ImGui::SameLine();
    if (ImGui::Button("Help")) show_help_ = true;
    tooltip("F1");
}

void App::draw_help() {
    ImGui::SetNextWindowPos(ImVec2(350, 8), ImGuiCond_Appearing);
    ImGui::Begin("Shortcuts", &show_help_, ImGuiWindowFlags_AlwaysAutoResize);
    if (ImGui::BeginTable("keys", 2, ImGuiTableFlags_RowBg)) {
        const auto row = [](const char* keys, const char* what) {
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(keys);
            ImGui::TableNextColumn();
            ImGui::TextUnformatted(what);
        };
        for (const editor::KeyBinding& k : editor::key_bindings()) row(k.key, k.help);
        for (const Shortcut& k : kShellShortcuts) row(k.keys, k.what);
        ImGui::EndTable();
    }
    ImGui::End();
}

constexpr const char* kRestoreTitle = "Restore autosave";

void App::draw_restore_offer() {
    const editor::Autosave& autosave = editor_->autosave();
    const auto& offer = autosave.offer();
    if (offer && !ImGui::IsPopupOpen(kRestoreTitle)) ImGui::OpenPopup(kRestoreTitle);
    ImGui::SetNextWindowPos(ImGui::GetMainViewport()->GetCenter(), ImGuiCond_Appearing, ImVec2(0.5f, 0.5f));
    if (!ImGui::BeginPopupModal(kRestoreTitle, nullptr, ImGuiWindowFlags_AlwaysAutoResize)) return;
    if (offer) {
        ImGui::Text("Restore the autosaved session from %s (%s)?", offer->written_text().c_str(), offer->mesh.c_str());
        ImGui::TextDisabled("%s", autosave.directory().c_str());
        const bool restore = ImGui::Button("Restore");
        ImGui::SameLine();
        const bool discard = ImGui::Button("Discard");
        if (restore || discard) command("restore-autosave", {{"answer", restore ? "restore" : "discard"}});
    }
    if (!autosave.offer()) ImGui::CloseCurrentPopup();  // answered here or by a script
    ImGui::EndPopup();
}

}  // namespace vfsd::desktop
