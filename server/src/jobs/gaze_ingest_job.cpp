#include "jobs/gaze_ingest_job.hpp"

#include "jobs/upload_file.hpp"
#include "limits.hpp"
#include "params/upload_body.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::server {
namespace fs = std::filesystem;

nlohmann::json ingest_gaze_into_store(GazeStore& store, GazeIngestRequest req, const ProgressFn& progress,
                                      const CancelToken* cancel, const std::shared_ptr<DiskBudget>& disk) {
  store.check_new(req.name);
  std::error_code ec;
  const auto size = fs::file_size(req.file, ec);
  if (ec) throw not_found("file", "cannot open gaze file " + req.file.string() + ": " + ec.message());
  if (size > limits::kMaxGazeUploadBytes)
    throw Error(Error::Kind::payload_too_large, "file",
                "the gaze file is " + std::to_string(size) + " bytes, more than kMaxGazeUploadBytes (" +
                    std::to_string(limits::kMaxGazeUploadBytes) + ")");
  const std::string content = read_whole_file(req.file);
  // Parsing takes the first 97 % and the store the rest, so that the progress never goes back.
  if (progress)
    req.options.progress = [&progress](double f, std::string_view stage) { progress(0.97 * f, stage); };
  req.options.cancel = cancel;
  auto ds = std::make_shared<gaze::GazeDataset>(gaze::read_gaze(content, req.options));
  if (cancel) cancel->throw_if_cancelled();
  for (gaze::Recording& r : ds->recordings)
    if (r.participant.empty()) r.participant = req.name;
  if (progress) progress(0.97, "store");
  std::shared_ptr<const DiskBudget::Grant> grant;  // held until the dataset is written
  if (disk)
    grant = disk->admit(GazeStore::bytes_estimate(*ds), "upload", "the gaze dataset",
                        std::to_string(ds->total_samples()) + " samples × 25 bytes and their tags");
  const std::string format = ds->recordings.empty() ? "" : ds->recordings.front().format;
  const nlohmann::json m = store.put(req.name, req.owner, format, ds);
  return {{"gaze", req.name}, {"recordings", m.at("recordings")}, {"samples", m.at("samples")}};
}

JobState submit_gaze_ingest(JobManager& jobs, std::shared_ptr<GazeStore> store, GazeIngestRequest req,
                            std::shared_ptr<DiskBudget> disk) {
  std::string name = req.name, owner = req.owner;
  auto cleanup = std::make_shared<UploadFile>();  // (not from a temporary, whose end would remove it)
  cleanup->path = req.file;
  return jobs.submit(
      "gaze_ingest", std::move(name),
      [store, req, disk, cleanup](const ProgressFn& progress, const CancelToken& cancel) mutable {
        const auto done = std::move(cleanup);  // the upload goes when this run ends
        return ingest_gaze_into_store(*store, req, progress, &cancel, disk);
      },
      std::move(owner));
}

}  // namespace trailscope::server
