#include "editor/piece_times.h"

#include <algorithm>

namespace vfsd::editor {
namespace {

void keep_last(std::deque<double>& times, double ms, std::size_t count) {
    times.push_back(ms);
    if (times.size() > count) times.pop_front();
}

double longest(const std::deque<double>& times) {
    return times.empty() ? 0.0 : *std::max_element(times.begin(), times.end());
}

}  // namespace

std::size_t PieceTimes::index(Kind kind) {
    return std::size_t(std::clamp(kind.place, 0, kPlaces - 1)) * 2 + (kind.affine ? 1 : 0);
}

void PieceTimes::record(Kind kind, double ms) {
    keep_last(of_kind_[index(kind)], ms, kRecentOfKind);
    keep_last(recent_, ms, kRecent);
}

double PieceTimes::expected(Kind kind) const {
    const std::deque<double>& same = of_kind_[index(kind)];
    return same.empty() ? longest(recent_) : longest(same);
}

}  // namespace vfsd::editor
