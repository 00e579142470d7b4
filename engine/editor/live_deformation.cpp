#include "editor/live_deformation.h"

#include <algorithm>

namespace vfsd::editor {
namespace {

class CpuDeformation final : public LiveDeformation {
public:
    explicit CpuDeformation(const PreparedScene& scene) : deformation_(scene.start_deformation()) {}
    int advance(double target, int max_steps) override { return deformation_.advance(target, max_steps); }
    double time() const override { return deformation_.time(); }
    const std::vector<Vec3>& positions() const override { return deformation_.positions(); }
    double ms_per_step() const override {
        // Median of the last 32 steps: robust to a slow first step.
        const auto& ms = deformation_.step_milliseconds();
        if (ms.empty()) return 0.0;
        std::vector<double> recent(ms.end() - std::min<std::ptrdiff_t>(32, ms.size()), ms.end());
        std::nth_element(recent.begin(), recent.begin() + recent.size() / 2, recent.end());
        return recent[recent.size() / 2];
    }
    std::string backend() const override { return "cpu"; }

private:
    Deformation deformation_;
};

}  // namespace

std::unique_ptr<LiveDeformation> make_cpu_deformation(const PreparedScene& scene) {
    return std::make_unique<CpuDeformation>(scene);
}

}  // namespace vfsd::editor
