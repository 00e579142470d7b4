#include "editor/autosave.h"

#include <cstdlib>
#include <ctime>
#include <filesystem>

#include "base/error.h"
#include "io/format_io.h"
#include "io/mesh_file.h"

namespace vfsd::editor {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr const char* kManifest = "autosave.json";
// Three slots: one committed, one holding a restored session's own mesh file,
// one free to write.
constexpr const char* kSlots[] = {"session-a", "session-b", "session-c"};

std::string environment(const char* name) {
    const char* value = std::getenv(name);
    return value ? value : "";
}

bool is_slot_scene(const std::string& name) {
    for (const char* slot : kSlots)
        if (name == std::string(slot) + ".json") return true;
    return false;
}

bool is_slot_file(const std::string& name, const std::string& slot) { return name.rfind(slot + ".", 0) == 0; }

bool is_slot_file(const std::string& name) {
    for (const char* slot : kSlots)
        if (is_slot_file(name, slot)) return true;
    return false;
}

// `path` is a file of `slot` in `folder`.
bool in_slot(const fs::path& path, const std::string& folder, const std::string& slot) {
    std::error_code ec;
    return is_slot_file(path.filename().string(), slot) && fs::equivalent(path.parent_path(), folder, ec);
}

// The manifest's fields, checked: the scene must be one of the two slots.
AutosaveInfo read_manifest(const std::string& path) {
    const json j = parse_scene_json(io::read_file_bytes(path), path);
    if (!j.is_object() || !j.value("scene", json()).is_string() || !j.value("mesh", json()).is_string() ||
        !j.value("written", json()).is_number_integer())
        throw InputError(path + ": not an autosave manifest (scene, mesh, written)");
    const std::string scene = j["scene"].get<std::string>();
    if (!is_slot_scene(scene)) throw InputError(path + ": scene '" + scene + "' is not an autosave slot");
    AutosaveInfo info;
    info.scene = (fs::path(path).parent_path() / scene).string();
    info.mesh = j["mesh"].get<std::string>();
    info.written = j["written"].get<std::int64_t>();
    return info;
}

// The scene the manifest names, when it is readable.
std::optional<std::string> committed_scene(const std::string& manifest) {
    try {
        return read_manifest(manifest).scene;
    } catch (const std::exception&) {
        return std::nullopt;
    }
}

// The slot to write: not the committed one, which stays whole until the manifest
// names the new one, and not the one holding the session's own mesh file.
std::string free_slot(const std::string& folder, const std::string& mesh) {
    const std::optional<std::string> committed = committed_scene((fs::path(folder) / kManifest).string());
    for (const char* slot : kSlots) {
        const bool is_committed = committed && fs::path(*committed).filename() == std::string(slot) + ".json";
        if (!is_committed && !in_slot(mesh, folder, slot)) return slot;
    }
    throw std::logic_error("autosave: no free slot");
}

// The scene must parse and its mesh must be there.
void check_scene(const std::string& path) {
    const Scene scene = load_scene(path);
    if (scene.mesh.rfind("builtin:", 0) != 0 && !fs::exists(scene.mesh))
        throw IoError(path + ": its mesh " + scene.mesh + " is missing");
}

}  // namespace

std::string AutosaveInfo::written_text() const {
    const std::time_t t = static_cast<std::time_t>(written);
    std::tm local{};
    localtime_r(&t, &local);
    char text[32];
    std::strftime(text, sizeof text, "%Y-%m-%d %H:%M", &local);
    return text;
}

std::string default_autosave_directory() {
    if (const std::string dir = environment("VFSD_AUTOSAVE_DIR"); !dir.empty()) return dir;
    if (const std::string state = environment("XDG_STATE_HOME"); !state.empty()) return state + "/vfsd/autosave";
    return environment("HOME") + "/.local/state/vfsd/autosave";
}

Autosave::Autosave(std::string directory, double interval_seconds)
    : directory_(std::move(directory)),
      interval_(std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(interval_seconds))) {}

std::string Autosave::file(const std::string& name) const { return (fs::path(directory_) / name).string(); }

void Autosave::mark_saved(const EditorSession& session) { saved_revision_ = session.document_revision(); }

bool Autosave::maybe_save(EditorSession& session, Clock::time_point now) {
    if (offer_ || !behind(session)) return false;
    if (last_attempt_ && now - *last_attempt_ < interval_) return false;
    last_attempt_ = now;
    return save(session);
}

bool Autosave::save(EditorSession& session) {
    try {
        fs::create_directories(directory_);
        const std::string scene = free_slot(directory_, session.mesh_name()) + ".json";
        session.save_scene(file(scene), InputMesh::copied);
        // A restored session edits the autosave's copy: the user's name stays.
        const bool restored = restored_mesh_ && restored_mesh_->second == session.mesh_revision();
        const json manifest = {{"scene", scene},
                               {"mesh", restored ? restored_mesh_->first : session.mesh_name()},
                               {"written", static_cast<std::int64_t>(std::time(nullptr))}};
        write_file_atomically(file(kManifest), manifest.dump(2) + "\n");
        saved_revision_ = session.document_revision();
        session.set_autosave_warning("");
        return true;
    } catch (const std::exception& e) {
        session.set_autosave_warning(std::string("autosave failed: ") + e.what());
        return false;
    }
}

std::optional<AutosaveInfo> Autosave::find() {
    problem_.clear();
    std::error_code ec;
    if (!fs::exists(file(kManifest), ec)) return std::nullopt;
    try {
        AutosaveInfo info = read_manifest(file(kManifest));
        check_scene(info.scene);
        return info;
    } catch (const std::exception& e) {
        problem_ = std::string("autosave ignored: ") + e.what();
        return std::nullopt;
    }
}

bool Autosave::restore(EditorSession& session) {
    const std::optional<AutosaveInfo> info = find();
    if (info) {
        try {
            session.open_scene(load_scene(info->scene));  // throws before changing anything; plays to its target
            mark_saved(session);
            restored_mesh_ = std::make_pair(info->mesh, session.mesh_revision());
            return true;
        } catch (const std::exception& e) {
            problem_ = std::string("autosave not restored: ") + e.what();
        }
    } else if (problem_.empty()) {
        problem_ = "no autosave in " + directory_;
    }
    session.set_autosave_warning(problem_);
    return false;
}

void Autosave::offer_restore(EditorSession& session) {
    offer_ = find();
    if (!problem_.empty()) session.set_autosave_warning(problem_);
}

bool Autosave::answer(EditorSession& session, bool accepted) {
    if (!offer_) throw InputError("no autosave was offered");
    offer_.reset();
    if (accepted) return restore(session);
    clear();
    mark_saved(session);
    return false;
}

void Autosave::clear() {
    // The manifest first: a folder half cleared is never offered.
    std::error_code ec;
    fs::remove(file(kManifest), ec);
    for (const auto& entry : fs::directory_iterator(directory_, ec))
        if (is_slot_file(entry.path().filename().string())) fs::remove(entry.path(), ec);
}

}  // namespace vfsd::editor
