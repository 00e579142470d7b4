#pragma once
// The times of a step's pieces (Editor::integrate_in_pieces), or of a run's
// preparation parts (Editor::integrate_for), kept by kind, so that a frame plans
// its next piece by the pieces like it. A step's pieces differ: its estimates,
// its move, at a fold repair's time the fold test, then its end; and at a time
// of the affine test (every fifth of the run) that test's piece takes two to
// three times as long as the others. Planned by the longest of all recent
// pieces, a frame could start that piece with most of its budget spent once the
// last one had left the window. Times are milliseconds.

#include <array>
#include <cstddef>
#include <deque>

namespace vfsd::editor {

class PieceTimes {
public:
    struct Kind {
        int place = 0;        // the piece's place in its step (0: the first)
        bool affine = false;  // the step passes a time of the affine test
    };
    void record(Kind kind, double ms);
    // The longest of the last pieces of this kind; where none was timed yet, the
    // longest of the last pieces of any kind (0 before the first).
    double expected(Kind kind) const;

private:
    static constexpr int kPlaces = 8;                // places past the last count as the last
    static constexpr std::size_t kRecentOfKind = 4;  // per kind
    static constexpr std::size_t kRecent = 24;       // of any kind
    static std::size_t index(Kind kind);
    std::array<std::deque<double>, 2 * kPlaces> of_kind_;
    std::deque<double> recent_;
};

}  // namespace vfsd::editor
