#include "editor/frame_log.h"

#include <algorithm>
#include <cstdio>

namespace vfsd::editor {
namespace {

double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

std::string line(const char* head, const FrameTimes& t) {
    char text[160];
    std::snprintf(text, sizeof text, "%s app %.2f ms, GL calls %.2f ms, swap %.2f ms, whole %.2f ms", head, t.app_ms,
                  t.draw_ms, t.swap_ms, t.whole_ms());
    return text;
}

}  // namespace

void FrameLog::start(int frames) {
    left_ = frames;
    frames_.clear();
}

std::vector<std::string> FrameLog::add(const FrameTimes& times) {
    frames_.push_back(times);
    std::vector<std::string> out = {line(("frame " + std::to_string(frames_.size()) + ":").c_str(), times)};
    if (--left_ > 0) return out;
    // The medians over the logged frames, each part and the whole on its own.
    const auto median_of = [&](auto part) {
        std::vector<double> v;
        for (const FrameTimes& f : frames_) v.push_back(part(f));
        return median(v);
    };
    const FrameTimes m{median_of([](const FrameTimes& f) { return f.app_ms; }),
                       median_of([](const FrameTimes& f) { return f.draw_ms; }),
                       median_of([](const FrameTimes& f) { return f.swap_ms; })};
    const double whole = median_of([](const FrameTimes& f) { return f.whole_ms(); });
    char text[160];
    std::snprintf(text, sizeof text, "frames: %zu, median app %.2f ms, GL calls %.2f ms, swap %.2f ms, whole %.2f ms",
                  frames_.size(), m.app_ms, m.draw_ms, m.swap_ms, whole);
    out.push_back(text);
    return out;
}

}  // namespace vfsd::editor
