// Serialisation of congestion counts: the one JSON and CSV shape that the REST API and the CLI print.
#include <string>

#include "trailscope/congestion/counts.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/core/text.hpp"

namespace trailscope::congestion {

namespace {

nlohmann::json optional_number(const std::optional<double>& v) {
  return v ? number_or_null(*v) : nlohmann::json(nullptr);
}

nlohmann::json complexity_fields(const ComplexityCell& c) {
  return {{"flight_hours", c.flight_hours},
          {"interaction_hours", c.interaction_hours},
          {"horizontal_hours", c.horizontal_hours},
          {"vertical_hours", c.vertical_hours},
          {"speed_hours", c.speed_hours},
          {"adjusted_density", number_or_null(c.adjusted_density())},
          {"structural_index", number_or_null(c.structural_index())},
          {"score", number_or_null(c.score())}};
}

// A CSV field: quoted when it holds a comma, a quote or a line break (RFC 4180).
std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\r\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

}  // namespace

nlohmann::json CountsResult::to_json() const {
  nlohmann::json vols = nlohmann::json::array();
  for (const VolumeResult& v : volumes) {
    vols.push_back({{"id", v.id},
                    {"kind", v.is_cell ? "cell" : "sector"},
                    {"south", v.bounds.south},
                    {"north", v.bounds.north},
                    {"west", v.bounds.west},
                    {"east", v.bounds.east},
                    {"lower_m", v.bounds.lower_m},
                    {"upper_m", v.bounds.upper_m},
                    {"peak", optional_number(v.peak)},
                    {"sustained", optional_number(v.sustained)},
                    {"max_occupancy", v.occupancy.max()},
                    {"total_entries", v.entries.sum()},
                    {"occupancy", {{"step", v.occupancy.index}, {"count", v.occupancy.value}}},
                    {"entries", {{"window", v.entries.index}, {"count", v.entries.value}}}});
  }
  nlohmann::json hs = nlohmann::json::array();
  for (const Hotspot& h : hotspots) {
    nlohmann::json fl = nlohmann::json::array();
    for (const auto& f : h.flights)
      fl.push_back({{"id", f.id}, {"callsign", f.callsign}, {"icao24", f.icao24}});
    hs.push_back({{"volume", volumes[h.volume].id},
                  {"kind", to_string(h.kind)},
                  {"first_step", h.first_step},
                  {"last_step", h.last_step},
                  {"start", h.start},
                  {"end", h.end},
                  {"peak", h.peak},
                  {"peak_time", h.peak_time},
                  {"threshold", h.threshold},
                  {"excess", h.excess},
                  {"flights", std::move(fl)}});
  }
  nlohmann::json cx = nullptr;
  if (has_complexity) {
    nlohmann::json cells = nlohmann::json::array();
    for (const ComplexityCell& c : complexity) {
      nlohmann::json j = {
          {"volume", volumes[c.volume].id}, {"hour", c.hour}, {"start", t0 + 3600.0 * c.hour}};
      j.update(complexity_fields(c));
      cells.push_back(std::move(j));
    }
    cx = {{"heading_deg", complexity_params.heading_deg},
          {"speed_kt", complexity_params.speed_kt},
          {"vrate_fpm", complexity_params.vrate_fpm},
          {"cells", std::move(cells)},
          {"total", complexity_fields(complexity_total)}};
  }
  return {{"t0", t0},
          {"t1", t1},
          {"step", step_s},
          {"duration", duration_s},
          {"method", to_string(method)},
          {"entry_window", entry_window_s},
          {"entry_step", entry_step_s},
          {"volumes_kind", grid ? "grid" : "sectors"},
          {"steps", steps},
          {"entry_windows", entry_windows},
          {"hours", hours},
          {"flights", flights},
          {"volumes", std::move(vols)},
          {"hotspots", std::move(hs)},
          {"hotspots_total", hotspots_total},
          {"complexity", std::move(cx)}};
}

void CountsResult::write_csv(std::ostream& out) const {
  std::string line;
  out << "volume,series,index,start,end,value\n";
  for (const VolumeResult& v : volumes) {
    const std::string id = csv_field(v.id);
    for (int series = 0; series < 2; ++series) {
      const Series& s = series == 0 ? v.occupancy : v.entries;
      for (std::size_t i = 0; i < s.index.size(); ++i) {
        const std::uint32_t k = s.index[i];
        const double start = series == 0 ? step_start(k) : window_start(k);
        const double len = series == 0 ? duration_s : entry_window_s;
        line.clear();
        line += id;
        line += series == 0 ? ",occupancy," : ",entries,";
        line += std::to_string(k);
        line += ',';
        append_shortest(line, start);
        line += ',';
        append_shortest(line, std::min(start + len, t1));
        line += ',';
        line += std::to_string(s.value[i]);
        line += '\n';
        out << line;
      }
    }
  }
}

void CountsResult::write_hotspots_csv(std::ostream& out) const {
  out << "volume,kind,first_step,last_step,start,end,peak,peak_time,threshold,excess,flights\n";
  for (const Hotspot& h : hotspots) {
    std::string line = csv_field(volumes[h.volume].id) + "," + to_string(h.kind) + "," +
                       std::to_string(h.first_step) + "," + std::to_string(h.last_step) + ",";
    append_shortest(line, h.start);
    line += ',';
    append_shortest(line, h.end);
    line += "," + std::to_string(h.peak) + ",";
    append_shortest(line, h.peak_time);
    line += ',';
    append_shortest(line, h.threshold);
    line += ',';
    append_shortest(line, h.excess);
    line += ',';
    for (std::size_t i = 0; i < h.flights.size(); ++i) {
      if (i) line += ' ';
      line += std::to_string(h.flights[i].id);
    }
    out << line << '\n';
  }
}

void CountsResult::write_complexity_csv(std::ostream& out) const {
  out << "volume,hour,start,flight_hours,interaction_hours,horizontal_hours,vertical_hours,speed_hours,"
         "adjusted_density,structural_index,score\n";
  for (const ComplexityCell& c : complexity) {
    std::string line = csv_field(volumes[c.volume].id) + "," + std::to_string(c.hour) + ",";
    for (double v :
         {t0 + 3600.0 * c.hour, c.flight_hours, c.interaction_hours, c.horizontal_hours, c.vertical_hours,
          c.speed_hours, c.adjusted_density(), c.structural_index(), c.score()}) {
      append_shortest(line, v);
      line += ',';
    }
    line.back() = '\n';
    out << line;
  }
}

}  // namespace trailscope::congestion
