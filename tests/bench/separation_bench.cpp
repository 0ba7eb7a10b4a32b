// All-pairs losses of separation over the Europe SO6 day: trailscope::congestion::losses_of_separation()
// on the whole day (5 NM / 1,000 ft, 2,000 ft above FL410), repeated; the median run against the 5 s
// target on this machine's cores.
//
//   separation_bench --file PATH.so6.gz [--reps 5]
//       one record {"bench":"separation", "label", "flights", "points", "window_s", "events", "pairs_tested",
//       "candidate_pairs", "pairs_with_events", "s_min", "s_p50", "s_max", "reps", "threads", "peak_rss_mib"}
#include <thread>

#include "bench_util.hpp"
#include "trailscope/congestion/separation.hpp"
#include "trailscope/ingest/ingest.hpp"

using namespace bench;

int main(int argc, char** argv) {
  try {
    const Args a(argc, argv);
    const std::string path = a.get("file");
    if (path.empty()) throw std::invalid_argument("--file PATH.so6.gz is required");
    const int reps = static_cast<int>(a.num("reps", 5));
    const trailscope::TrailSet set = trailscope::ingest::ingest_file(path);
    // The whole data: from the first sample to just past the last.
    trailscope::Query q;
    q.t0 = std::floor(set.t_min());
    q.t1 = std::floor(set.t_max()) + 1;
    trailscope::congestion::SeparationResult first = trailscope::congestion::losses_of_separation(set, q);
    std::vector<double> ms;
    for (int r = 0; r < reps; ++r) {
      const auto t0 = Clock::now();
      const trailscope::congestion::SeparationResult res =
          trailscope::congestion::losses_of_separation(set, q);
      ms.push_back(ms_since(t0));
      if (res.events.size() != first.events.size()) throw std::runtime_error("separation not deterministic");
      log("separation run " + std::to_string(r + 1) + ": " + std::to_string(ms.back()) + " ms");
    }
    const Stats st = Stats::of(ms);
    emit({{"bench", "separation"},
          {"label", "so6_europe_day"},
          {"flights", set.num_flights()},
          {"points", set.num_points()},
          {"window_s", *q.t1 - *q.t0},
          {"events", first.events.size()},
          {"pairs_with_events", first.pairs_with_events},
          {"pairs_tested", first.pairs_tested},
          {"candidate_pairs", first.candidate_pairs},
          {"s_min", st.min / 1000.0},
          {"s_p50", st.p50 / 1000.0},
          {"s_max", st.max / 1000.0},
          {"reps", reps},
          {"threads", std::thread::hardware_concurrency()},
          {"peak_rss_mib", std::round(peak_rss_mib())}});
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "separation_bench: " << e.what() << "\n";
    return 1;
  }
}
