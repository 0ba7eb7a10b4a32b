#include "jobs/disk_budget.hpp"

#include <algorithm>

#include "trailscope/core/error.hpp"

namespace trailscope::server {
namespace fs = std::filesystem;

namespace {
std::string bytes_text(std::uint64_t b) {
  return std::to_string(b) + " bytes";
}
}  // namespace

DiskBudget::DiskBudget(fs::path dir, std::uint64_t reserve, std::uint64_t cap, FreeSpace free_space)
    : dir_(std::move(dir)), reserve_(reserve), cap_(cap), free_space_(std::move(free_space)) {}

std::shared_ptr<DiskBudget> DiskBudget::open(fs::path dir, std::uint64_t reserve, std::uint64_t cap,
                                             FreeSpace free_space) {
  return std::shared_ptr<DiskBudget>(new DiskBudget(std::move(dir), reserve, cap, std::move(free_space)));
}

std::uint64_t DiskBudget::free_space() const {
  if (free_space_) return free_space_();
  std::error_code ec;
  const fs::space_info s = fs::space(dir_, ec);
  // Unmeasurable (the folder is gone): nothing is free, so nothing more is written.
  return ec ? 0 : static_cast<std::uint64_t>(s.available);
}

std::uint64_t DiskBudget::granted() const {
  std::lock_guard lock(mu_);
  return granted_;
}

std::shared_ptr<const DiskBudget::Grant> DiskBudget::admit(std::uint64_t bytes, const std::string& param,
                                                           const std::string& what, const std::string& how) {
  const std::string needs = what + " needs up to " + bytes_text(bytes) + " (" + how + ")";
  if (bytes > cap_)
    throw Error(Error::Kind::insufficient_storage, param,
                needs + ", more than one job may write: " + bytes_text(cap_) + " (kMaxJobWriteBytes)");
  const std::uint64_t free = free_space();
  std::lock_guard lock(mu_);
  const std::uint64_t held = reserve_ + granted_;
  if (free < held || bytes > free - held)
    throw Error(Error::Kind::insufficient_storage, param,
                needs + ", more than the disk can take: " + bytes_text(free) + " free, less " +
                    bytes_text(reserve_) + " kept free (kDiskReserveBytes) and " + bytes_text(granted_) +
                    " granted to jobs still writing");
  granted_ += bytes;
  return std::shared_ptr<const Grant>(new Grant(shared_from_this(), bytes, param));
}

void DiskBudget::give_back(std::uint64_t bytes) {
  std::lock_guard lock(mu_);
  granted_ -= std::min(granted_, bytes);
}

DiskBudget::Grant::~Grant() {
  budget_->give_back(bytes_);
}

void DiskBudget::Grant::check(std::uint64_t written) const {
  if (written > bytes_)
    throw Error(Error::Kind::insufficient_storage, param_,
                "the job stopped: it wrote " + bytes_text(written) + ", more than the " + bytes_text(bytes_) +
                    " it was granted; nothing of it was kept");
  const std::uint64_t free = budget_->free_space();
  if (free < budget_->reserve())
    throw Error(Error::Kind::insufficient_storage, param_,
                "the job stopped after writing " + bytes_text(written) + ": the disk has " +
                    bytes_text(free) + " free, less than the " + bytes_text(budget_->reserve()) +
                    " the server keeps free (kDiskReserveBytes); nothing of it was kept");
}

}  // namespace trailscope::server
