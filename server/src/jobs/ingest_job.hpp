#pragma once
// The ingest job of POST /api/v1/datasets: one uploaded file into the dataset store (ingest_into_store,
// store/dataset_ingest.hpp, the same step `trailscope ingest` takes without a job).
#include <memory>

#include "jobs/disk_budget.hpp"
#include "jobs/job_manager.hpp"
#include "store/dataset_ingest.hpp"

namespace trailscope::server {

/// Queues a job "ingest" of req.owner (JobState::dataset = the new dataset's name) that ingests `req` into
/// `store` and removes req.file afterwards, whatever the outcome (a job cancelled while queued removes it
/// too). Once the file is parsed, the dataset's bytes (EmbeddedStore::bytes_estimate) are granted by
/// `disk` before anything is written (the job fails with 507 and the numbers otherwise). The job's result
/// is the dataset's JSON.
JobState submit_ingest(JobManager& jobs, std::shared_ptr<DatasetStore> store, IngestRequest req,
                       std::shared_ptr<DiskBudget> disk = nullptr);

}  // namespace trailscope::server
