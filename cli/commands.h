#pragma once
// The subcommands of the vfsd CLI and the small argument parser they share.

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "curve/bezier_curve.h"
#include "deform/deformation.h"

namespace vfsd::cli {

constexpr int kExitOk = 0;
constexpr int kExitInput = 1;
constexpr int kExitUsage = 2;

struct UsageError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// Positional arguments and --name value / --flag options, parsed against the
// options a command declares.
class Args {
public:
    Args(const char* command, int argc, char** argv);
    bool wants_help() const { return help_; }
    // The i-th positional argument; throws UsageError naming `what` when missing.
    const std::string& positional(std::size_t i, const char* what) const;
    std::size_t positional_count() const { return positional_.size(); }
    bool has(const std::string& option) const { return options_.count(option) > 0; }
    std::string get(const std::string& option, const std::string& fallback = "") const;
    double get_number(const std::string& option, double fallback) const;
    // Throws UsageError for any option not in `known`, and when the number of
    // positionals is outside [min_positional, max_positional].
    void expect(const std::vector<std::string>& known, std::size_t min_positional, std::size_t max_positional) const;

private:
    bool help_ = false;
    std::vector<std::string> positional_;
    std::map<std::string, std::string> options_;
};

struct Command {
    const char* name;
    const char* summary;
    const char* help;
    int (*run)(const Args&);
};

const std::vector<Command>& commands();

int run_info(const Args& args);
int run_convert(const Args& args);
int run_deform(const Args& args);
int run_scene_keys(const Args& args);
int run_render(const Args& args);
int run_bench(const Args& args);
int run_battery(const Args& args);
int run_picking_bench(const Args& args);  // vfsd bench --picking
int run_latency_bench(const Args& args);  // vfsd bench --latency
int run_gpu_schemes_bench(const Args& args);  // vfsd bench --gpu-schemes
int run_fold_tests_bench(const Args& args);   // vfsd bench --fold-tests

// vfsd bench's deformation of a mesh: the top 15 % of its longest axis bent by
// about 45° (s = 0 there, 1 on the bottom 40 %, linear between).
void bench_region_and_curve(const TriangleMesh& mesh, Region& region, BezierCurve& curve);

// The paper-figure scenes the benches time (assets/scenes/: fig. 11's arm, the
// raised claw, figs. 14 and 13) whose meshes are here; each one missing is said
// on stdout.
std::vector<std::string> paper_scene_files();

// --threads N (a positive integer), if given: the thread pool's limit.
void apply_threads_option(const Args& args);

// The middle value (the upper one of an even count); 0 for none.
double median(std::vector<double> values);

}  // namespace vfsd::cli
