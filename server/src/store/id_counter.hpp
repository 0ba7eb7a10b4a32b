#pragma once
// The high-water mark of a family of numbered ids (a store's "g12", the jobs' "j7"), persisted so that an
// id is never handed out twice: not while the server runs, not after a restart, not after a crash. The
// mark is written to its file (temporary file, fsync, rename, fsync of the folder: column_io.hpp's
// write_file_atomic) BEFORE the number it covers is handed out, so a crash between the two loses a number
// (a gap) and never repeats one. Deleting the newest item and restarting therefore still numbers after it,
// and a client holding an id from before a restart can never see it name a different thing.
#include <cstdint>
#include <filesystem>
#include <mutex>

namespace trailscope::server {

/// The name of a store's counter file, in the store's own folder (e.g. <root>/graphs/.last_id): a name no
/// item of any store can have.
inline constexpr char kIdCounterFile[] = ".last_id";

class IdCounter {
 public:
  /// Reads the mark from `file` when it exists (0 otherwise) and removes temporary files a crash left
  /// beside it. An empty `file` keeps the mark in memory only (a server without a data folder). Throws
  /// Error(internal) when `file` exists but does not hold a number: handing out ids from a guess could
  /// repeat one.
  explicit IdCounter(std::filesystem::path file = {});
  IdCounter(const IdCounter&) = delete;
  IdCounter& operator=(const IdCounter&) = delete;

  /// Raises the mark to at least `n`: an id found on disk (written before the counter existed, or by a
  /// copy of the folder). Not persisted by itself; the next next() writes a mark above it.
  void observe(std::uint64_t n);
  /// The next number (the mark plus one, from 1), persisted before it is returned. Throws Error(internal)
  /// when the file cannot be written; the number is then not handed out. Thread-safe.
  std::uint64_t next();
  /// The last number handed out or observed (0 when none).
  std::uint64_t mark() const;
  const std::filesystem::path& file() const { return file_; }

 private:
  std::filesystem::path file_;
  mutable std::mutex mu_;
  std::uint64_t mark_ = 0;
};

}  // namespace trailscope::server
