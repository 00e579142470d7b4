#pragma once
// The browser page's side of the Editor (web/vfsd-page.js, window.vfsd, docs/web.md)
// as JSON: the state its panel shows, the overlay as it paints it, and its
// queries. Kept in the engine, next to the Editor, so the page's command strings
// run natively in the tests; web/main.cpp only passes them through.

#include <string>

#include <nlohmann/json.hpp>

#include "editor/editor.h"

namespace vfsd::editor {

// What the page's shell knows that the Editor does not.
struct PageInfo {
    std::string files;     // the folder of uploaded meshes and scenes, and of exports
    std::string renderer;  // the WebGL renderer's name
    bool context_lost = false;
    bool multisampled = true;  // the view's canvas (gpu::multisample_view)
    long canvas_draws = 0;     // the view's draws so far (frames that only moved the overlay do not count)
};

// Everything the panel shows: stats, tool settings, control points, undo / redo,
// warnings, the autosave's offer, the script's progress.
nlohmann::json page_state(const Editor& editor, const PageInfo& page);
// The overlay in canvas pixels: {polygon, points, loops, current, brush, gizmo}.
nlohmann::json overlay_json(const Overlay& overlay);

// Whether the page's `cmd` only reads (state, project, gizmo-parts, checksum):
// nothing it does changes what is drawn.
bool page_query(const std::string& cmd);

// One page command {"cmd": NAME, ...}: a query of the page's (state, open,
// load-scene, export-mesh, export-scene, project, gizmo-parts, checksum, script,
// key) or else a command of the table (docs/commands.md), answered by the state.
// Throws InputError (the page shows it).
nlohmann::json page_command(Editor& editor, const nlohmann::json& command, const PageInfo& page);

}  // namespace vfsd::editor
