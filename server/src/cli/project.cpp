// `trailscope project`: a 2D projection of a numeric CSV table (PCA, classical/landmark MDS, t-SNE, LAMP,
// Force Scheme) with its quality figures, as text or JSON, and the coordinates as CSV.
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>

#include "cli/commands.hpp"
#include "cli/progress_bar.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/projection/projection.hpp"
#include "trailscope/projection/quality.hpp"

namespace trailscope::cli {

void add_project(CLI::App& app) {
  auto* cmd = app.add_subcommand("project", "2D projection of a numeric CSV table, with its quality");
  cmd->footer(
      "TABLE: CSV with a header line; every column numeric (a non-numeric or NaN field is an error naming "
      "its\n"
      "line and column). Columns are z-scored first unless --no-standardize. Quality: trustworthiness,\n"
      "continuity, neighbourhood preservation (k neighbours), scale-normalised stress and Shepard "
      "correlation,\n"
      "exact up to " +
      std::to_string(limits::kMaxQualitySample) + " rows and sampled above. Limits: " +
      std::to_string(limits::kMaxProjectionRows) + " rows, " + std::to_string(limits::kMaxProjectionColumns) +
      " columns; MDS is exact up to " + std::to_string(limits::kMaxExactMdsRows) +
      " rows (landmark above); force " + "up to " + std::to_string(limits::kMaxForceSchemeRows) +
      " rows; tsne up to " + std::to_string(limits::kMaxTsneRows) + " rows.");
  struct Opts {
    std::string table, method = "pca", out, backend;
    double perplexity = 30.0;
    int iterations = 0, k = 10;
    std::uint64_t seed = 42;
    bool json = false, quiet = false, no_standardize = false;
  };
  auto o = std::make_shared<Opts>();
  cmd->add_option("TABLE", o->table, "CSV table (header + numeric rows)")->required();
  cmd->add_option("--method", o->method, "pca | mds | tsne | lamp | force")->capture_default_str();
  cmd->add_option("--perplexity", o->perplexity, "t-SNE perplexity, 1..100 (needs rows > 3·perplexity)")
      ->capture_default_str();
  cmd->add_option(
         "--iterations", o->iterations,
         "t-SNE iterations after the 250 of early exaggeration (default 750); Force Scheme iterations "
         "(default 100); 0 = default")
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "seed of every random choice")->capture_default_str();
  cmd->add_option("--k", o->k, "neighbourhood size of the quality metrics")->capture_default_str();
  cmd->add_option("-o,--out", o->out, "write the coordinates as CSV (x,y per input row)");
  cmd->add_option("--backend", o->backend, "cpu | opencl | auto (default: the process default)");
  cmd->add_flag("--no-standardize", o->no_standardize, "project the raw columns (no z-scoring)");
  cmd->add_flag("--json", o->json, "print JSON: method, timings, quality and the coordinates");
  cmd->add_flag("--quiet", o->quiet, "no progress bar");
  cmd->callback([o] {
    projection::ProjectOptions po;
    po.method = projection::parse_method(o->method, "method");
    po.backend = o->backend.empty() ? default_backend() : parse_backend(o->backend, "backend");
    po.perplexity = o->perplexity;
    po.iterations = o->iterations;
    po.seed = o->seed;
    po.standardize = !o->no_standardize;
    if (o->k < 1 || o->k > limits::kMaxQualityK)
      throw invalid_argument(
          "k", "k must be in [1, " + std::to_string(limits::kMaxQualityK) + "], not " + std::to_string(o->k));
    const projection::Table table = projection::read_table_csv(o->table, "table");
    projection::Embedding e;
    projection::Quality q;
    {
      ProgressBar bar("project", !o->quiet);
      po.progress = bar.fn();
      e = projection::project(table, po);
      bar.update(1.0, "quality");
      projection::Table seen = table;  // quality in the space the method saw
      if (po.standardize) projection::standardize(seen);
      projection::QualityOptions qo;
      qo.k = std::min<int>(o->k, static_cast<int>((table.rows - 1) / 2));
      qo.seed = o->seed;
      qo.backend = po.backend;
      q = projection::quality(seen, e.xy, qo);
    }
    if (!o->out.empty()) {
      std::ofstream out(o->out);
      if (!out) throw invalid_argument("out", "cannot write '" + o->out + "'");
      out << "x,y\n" << std::setprecision(9);
      for (std::size_t i = 0; i < e.rows; ++i) out << e.x(i) << ',' << e.y(i) << '\n';
      if (!out.flush()) throw Error(Error::Kind::internal, "out", "write to '" + o->out + "' failed");
    }
    nlohmann::json quality = {{"k", q.k},
                              {"trustworthiness", q.trustworthiness},
                              {"continuity", q.continuity},
                              {"neighborhood_preservation", q.neighborhood_preservation},
                              {"stress", q.stress},
                              {"shepard", q.shepard},
                              {"sampled", q.sampled},
                              {"queries", q.queries}};
    if (o->json) {
      nlohmann::json j = {{"method", projection::to_string(po.method)},
                          {"rows", table.rows},
                          {"columns", table.columns},
                          {"path", e.path},
                          {"variant", e.variant},
                          {"quality", quality}};
      for (const auto& [phase, ms] : e.timings_ms) j["timings_ms"][phase] = ms;
      nlohmann::json coords = nlohmann::json::array();
      for (std::size_t i = 0; i < e.rows; ++i) coords.push_back({e.x(i), e.y(i)});
      j["coordinates"] = std::move(coords);
      std::cout << json_text(j, 2) << std::endl;
      return;
    }
    std::cout << projection::to_string(po.method) << " (" << e.variant << ", " << e.path << ") of "
              << table.rows << " rows x " << table.cols << " columns\n";
    for (const auto& [phase, ms] : e.timings_ms)
      std::cout << "  " << phase << ": " << std::fixed << std::setprecision(1) << ms << " ms\n";
    std::cout << std::setprecision(4) << "quality (k = " << q.k
              << (q.sampled ? ", sampled " + std::to_string(q.queries) + " rows" : "")
              << "): trustworthiness " << q.trustworthiness << ", continuity " << q.continuity
              << ", neighbourhood preservation " << q.neighborhood_preservation << ", stress " << q.stress
              << ", Shepard " << q.shepard << "\n";
    if (!o->out.empty()) std::cout << "coordinates → " << o->out << "\n";
  });
}

}  // namespace trailscope::cli
