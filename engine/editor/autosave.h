#pragma once
// "Nothing lost": an autosave of an editor's session that a restarted editor
// offers to restore. Knows nothing of windows or HTML; the shells call it.
//
// The folder holds the session as a scene (EditorSession::save_scene with the
// input mesh copied beside it, and the base mesh after an apply) and a manifest,
// autosave.json, naming the scene, the mesh the user was editing and when it was
// written. Saves go to a slot (session-a.*, -b.*, -c.*) other than the one the
// manifest names and the one holding a restored session's own mesh file, and the
// manifest is written last, so a save that dies half-way leaves the previous one
// restorable: the manifest's atomic rename is the commit.

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>

#include "editor/session.h"

namespace vfsd::editor {

struct AutosaveInfo {
    std::string scene;         // the saved scene file
    std::string mesh;          // the mesh the session was editing, as the user named it
    std::int64_t written = 0;  // seconds since the Unix epoch
    // "2026-11-23 10:53" in local time.
    std::string written_text() const;
};

// VFSD_AUTOSAVE_DIR when set, else $XDG_STATE_HOME/vfsd/autosave, else
// ~/.local/state/vfsd/autosave.
std::string default_autosave_directory();

class Autosave {
public:
    using Clock = std::chrono::steady_clock;

    explicit Autosave(std::string directory, double interval_seconds = 10.0);

    const std::string& directory() const { return directory_; }

    // The session as it is now needs no saving (as opened, or as just restored).
    void mark_saved(const EditorSession& session);
    // Saves when the session's document changed since the last save, at most once
    // per interval, and never while a restore is offered. Returns true when it wrote.
    bool maybe_save(EditorSession& session, Clock::time_point now = Clock::now());
    // Saves now. Never throws: a failure becomes the session's autosave warning
    // (a later success clears it) and false.
    bool save(EditorSession& session);

    // The restorable autosave, or nullopt: there is none, or it is unreadable
    // (problem() says why; it is then ignored, never deleted).
    std::optional<AutosaveInfo> find();
    // Opens the autosave in `session` at its target time. False, with the reason
    // in problem() and in the session's warnings, leaves the session as it was.
    bool restore(EditorSession& session);
    // Removes the autosave (a clean exit, or the user declined it).
    void clear();
    // At start-up: offers what find() finds (an unreadable autosave becomes the
    // session's warning instead). The offer stands until answered.
    void offer_restore(EditorSession& session);
    const std::optional<AutosaveInfo>& offer() const { return offer_; }
    // The user's answer to the offer: accepted, restore it (as restore());
    // declined, clear() it. True when `session` now holds it; InputError without
    // an offer.
    bool answer(EditorSession& session, bool accepted);
    // The session has changes the autosave does not hold yet.
    bool behind(const EditorSession& session) const { return session.document_revision() != saved_revision_; }

    const std::string& problem() const { return problem_; }

private:
    std::string file(const std::string& name) const;

    std::string directory_;
    Clock::duration interval_;
    std::optional<Clock::time_point> last_attempt_;
    std::uint64_t saved_revision_ = 0;
    // The mesh name the restored autosave showed, and the document it opened.
    std::optional<std::pair<std::string, std::uint64_t>> restored_mesh_;
    std::string problem_;
    std::optional<AutosaveInfo> offer_;
};

}  // namespace vfsd::editor
