#include <cstdlib>

#include "cli/commands.hpp"

namespace trailscope::cli {

std::string default_data_dir() {
  const char* v = std::getenv("TRAILSCOPE_DATA_DIR");
  return v && *v ? v : "data";
}

void QueryFlags::add_to(CLI::App& cmd) {
  // Each flag writes straight into the parameter map under the REST API's name.
  const auto flag = [&](const std::string& name, const std::string& key, const std::string& help) {
    cmd.add_option_function<std::string>(
        name, [this, key](const std::string& v) { params[key] = v; }, help);
  };
  flag("--bbox", "bbox", "west,south,east,north in degrees");
  flag("--t0", "t0", "window start (Unix seconds or ISO 8601), inclusive");
  flag("--t1", "t1", "window end (Unix seconds or ISO 8601), exclusive");
  flag("--alt-min", "alt_min", "lowest altitude (in --alt-unit)");
  flag("--alt-max", "alt_max", "highest altitude (in --alt-unit)");
  flag("--alt-unit", "alt_unit", "ft (default) or m");
  flag("--icao24", "icao24", "comma-separated 24-bit addresses (hex)");
  flag("--callsign", "callsign", "callsign prefix, or a pattern with * and ?");
  flag("--on-ground", "on_ground", "true or false");
}

}  // namespace trailscope::cli
