#include "editor/edit_history.h"

namespace vfsd::editor {

bool operator==(const CurveSettings& a, const CurveSettings& b) {
    const auto frame_equal = [](const HandleFrame& x, const HandleFrame& y) {
        return x.position == y.position && x.normal == y.normal && x.binormal == y.binormal;
    };
    return a.curve.is_handle == b.curve.is_handle && a.curve.bezier == b.curve.bezier &&
           frame_equal(a.curve.from, b.curve.from) && frame_equal(a.curve.to, b.curve.to) &&
           a.inner_motion == b.inner_motion && a.twist_degrees[0] == b.twist_degrees[0] &&
           a.twist_degrees[1] == b.twist_degrees[1] && a.twist_plane == b.twist_plane &&
           a.stream_origin == b.stream_origin;
}

void EditHistory::push(HistoryEntry entry) {
    done_.push_back(std::move(entry));
    undone_.clear();
}

const HistoryEntry* EditHistory::undo() {
    if (done_.empty()) return nullptr;
    undone_.push_back(std::move(done_.back()));
    done_.pop_back();
    return &undone_.back();
}

const HistoryEntry* EditHistory::redo() {
    if (undone_.empty()) return nullptr;
    done_.push_back(std::move(undone_.back()));
    undone_.pop_back();
    return &done_.back();
}

void EditHistory::clear() {
    done_.clear();
    undone_.clear();
}

}  // namespace vfsd::editor
