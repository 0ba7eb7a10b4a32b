#pragma once
// The disk budget of the jobs that write (synthetic videos, ingest, bundles, tracker runs): before a job
// writes it is granted the bytes it estimates it will write, and refused up front (507,
// Error::Kind::insufficient_storage, the numbers in the detail) when that is more than one job may write
// (limits::kMaxJobWriteBytes) or more than the disk has free once limits::kDiskReserveBytes are kept back
// and the grants of other jobs still writing are counted; while it writes, the job checks the bytes written
// against its grant and the free space against the reserve, and stops cleanly when either runs out (the
// stores stage every item in tmp/ and rename it into place, so a stopped write leaves nothing partial).
// Thread-safe.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <mutex>
#include <string>

#include "limits.hpp"

namespace trailscope::server {

class DiskBudget : public std::enable_shared_from_this<DiskBudget> {
 public:
  /// Bytes available to the server on the file system it writes to.
  using FreeSpace = std::function<std::uint64_t()>;

  /// What one job was granted; given back when destroyed (when the job lets go of it).
  class Grant {
   public:
    ~Grant();
    Grant(const Grant&) = delete;
    Grant& operator=(const Grant&) = delete;
    std::uint64_t bytes() const { return bytes_; }
    /// Throws Error(insufficient_storage, param) when `written` (bytes this job has written so far) is more
    /// than its grant, or when the disk's free space has fallen below limits::kDiskReserveBytes (something
    /// else filled it meanwhile).
    void check(std::uint64_t written) const;

   private:
    friend class DiskBudget;
    Grant(std::shared_ptr<DiskBudget> budget, std::uint64_t bytes, std::string param)
        : budget_(std::move(budget)), bytes_(bytes), param_(std::move(param)) {}
    std::shared_ptr<DiskBudget> budget_;
    std::uint64_t bytes_;
    std::string param_;
  };

  /// A budget over the file system of `dir` (the data folder), keeping `reserve` bytes free and granting
  /// one job at most `cap` bytes; `free_space` measures the free bytes (default: what
  /// std::filesystem::space(dir) says is available; tests pass their own).
  static std::shared_ptr<DiskBudget> open(std::filesystem::path dir,
                                          std::uint64_t reserve = limits::kDiskReserveBytes,
                                          std::uint64_t cap = limits::kMaxJobWriteBytes,
                                          FreeSpace free_space = {});

  /// Grants `bytes` to a job about to write `what` (e.g. "the video"), `how` saying where the estimate comes
  /// from (e.g. "100000 frames × 1024 × 1024 px × 4 bytes"). Throws Error(insufficient_storage, param) with
  /// the numbers when `bytes` is over the cap or over the free space less the reserve and the other grants.
  std::shared_ptr<const Grant> admit(std::uint64_t bytes, const std::string& param, const std::string& what,
                                     const std::string& how);
  std::uint64_t reserve() const { return reserve_; }
  std::uint64_t cap() const { return cap_; }
  /// Bytes granted to jobs still holding their grants.
  std::uint64_t granted() const;
  std::uint64_t free_space() const;

 private:
  DiskBudget(std::filesystem::path dir, std::uint64_t reserve, std::uint64_t cap, FreeSpace free_space);
  void give_back(std::uint64_t bytes);

  const std::filesystem::path dir_;
  const std::uint64_t reserve_, cap_;
  const FreeSpace free_space_;
  mutable std::mutex mu_;
  std::uint64_t granted_ = 0;
};

}  // namespace trailscope::server
