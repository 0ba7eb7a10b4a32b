// ingest_file() and ingest_bytes(): open, detect, dispatch to the reader, build the TrailSet, fill the
// report.
#include "trailscope/ingest/ingest.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "ingest/detail.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::ingest {

nlohmann::json IngestReport::to_json() const {
  nlohmann::json list = nlohmann::json::array();
  for (const Reject& r : rejects) list.push_back({{"line", r.line}, {"reason", r.reason}});
  return {{"format", to_string(format)},
          {"rows", rows},
          {"accepted", accepted},
          {"rejected", rejected},
          {"duplicates", duplicates},
          {"flights", flights},
          {"points", points},
          {"rejects", std::move(list)},
          {"seconds", seconds},
          {"quality", [&] {
             nlohmann::json q = quality.to_json();
             nlohmann::json ex = nlohmann::json::array();
             for (const auto& e : jump_splits.examples)
               ex.push_back({{"flight_id", e.flight_id},
                             {"callsign", e.callsign},
                             {"t", e.t},
                             {"value", e.value},
                             {"value_kt", e.value / kKnot}});
             q["jump_splits"] = {{"count", jump_splits.count}, {"examples", std::move(ex)}};
             nlohmann::json legs = nlohmann::json::array();
             for (const auto& e : leg_splits.examples)
               legs.push_back({{"flight_id", e.flight_id},
                               {"callsign", e.callsign},
                               {"t", e.t},
                               {"value", e.value},
                               {"value_h", e.value / 3600}});
             q["leg_splits"] = {{"count", leg_splits.count}, {"examples", std::move(legs)}};
             return q;
           }()}};
}

namespace {

// The splits with the largest values (implied speed, or gap), each named by the flight that starts after it
// (the flight of that aircraft whose first sample is the split's).
QualityCount jump_split_report(const TrailSet& set, std::vector<TrailSetBuilder::Stats::Jump> jumps) {
  QualityCount out;
  out.count = jumps.size();
  std::sort(jumps.begin(), jumps.end(), [](const auto& a, const auto& b) {
    return a.speed_ms != b.speed_ms ? a.speed_ms > b.speed_ms : a.t < b.t;
  });
  if (jumps.size() > kQualityExamples) jumps.resize(kQualityExamples);
  for (const auto& j : jumps) {
    QualityExample e;
    e.callsign = j.callsign, e.t = j.t, e.value = j.speed_ms;
    for (std::size_t fi = 0; fi < set.num_flights(); ++fi) {
      const Flight& f = set.flights()[fi];
      if (f.t_min == j.t && f.callsign == j.callsign && f.icao24 == j.icao24) {
        e.flight_id = static_cast<std::uint32_t>(fi);
        break;
      }
    }
    out.examples.push_back(std::move(e));
  }
  return out;
}

void check_options(const IngestOptions& opts) {
  if (!(opts.gap_seconds > 0))
    throw invalid_argument("gap_seconds",
                           "gap_seconds must be > 0 (seconds), got " + std::to_string(opts.gap_seconds));
  if (opts.cancel) opts.cancel->throw_if_cancelled();
}

// Both entry points: detect, dispatch to the reader, build the TrailSet, fill the report.
TrailSet ingest_source(detail::ByteSource& src, const IngestOptions& opts, IngestReport* report,
                       std::chrono::steady_clock::time_point start) {
  const std::string& path = src.path();
  IngestReport rep;
  rep.format = opts.format ? *opts.format : detect_format(src.head());
  TrailSetBuilder builder;
  detail::ReadContext ctx(src, builder, rep, opts);
  switch (rep.format) {
    case Format::opensky_csv:
      detail::read_opensky_csv(ctx);
      break;
    case Format::traffic_json:
      detail::read_traffic_json(ctx);
      break;
    case Format::so6:
      detail::read_so6(ctx);
      break;
    case Format::readsb_trace:
      detail::read_readsb_trace(ctx);
      break;
  }
  if (opts.cancel) opts.cancel->throw_if_cancelled();
  if (opts.progress) opts.progress(1.0, "parse");

  if (rep.rows == 0)
    throw Error(Error::Kind::unprocessable, "file",
                std::string("no data rows in '") + path + "' (read as " + to_string(rep.format) + ")");
  if (rep.accepted == 0) {
    std::string msg = "no valid rows: all " + std::to_string(rep.rows) + " rows of '" + path + "' (read as " +
                      to_string(rep.format) + ") were rejected";
    for (std::size_t i = 0; i < rep.rejects.size() && i < 3; ++i)
      msg += std::string(i ? "; " : ": ") + "line " + std::to_string(rep.rejects[i].line) + ": " +
             rep.rejects[i].reason;
    throw Error(Error::Kind::unprocessable, "file", msg);
  }

  if (opts.progress) opts.progress(0.0, "assemble");
  TrailSetBuilder::Stats stats;
  TrailSet set = builder.build(&stats, ctx.gap_seconds, opts.split_jumps.value_or(true));
  if (opts.cancel) opts.cancel->throw_if_cancelled();
  if (opts.progress) opts.progress(1.0, "assemble");

  rep.duplicates = stats.duplicates + ctx.reader_duplicates;
  rep.flights = set.num_flights();
  rep.points = set.num_points();
  rep.quality = check_quality(set, Query{});
  rep.jump_splits = jump_split_report(set, stats.jumps);
  rep.leg_splits = jump_split_report(set, stats.legs);
  rep.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (report) *report = std::move(rep);
  return set;
}

}  // namespace

TrailSet ingest_file(const std::string& path, const IngestOptions& opts, IngestReport* report) {
  const auto start = std::chrono::steady_clock::now();
  check_options(opts);
  detail::ByteSource src(path);
  return ingest_source(src, opts, report, start);
}

TrailSet ingest_bytes(std::string_view bytes, const std::string& name, const IngestOptions& opts,
                      IngestReport* report) {
  const auto start = std::chrono::steady_clock::now();
  check_options(opts);
  detail::ByteSource src(bytes, name);
  return ingest_source(src, opts, report, start);
}

}  // namespace trailscope::ingest
