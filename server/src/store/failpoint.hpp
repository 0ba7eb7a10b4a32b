#pragma once
// Named kill points on the write paths of the stores, for the chaos test (tests/chaos/chaos_test.sh): a
// process started with TRAILSCOPE_FAILPOINT=<name> kills itself with SIGKILL the first time it reaches the
// failpoint of that name, as a power cut or the OOM killer would, so that the test can check what a crash
// at exactly that point leaves on disk. `<name>#<n>` kills at the n-th time instead (n >= 1), e.g. the
// third atomic file replacement of a sweep. Without the variable a failpoint costs one read of a string
// fixed at start-up (the variable is read once, the first time any failpoint is reached).
//
// The names say where the process stops (the full list is in tests/chaos/chaos_test.sh, which reaches each):
//   store.stage                   a staging folder in tmp/ was just created, nothing written into it
//   store.write.column            the first column file of a staged item is written, the others are not
//   store.write.before_manifest   every column is written, the manifest (written last) is not
//   store.publish.before_rename   the staged item is whole in tmp/, not yet renamed into place
//   store.publish.after_rename    renamed into place, the parent folder not yet flushed, nobody told
//   store.remove.after_rename     a deleted item moved out to tmp/, not yet deleted
//   store.replace.before_rename   an atomically replaced file (a row, a sweep record, a token list) is
//                                 written beside its destination as *.tmp.*, not yet renamed over it;
//                                 `store.replace.before_rename:.json` only for a destination *.json
//   store.replace.after_rename    renamed over its destination, what the caller does next not done (`:.json`
//                                 as above)
//   store.row.before_row          a run's or MOT file's payload is written, its row (written last) is not
//   store.row.remove.after_row    a run's or MOT file's row is removed, its payload not yet
//   clickhouse.insert.batch       the ClickHouse store (clickhouse_store.hpp) inserted a batch of a dataset's
//                                 rows, its catalogue row not written (`#n`: the n-th batch)
//   clickhouse.before_catalogue   every row of a dataset inserted, its catalogue row (written last) not
//   (the two ClickHouse ones are reached by tests/cluster/clickhouse_store_test.cpp, not the chaos test)
//   job.progress                  a job reported progress (mid-parse of an ingest, mid-synth, mid-bundle);
//                                 `job.progress:<kind>` only for jobs of that kind (ingest, synth, ...)
#include <string_view>

namespace trailscope::server {

namespace failpoint_detail {
/// TRAILSCOPE_FAILPOINT's name part as read at the first call ("" when unset), never changed afterwards.
std::string_view armed() noexcept;
/// Counts a hit of the armed failpoint and kills the process (SIGKILL) at the chosen hit.
void hit(std::string_view name) noexcept;
}  // namespace failpoint_detail

/// Kills the process when `name` is the armed failpoint (see above); otherwise does nothing.
inline void failpoint(std::string_view name) noexcept {
  const std::string_view armed = failpoint_detail::armed();
  if (!armed.empty() && armed == name) failpoint_detail::hit(name);
}

/// The same for a failpoint with a qualifier: armed as `name` (any qualifier) or as `name:qualifier`.
inline void failpoint(std::string_view name, std::string_view qualifier) noexcept {
  const std::string_view armed = failpoint_detail::armed();
  if (armed.empty() || armed.substr(0, name.size()) != name) return;
  const std::string_view rest = armed.substr(name.size());
  if (rest.empty() || (rest.size() == qualifier.size() + 1 && rest[0] == ':' && rest.substr(1) == qualifier))
    failpoint_detail::hit(armed);
}

}  // namespace trailscope::server
