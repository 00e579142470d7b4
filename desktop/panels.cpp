// The editor's panels and keyboard shortcuts. Every control calls the editor core;
// the shortcuts are listed once (kShortcuts) for tooltips and the help window.

#include <cstdio>
#include <filesystem>

#include <GLFW/glfw3.h>
#include <imgui.h>

#include "desktop/app.h"

namespace vfsd::desktop {
namespace {

struct Shortcut {
    const char* keys;
    const char* what;
};

constexpr Shortcut kShortcuts[] = {
    {"N", "navigate: drag control points or the handle's gizmo; elsewhere drag to orbit"},
    {"G", "geodesic region: click a vertex"},
    {"I", "paint the inner region (moves fully)"},
    {"O", "paint the outer region (stays)"},
    {"E", "erase painted labels"},
    {"S", "paint s directly"},
    {"L", "draw boundary loops (Enter closes a loop)"},
    {"H", "handle: click the surface to place a handle, then drag its gizmo"},
    {"[ / ]", "brush radius smaller / larger"},
    {"X / Y / Z", "constrain control point drags to an axis (again: free)"},
    {"Space", "play / pause"},
    {"R", "reset to t = 0"},
    {"A", "apply: bake the deformed mesh"},
    {"Ctrl+Z / Ctrl+Shift+Z", "undo / redo (also Ctrl+Y)"},
    {"F", "frame all"},
    {"1 / 3 / 7 / 0", "front / right / top / 3/4 view (Ctrl: back / left / bottom)"},
    {"W", "wireframe"},
    {"Tab", "hide / show the panels"},
    {"F1", "this help"},
    {"left drag", "tool, or orbit"},
    {"right / middle / Shift+left drag", "pan"},
    {"wheel", "zoom toward the cursor"},
};

const char* shortcut_for(editor::Tool tool) {
    switch (tool) {
        case editor::Tool::navigate: return "N";
        case editor::Tool::geodesic: return "G";
        case editor::Tool::paint_inner: return "I";
        case editor::Tool::paint_outer: return "O";
        case editor::Tool::erase: return "E";
        case editor::Tool::paint_s: return "S";
        case editor::Tool::loops: return "L";
        case editor::Tool::handle: return "H";
    }
    return "";
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
    const bool ctrl = io.KeyCtrl;
    if (ctrl && pressed(GLFW_KEY_Z)) {
        if (io.KeyShift) session_->redo();
        else session_->undo();
        return;
    }
    if (ctrl && pressed(GLFW_KEY_Y)) {
        session_->redo();
        return;
    }
    if (pressed(GLFW_KEY_F1)) show_help_ = !show_help_;
    if (pressed(GLFW_KEY_TAB)) show_ui_ = !show_ui_;
    if (io.WantCaptureKeyboard) return;
    const std::pair<int, editor::Tool> tools[] = {
        {GLFW_KEY_N, editor::Tool::navigate},   {GLFW_KEY_G, editor::Tool::geodesic}, {GLFW_KEY_I, editor::Tool::paint_inner},
        {GLFW_KEY_O, editor::Tool::paint_outer}, {GLFW_KEY_E, editor::Tool::erase},   {GLFW_KEY_S, editor::Tool::paint_s},
        {GLFW_KEY_L, editor::Tool::loops},      {GLFW_KEY_H, editor::Tool::handle}};
    for (const auto& [key, tool] : tools)
        if (!ctrl && pressed(key)) tools_.tool = tool;
    if (pressed(GLFW_KEY_LEFT_BRACKET)) tools_.brush.radius /= 1.2;
    if (pressed(GLFW_KEY_RIGHT_BRACKET)) tools_.brush.radius *= 1.2;
    for (const auto& [key, axis] : {std::pair{GLFW_KEY_X, 0}, std::pair{GLFW_KEY_Y, 1}, std::pair{GLFW_KEY_Z, 2}})
        if (!ctrl && pressed(key)) tools_.axis = tools_.axis == axis ? -1 : axis;
    if (pressed(GLFW_KEY_ENTER) && tools_.tool == editor::Tool::loops) tools_.close_loop();
    if (pressed(GLFW_KEY_SPACE)) {
        if (session_->moving()) session_->pause();
        else session_->play();
    }
    if (pressed(GLFW_KEY_R)) session_->reset();
    if (pressed(GLFW_KEY_A)) session_->apply();
    if (pressed(GLFW_KEY_W)) wireframe_ = !wireframe_;
    if (pressed(GLFW_KEY_F)) loaded();
    using editor::StandardView;
    if (pressed(GLFW_KEY_1)) camera_.set_view(ctrl ? StandardView::back : StandardView::front);
    if (pressed(GLFW_KEY_3)) camera_.set_view(ctrl ? StandardView::left : StandardView::right);
    if (pressed(GLFW_KEY_7)) camera_.set_view(ctrl ? StandardView::bottom : StandardView::top);
    if (pressed(GLFW_KEY_0)) camera_.set_view(StandardView::iso);
}

void App::draw_panels() {
    if (!show_ui_) return;
    editor::EditorSession& s = *session_;
    ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_Always);
    ImGui::SetNextWindowSize(ImVec2(330, 0), ImGuiCond_Always);
    ImGui::SetNextWindowBgAlpha(0.92f);
    ImGui::Begin("vfsd", nullptr, ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse);

    // ---- file
    if (ImGui::CollapsingHeader("File", ImGuiTreeNodeFlags_DefaultOpen)) {
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
        if (!load_error_.empty()) ImGui::TextColored(ImVec4(0.8f, 0.1f, 0.1f, 1), "%s", load_error_.c_str());
        ImGui::SetNextItemWidth(230);
        ImGui::InputText("output", output_field_, sizeof output_field_);
        tooltip("Base name of exports: NAME.obj/.ply/.glb, NAME.json, NAME.png");
        const std::string base = output_field_;
        const auto attempt = [&](const char* what, const auto& action) {
            try {
                action();
                status_ = what;
            } catch (const std::exception& e) {
                status_ = e.what();
            }
        };
        for (const char* ext : {".obj", ".ply", ".glb"}) {
            if (ImGui::Button((std::string("Export ") + ext).c_str()))
                attempt(("exported " + base + ext).c_str(), [&] { s.export_mesh(base + ext); });
            ImGui::SameLine();
        }
        ImGui::NewLine();
        if (ImGui::Button("Save scene")) attempt(("saved " + base + ".json").c_str(), [&] { s.save_scene(base + ".json"); });
        tooltip("A scene file that `vfsd deform` turns into the same result");
        ImGui::SameLine();
        if (ImGui::Button("Screenshot")) screenshot(base + ".png", true);
        if (!status_.empty()) ImGui::TextWrapped("%s", status_.c_str());
    }

    // ---- tools
    if (ImGui::CollapsingHeader("Tools", ImGuiTreeNodeFlags_DefaultOpen)) {
        for (const auto tool : editor::kAllTools) {
            if (ImGui::RadioButton(editor::tool_name(tool), tools_.tool == tool)) tools_.tool = tool;
            if (ImGui::IsItemHovered()) ImGui::SetTooltip("shortcut: %s", shortcut_for(tool));
            if (tool != editor::Tool::paint_inner && tool != editor::Tool::paint_s) ImGui::SameLine();
        }
        ImGui::NewLine();
        const float d = float(s.diagonal());
        float radius = float(tools_.brush.radius);
        if (ImGui::SliderFloat("brush radius", &radius, 0.005f * d, 0.5f * d, "%.3f")) tools_.brush.radius = radius;
        tooltip("[ and ] change it");
        if (tools_.tool == editor::Tool::paint_s) {
            float target = float(tools_.brush.s_target), strength = float(tools_.brush.strength);
            if (ImGui::SliderFloat("s target", &target, 0.0f, 1.0f)) tools_.brush.s_target = target;
            if (ImGui::SliderFloat("strength", &strength, 0.0f, 1.0f)) tools_.brush.strength = strength;
        }
        // g_min / g_max change the geodesic region live; one undo step per drag.
        float g[2] = {float(tools_.g_min), float(tools_.g_max)};
        if (ImGui::SliderFloat2("g_min, g_max", g, 0.0f, d, "%.3f")) {
            tools_.g_min = std::min(g[0], g[1] - 1e-4f * d);
            tools_.g_max = std::max(g[1], g[0] + 1e-4f * d);
            try {
                s.set_geodesic_range(tools_.g_min, tools_.g_max);
            } catch (const std::exception& e) {
                tools_.message = e.what();
            }
        }
        if (ImGui::IsItemActivated()) s.begin_region_gesture();
        if (ImGui::IsItemDeactivated()) s.end_region_gesture("geodesic range");
        tooltip("Eq. (15): s = 0 within g_min of the picked vertex, 1 beyond g_max");
        if (tools_.tool == editor::Tool::loops) {
            ImGui::Text("loops: %zu closed, %zu points", tools_.loops().size(), tools_.loop_in_progress().size());
            if (ImGui::Button("Close loop")) tools_.close_loop();
            ImGui::SameLine();
            if (ImGui::Button("Clear loops")) tools_.clear_loops();
        }
        if (!tools_.message.empty()) ImGui::TextWrapped("%s", tools_.message.c_str());
    }

    // ---- curve
    if (ImGui::CollapsingHeader("Curve", ImGuiTreeNodeFlags_DefaultOpen)) {
        const char* axes[] = {"free", "x", "y", "z"};
        int axis = tools_.axis + 1;
        ImGui::SetNextItemWidth(120);
        if (ImGui::Combo("drag axis", &axis, axes, 4)) tools_.axis = axis - 1;
        tooltip("X, Y, Z toggle the constraint");
        if (!s.curve().curve.is_handle) {
            if (ImGui::Button("Add segment")) s.add_segment();
            ImGui::SameLine();
            if (ImGui::Button("Remove segment")) s.remove_segment();
            ImGui::SameLine();
            if (ImGui::Button("Handle")) tools_.tool = editor::Tool::handle;
            tooltip("H: click the surface to place a handle (sec. 6.2) instead of the curve");
        } else {
            ImGui::TextWrapped("Handle: drag the gizmo on the target. Centre: move in the screen plane; "
                               "x / y / z axes (red, green, blue = normal): move along; rings: rotate about.");
        }
        editor::CurveSettings c = s.curve();
        int mode = c.inner_motion == InnerMotionMode::Rotation ? 0 : 1;
        if (ImGui::Combo("inner motion", &mode, "rotation\0translation\0")) {
            c.inner_motion = mode == 0 ? InnerMotionMode::Rotation : InnerMotionMode::Translation;
            s.set_curve(c);
        }
        float alpha[2] = {float(c.twist_degrees[0]), float(c.twist_degrees[1])};
        if (ImGui::SliderFloat2("alpha0, alpha1", alpha, -360.0f, 360.0f, "%.0f deg")) {
            c.twist_degrees[0] = alpha[0], c.twist_degrees[1] = alpha[1];
            s.set_curve(c);
        }
        if (ImGui::IsItemActivated()) s.begin_curve_gesture();
        if (ImGui::IsItemDeactivated()) s.end_curve_gesture("twist");
        tooltip("Twist about the curve's tangent, eq. (14)");
    }

    // ---- time
    if (ImGui::CollapsingHeader("Time", ImGuiTreeNodeFlags_DefaultOpen)) {
        float target = float(s.target_time());
        if (ImGui::SliderFloat("target t", &target, 0.0f, 1.0f, "%.3f")) s.set_target_time(target);
        tooltip("The dark sphere; the white one is the current time");
        char label[64];
        std::snprintf(label, sizeof label, "t = %.3f", s.time());
        const double span = std::abs(s.target_time() - 0.0);
        ImGui::ProgressBar(span > 0 ? float(s.time() / span) : 0.0f, ImVec2(-1, 0), label);
        if (ImGui::Button(s.moving() ? "Pause" : "Play")) s.moving() ? s.pause() : s.play();
        tooltip("Space");
        ImGui::SameLine();
        if (ImGui::Button("Reset")) s.reset();
        tooltip("R");
        ImGui::SameLine();
        if (ImGui::Button("Apply")) s.apply();
        tooltip("A: the deformed mesh becomes the base of the next deformation");
        ImGui::SameLine();
        if (ImGui::Button("Undo")) s.undo();
        tooltip("Ctrl+Z");
        ImGui::SameLine();
        if (ImGui::Button("Redo")) s.redo();
        tooltip("Ctrl+Shift+Z");
    }

    // ---- stats and warnings
    if (ImGui::CollapsingHeader("Stats", ImGuiTreeNodeFlags_DefaultOpen)) {
        const editor::SessionStats& st = s.stats();
        ImGui::Text("%zu vertices, %zu triangles", st.vertices, st.triangles);
        ImGui::Text("backend: %s", st.backend.c_str());
        if (!st.backend_reason.empty()) {
            ImGui::SameLine();
            ImGui::TextDisabled("(why?)");
            tooltip(st.backend_reason.c_str());
        }
        ImGui::Text("%.3f ms/step, volume error %.3f%%", st.ms_per_step, st.volume_error_percent);
        if (st.flipped_triangles > 0 && st.first_fold_time >= 0.0)
            ImGui::TextColored(ImVec4(1.0f, 0.55f, 0.3f, 1.0f), "flipped triangles: %zu (since t = %.2f)",
                               st.flipped_triangles, st.first_fold_time);
        else
            ImGui::Text("flipped triangles: %zu", st.flipped_triangles);
        ImGui::Text("undo: %zu, redo: %zu", s.history().undo_count(), s.history().redo_count());
        bool cpu = options_.backend == "cpu";
        if (ImGui::Checkbox("force CPU", &cpu)) {
            options_.backend = cpu ? "cpu" : "auto";
            s.set_force_cpu(cpu);
        }
        ImGui::SameLine();
        ImGui::Checkbox("wireframe", &wireframe_);
        ImGui::SameLine();
        if (ImGui::Button("Help")) show_help_ = true;
        tooltip("F1");
    }
    for (const std::string& w : s.warnings()) ImGui::TextColored(ImVec4(0.75f, 0.35f, 0.0f, 1), "! %s", w.c_str());
    ImGui::End();

    if (show_help_) {
        ImGui::SetNextWindowPos(ImVec2(350, 8), ImGuiCond_Appearing);
        ImGui::Begin("Shortcuts", &show_help_, ImGuiWindowFlags_AlwaysAutoResize);
        if (ImGui::BeginTable("keys", 2, ImGuiTableFlags_RowBg)) {
            for (const Shortcut& k : kShortcuts) {
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(k.keys);
                ImGui::TableNextColumn();
                ImGui::TextUnformatted(k.what);
            }
            ImGui::EndTable();
        }
        ImGui::End();
    }
}

}  // namespace vfsd::desktop
