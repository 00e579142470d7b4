#include "editor/edit_history.h"

namespace vfsd::editor {

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
