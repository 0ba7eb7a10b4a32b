#include "jobs/ingest_job.hpp"

#include "jobs/upload_file.hpp"
#include "store/embedded_store.hpp"

namespace trailscope::server {

JobState submit_ingest(JobManager& jobs, std::shared_ptr<DatasetStore> store, IngestRequest req,
                       std::shared_ptr<DiskBudget> disk) {
  std::string name = req.name, owner = req.owner;
  return jobs.submit(
      "ingest", std::move(name),
      [store, req, disk](const ProgressFn& progress, const CancelToken& cancel) mutable {
        const UploadFile cleanup{req.file};
        std::shared_ptr<const DiskBudget::Grant> grant;  // held until the dataset is written
        if (disk)
          req.before_write = [&](const Dataset& ds) {
            grant = disk->admit(EmbeddedStore::bytes_estimate(ds), "upload", "the dataset",
                                std::to_string(ds.trails->num_points()) + " points × " +
                                    std::to_string(EmbeddedStore::kBytesPerPoint) + " bytes and " +
                                    std::to_string(ds.trails->num_flights()) + " flights × " +
                                    std::to_string(EmbeddedStore::kBytesPerFlight) + " bytes");
          };
        return ingest_into_store(*store, req, progress, &cancel)->to_json();
      },
      std::move(owner));
}

}  // namespace trailscope::server
