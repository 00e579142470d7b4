#pragma once
// The runs run_scene made (scene/scene_run.h), as `vfsd deform`'s report and
// `vfsd battery`'s battery.json list them: each run's mesh vertices and folds.

#include <vector>

#include <nlohmann/json.hpp>

#include "scene/scene_run.h"

namespace vfsd::cli {

inline nlohmann::json runs_json(const std::vector<RunTried>& tried) {
    nlohmann::json runs = nlohmann::json::array();
    for (const RunTried& t : tried)
        runs.push_back({{"vertices", t.vertices},
                        {"folded_at_end", t.folded_at_end},
                        {"folded_over_tenths", t.folded_over_tenths}});
    return runs;
}

}  // namespace vfsd::cli
