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
#include "trailscope/projection/report.hpp"

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
         "t-SNE iterations after the 250 of early exaggeration (default 500); Force Scheme iterations "
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
    const projection::Table table = projection::read_table_csv(o->table, "table");
    projection::ProjectionReport r;
    {
      ProgressBar bar("project", !o->quiet);
      po.progress = bar.fn();
      r = projection::project_with_quality(table, po, o->k);
    }
    const projection::Embedding& e = r.embedding;
    const projection::Quality& q = r.quality;
    if (!o->out.empty()) {
      std::ofstream out(o->out);
      if (!out) throw invalid_argument("out", "cannot write '" + o->out + "'");
      out << "x,y\n" << std::setprecision(9);
      for (std::size_t i = 0; i < e.rows; ++i) out << e.x(i) << ',' << e.y(i) << '\n';
      if (!out.flush()) throw Error(Error::Kind::internal, "out", "write to '" + o->out + "' failed");
    }
    if (o->json) {
      std::cout << json_text(projection::to_json(r), 2) << std::endl;
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
