#pragma once
// One description of a tunable parameter, shared by every op that has a parameter table (bundling,
// DMD, the tracker): what the CLI's --help, the API's parameter lists and the dashboards' panels show.
// Each op builds its table next to its parameter struct (bundling/params.hpp, dmd/dmd.hpp,
// tracker/params.hpp) and keeps its own setters and messages; this type is only the description.
#include <string>
#include <utility>

namespace trailscope {

struct ParamInfo {
  std::string name;           ///< e.g. "smooth_kernel" (the CLI flag is --smooth-kernel)
  std::string type;           ///< "number", "integer", "boolean" or "enum"
  std::string default_value;  ///< the default as text: "0.05", "15", "true", "weighted"
  std::string range;          ///< the allowed values as text, with the unit: "[0, 2] px", "true, false"
  std::string help;           ///< one line
  // A numeric parameter (number or integer) also has its range and default as numbers; the tracker's
  // parameters are all numeric and its API and CLI show these fields.
  std::string unit;           ///< "mm", "px", "frames", or "" (unitless)
  double default_number = 0;  ///< the default as a number
  double min = 0, max = 0;    ///< inclusive range
  bool integer = false;       ///< whole values only
};

/// A description with its text fields set (numeric fields are then set by the caller where they apply).
inline ParamInfo describe_param(std::string name, std::string type, std::string default_value,
                                std::string range, std::string help) {
  ParamInfo i;
  i.name = std::move(name), i.type = std::move(type), i.default_value = std::move(default_value);
  i.range = std::move(range), i.help = std::move(help);
  return i;
}

}  // namespace trailscope
