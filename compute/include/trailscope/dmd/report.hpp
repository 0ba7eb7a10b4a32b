#pragma once
// JSON of a DMD run, for the CLI's --json and for the service.
#include <nlohmann/json.hpp>

#include "trailscope/dmd/dmd.hpp"

namespace trailscope::dmd {

/// {"params", "levels", "layers": [...], "skeleton_pixels", "medial_axis_pixels", "times_ms": {...},
/// "segments": [...]}. Times in ms, coordinates in px, levels in grey values.
nlohmann::json to_json(const DmdResult& result, const DmdParams& params);

}  // namespace trailscope::dmd
