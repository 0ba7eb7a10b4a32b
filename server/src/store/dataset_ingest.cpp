#include "store/dataset_ingest.hpp"

#include <chrono>
#include <cmath>
#include <ctime>

#include "trailscope/ingest/ingest.hpp"

namespace trailscope::server {

std::string iso_utc(double unix_seconds) {
  const std::time_t s = static_cast<std::time_t>(std::floor(unix_seconds));
  std::tm tm{};
  gmtime_r(&s, &tm);
  char buf[32];
  std::strftime(buf, sizeof buf, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buf;
}

std::string utc_now_iso() {
  return iso_utc(static_cast<double>(std::chrono::system_clock::to_time_t(std::chrono::system_clock::now())));
}

std::shared_ptr<const Dataset> ingest_into_store(DatasetStore& store, const IngestRequest& req,
                                                 const ProgressFn& progress, const CancelToken* cancel) {
  validate_dataset_id(req.name, "name");
  if (store.contains(req.name))
    throw Error(Error::Kind::conflict, "name", "dataset '" + req.name + "' already exists");
  ingest::IngestOptions opts;
  if (req.format) opts.format = ingest::parse_format(*req.format, "format");
  // Reading and parsing take the first 97 % and the store the rest, so that the job's progress never goes
  // back (the parser reports its own 0..1).
  if (progress) opts.progress = [&progress](double f, std::string_view stage) { progress(0.97 * f, stage); };
  opts.split_jumps = req.split_jumps;
  opts.cancel = cancel;
  ingest::IngestReport report;
  TrailSet trails = ingest::ingest_file(req.file.string(), opts, &report);
  if (cancel) cancel->throw_if_cancelled();
  if (progress) progress(0.97, "store");
  auto ds = std::make_shared<Dataset>();
  ds->id = req.name;
  ds->name = req.name;
  ds->format = ingest::to_string(report.format);
  ds->created = utc_now_iso();
  ds->ingest = report.to_json();
  ds->owner = req.owner;
  ds->trails = std::make_shared<const TrailSet>(std::move(trails));
  if (req.before_write) req.before_write(*ds);
  // Writing over a network (the ClickHouse store) takes the last 3 %.
  ProgressFn store_progress;
  if (progress)
    store_progress = [&progress](double f, std::string_view) { progress(0.97 + 0.03 * f, "store"); };
  store.put(ds, store_progress);
  return ds;
}

}  // namespace trailscope::server
