#pragma once
// The ingest job of POST /api/v1/datasets: one uploaded file into the dataset store (ingest_into_store,
// store/dataset_ingest.hpp, the same step `trailscope ingest` takes without a job).
#include <memory>

#include "jobs/job_manager.hpp"
#include "store/dataset_ingest.hpp"

namespace trailscope::server {

/// Queues a job "ingest" (JobState::dataset = the new dataset's name) that ingests `req` into `store` and
/// removes req.file afterwards, whatever the outcome (a job cancelled while queued removes it too). The
/// job's result is the dataset's JSON.
JobState submit_ingest(JobManager& jobs, std::shared_ptr<DatasetStore> store, IngestRequest req);

}  // namespace trailscope::server
