// Damaged input never crashes or hangs the ingest: every real sample file, truncated and with bytes
// flipped at random (fixed seeds), either ingests or throws a trailscope::Error with a message.
#include <random>

#include "ingest_test_helpers.hpp"
#include "trailscope/ingest/ingest.hpp"

namespace trailscope::test {
namespace {

struct Sample {
  const char* file;
  std::size_t prefix;  ///< bytes of the decompressed file to mutate (keeps the test fast)
};

const Sample kSamples[] = {
    {"flights/traffic_europe_20180101_m3.so6.gz", 200000},
    {"flights/traffic_sample_belevingsvlucht.json.gz", 200000},
    {"flights/traffic_sample_zurich_airport.json.gz", 200000},
    {"flights/traffic_sample_trace_full_ac671b.json", 200000},
};

// Runs the ingest; true when it returned, false when it threw a trailscope::Error. Anything else fails.
bool ingest_or_error(const std::filesystem::path& p) {
  try {
    ingest::ingest_file(p.string());
    return true;
  } catch (const Error& e) {
    EXPECT_GT(std::string(e.what()).size(), 10u) << "an error must say what is wrong";
    return false;
  } catch (const std::exception& e) {
    ADD_FAILURE() << p << ": not a trailscope::Error: " << e.what();
    return false;
  }
}

TEST(IngestRobustness, TruncatedAndCorruptedFilesGiveErrorsNotCrashes) {
  TempDir tmp;
  std::mt19937_64 rng(20261122);
  for (const Sample& s : kSamples) {
    const std::string text = read_all(shared_data(s.file)).substr(0, s.prefix);
    for (int round = 0; round < 12; ++round) {
      std::string damaged = text;
      switch (round % 3) {
        case 0:  // cut anywhere, even inside a number or a JSON string
          damaged.resize(std::uniform_int_distribution<std::size_t>(0, damaged.size())(rng));
          break;
        case 1:  // flip a few hundred bytes to random values, NULs included
          for (int k = 0; k < 300 && !damaged.empty(); ++k)
            damaged[std::uniform_int_distribution<std::size_t>(0, damaged.size() - 1)(rng)] =
                static_cast<char>(rng() & 0xff);
          break;
        case 2:  // overwrite a run with digits and separators (plausible-looking garbage)
          for (std::size_t k = damaged.size() / 3; k < damaged.size() / 3 + 2000 && k < damaged.size(); ++k)
            damaged[k] = "0123456789.,- \n:[]{}\""[rng() % 22];
          break;
      }
      const auto path = tmp.path() / ("damaged-" + std::to_string(round));
      write_text(path, damaged);
      ingest_or_error(path);
      // The same damage behind gzip, and a gzip stream cut short.
      const auto gz = tmp.path() / ("damaged-" + std::to_string(round) + ".gz");
      write_gz(gz, damaged);
      ingest_or_error(gz);
      std::string raw = read_raw(gz);
      raw.resize(raw.size() / 2);
      write_text(gz, raw);
      ingest_or_error(gz);
    }
  }
}

}  // namespace
}  // namespace trailscope::test
