#pragma once
// Undo and redo for the editor. Every change a user makes is recorded as data,
// the state before and after (or, for painting, the brush's RegionEdit), so
// reverting and re-applying restore the state exactly. EditorSession applies them;
// the history only orders them.

#include <cstddef>
#include <string>
#include <variant>
#include <vector>

#include "region/brush.h"
#include "scene/scene.h"

namespace vfsd::editor {

// What defines the region field s.
struct RegionSource {
    enum class Kind {
        spec,    // a scene's region as stated (selectors, geodesic level, sphere tool, or a given field)
        labels,  // the painted inner / outer labels (eq. 16), saved as vertex selectors
        field,   // the directly painted s, saved as a field
    };
    Kind kind = Kind::spec;
    RegionSpec spec;    // Kind::spec only
    double band = 0.0;  // Kind::labels only: the transition band (region_field.h), mesh units
};

// A region edit: the source before and after, and the painting that went with it
// (possibly empty: a geodesic pick or a slider change only swaps the source).
struct RegionChange {
    RegionSource before, after;
    RegionEdit paint;
    // The curve follows the inner region (curve/curve_on_region.h): the motion
    // before and after (equal when it did not move).
    MotionSpec motion_before, motion_after;
};

// A curve edit: the scene's motion (curve or handle and its settings) before and after.
struct CurveChange {
    MotionSpec before, after;
};

// "Apply": the deformed positions become the base mesh; the region is kept as the
// field it was, and the curve restarts where the old one ended. Its undo plays
// the old deformation to `time` again (the pose that was applied).
struct BakeChange {
    std::vector<Vec3> before, after;
    RegionSource region_before, region_after;
    MotionSpec motion_before, motion_after;
    bool baked_before = false;
    double time = 0.0;
};

using Edit = std::variant<RegionChange, CurveChange, BakeChange>;

struct HistoryEntry {
    std::string label;  // "paint inner", "move control point 2", ...
    Edit edit;
};

class EditHistory {
public:
    // Records an edit that has been applied; clears the redo list.
    void push(HistoryEntry entry);
    // The entry to revert (moved to the redo list), or nullptr when there is none.
    const HistoryEntry* undo();
    // The entry to re-apply (moved back to the undo list), or nullptr.
    const HistoryEntry* redo();
    void clear();
    std::size_t undo_count() const { return done_.size(); }
    std::size_t redo_count() const { return undone_.size(); }
    const HistoryEntry* last() const { return done_.empty() ? nullptr : &done_.back(); }

private:
    std::vector<HistoryEntry> done_, undone_;
};

}  // namespace vfsd::editor
