#include "jobs/ingest_job.hpp"

namespace trailscope::server {
namespace fs = std::filesystem;

namespace {
/// Removes the upload when the job lets go of it: after its work, or unrun when cancelled while queued.
struct UploadFile {
  fs::path path;
  ~UploadFile() {
    std::error_code ec;
    fs::remove(path, ec);
  }
};
}  // namespace

JobState submit_ingest(JobManager& jobs, std::shared_ptr<DatasetStore> store, IngestRequest req) {
  std::string name = req.name;
  return jobs.submit("ingest", std::move(name),
                     [store, req](const ProgressFn& progress, const CancelToken& cancel) {
                       const UploadFile cleanup{req.file};
                       return ingest_into_store(*store, req, progress, &cancel)->to_json();
                     });
}

}  // namespace trailscope::server
