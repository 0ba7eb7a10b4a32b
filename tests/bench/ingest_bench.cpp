// Ingest throughput: trailscope::ingest::ingest_file() on a file, repeated, rows/s from the median run.
//
//   ingest_bench --file PATH [--label NAME] [--reps 3]
//       one record {"bench":"ingest", "label", "file", "bytes", "format", "rows", "points", ...,
//       "s_p50", "rows_per_s_p50", "parse_s_p50", "assemble_s_p50", ...}
//   ingest_bench --make-csv OUT.csv[.gz] --flights N [--seed 42] [--demo-source DIR]
//       generates the demo day and writes it as an OpenSky state-vector CSV (the benchmark input);
//       one record {"bench":"make_csv", "rows", "bytes", "generate_s", "write_s"}
//
// The parse/assemble split comes from the progress callback: ingest reports ("assemble", 0) when the
// parser is done and the TrailSet is being built (sort by aircraft and time, gap split, Mercator columns).
#include <filesystem>

#include "bench_util.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/ingest/ingest.hpp"
#include "trailscope/ingest/opensky_csv_writer.hpp"

namespace fs = std::filesystem;
using namespace bench;

static int make_csv(const Args& a) {
  const std::string out = a.get("make-csv");
  const auto flights = static_cast<std::size_t>(a.num("flights", 7000));
  double gen_s = 0;
  const trailscope::TrailSet set =
      generate_demo(demo_source(a), flights, static_cast<std::uint64_t>(a.num("seed", 42)), &gen_s);
  const bool gz = out.size() > 3 && out.compare(out.size() - 3, 3, ".gz") == 0;
  const auto t0 = Clock::now();
  trailscope::ingest::write_opensky_csv(set, out, gz);
  const double write_s = ms_since(t0) / 1000.0;
  emit({{"bench", "make_csv"},
        {"file", out},
        {"gzip", gz},
        {"flights", set.num_flights()},
        {"rows", set.num_points()},
        {"bytes", fs::file_size(out)},
        {"generate_s", gen_s},
        {"write_s", write_s}});
  log("wrote " + std::to_string(set.num_points()) + " rows to " + out + " in " + std::to_string(write_s) +
      " s");
  return 0;
}

static int ingest(const Args& a) {
  const std::string path = a.get("file");
  const int reps = static_cast<int>(a.num("reps", 3));
  std::vector<double> total, parse, assemble;
  trailscope::ingest::IngestReport rep;
  for (int r = 0; r < reps; ++r) {
    Clock::time_point start, parsed;
    bool seen_assemble = false;
    trailscope::ingest::IngestOptions opts;
    opts.progress = [&](double, std::string_view stage) {
      if (!seen_assemble && stage == "assemble") seen_assemble = true, parsed = Clock::now();
    };
    start = Clock::now();
    trailscope::TrailSet set = trailscope::ingest::ingest_file(path, opts, &rep);
    const auto end = Clock::now();
    total.push_back(ms_between(start, end) / 1000.0);
    if (seen_assemble)
      parse.push_back(ms_between(start, parsed) / 1000.0),
          assemble.push_back(ms_between(parsed, end) / 1000.0);
    log("ingest " + path + " run " + std::to_string(r + 1) + "/" + std::to_string(reps) + ": " +
        std::to_string(rep.rows) + " rows in " + std::to_string(total.back()) + " s");
  }
  const Stats s = Stats::of(total);
  json rec = {{"bench", "ingest"},
              {"label", a.get("label", fs::path(path).filename().string())},
              {"file", path},
              {"bytes", fs::file_size(path)},
              {"format", rep.to_json()["format"]},
              {"rows", rep.rows},
              {"accepted", rep.accepted},
              {"rejected", rep.rejected},
              {"duplicates", rep.duplicates},
              {"flights", rep.flights},
              {"points", rep.points},
              {"reps", reps}};
  s.put(rec, "s_");
  rec["rows_per_s_p50"] = std::round(static_cast<double>(rep.rows) / s.p50);
  rec["rows_per_s_best"] = std::round(static_cast<double>(rep.rows) / s.min);
  rec["points_per_s_p50"] = std::round(static_cast<double>(rep.points) / s.p50);
  rec["mb_per_s_p50"] = std::round(static_cast<double>(fs::file_size(path)) / 1e6 / s.p50 * 10) / 10;
  if (!parse.empty()) {
    rec["parse_s_p50"] = std::round(Stats::of(parse).p50 * 1000) / 1000;
    rec["assemble_s_p50"] = std::round(Stats::of(assemble).p50 * 1000) / 1000;
  }
  rec["peak_rss_mib"] = std::round(peak_rss_mib());
  emit(rec);
  return 0;
}

int main(int argc, char** argv) {
  try {
    const Args a(argc, argv);
    if (a.has("make-csv")) return make_csv(a);
    if (a.has("file")) return ingest(a);
    std::cerr << "usage: ingest_bench --file PATH [--label NAME] [--reps N]\n"
                 "       ingest_bench --make-csv OUT.csv[.gz] --flights N [--seed S] [--demo-source DIR]\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "ingest_bench: " << e.what() << "\n";
    return 1;
  }
}
