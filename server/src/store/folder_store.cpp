#include "store/folder_store.hpp"

#include <iostream>

#include "store/column_io.hpp"
#include "store/failpoint.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::server {
namespace fs = std::filesystem;
using namespace column_io;

FolderStore::FolderStore(fs::path root, Layout layout, const ReadMeta& read_meta)
    : root_(std::move(root)),
      layout_(std::move(layout)),
      index_(layout_.prefix, layout_.noun, root_ / layout_.folder / kIdCounterFile) {
  std::error_code ec;
  for (const std::string& sub : {layout_.folder, std::string("tmp")}) {
    fs::create_directories(root_ / sub, ec);
    if (ec) throw io_error(root_ / sub, "create");
  }
  const std::string staged = layout_.noun + ".";
  for (const auto& e : fs::directory_iterator(root_ / "tmp"))
    if (e.path().filename().string().rfind(staged, 0) == 0) fs::remove_all(e.path(), ec);
  for (const auto& e : fs::directory_iterator(root_ / layout_.folder)) {
    const std::string id = e.path().filename().string();
    if (!e.is_directory() || index_.number(id) == 0 || !fs::exists(e.path() / layout_.meta_file, ec))
      continue;
    try {
      index_.add(id, read_meta(e.path()));
    } catch (const std::exception& ex) {
      // Unreadable on disk: reported and skipped for this run, never deleted (as datasets).
      std::cerr << "store: skipping " << layout_.noun << " '" << id << "': " << ex.what() << "\n";
    }
  }
}

std::vector<nlohmann::json> FolderStore::list() const {
  std::lock_guard lock(mu_);
  return index_.list();
}

nlohmann::json FolderStore::meta(const std::string& id) const {
  std::lock_guard lock(mu_);
  return index_.at(id, layout_.noun);
}

void FolderStore::check(const std::string& id) const {
  std::lock_guard lock(mu_);
  index_.check(id, layout_.noun);
}

bool FolderStore::contains(const std::string& id) const {
  std::lock_guard lock(mu_);
  return index_.contains(id);
}

std::size_t FolderStore::size() const {
  std::lock_guard lock(mu_);
  return index_.size();
}

std::string FolderStore::oldest() const {
  std::lock_guard lock(mu_);
  return index_.oldest();
}

fs::path FolderStore::dir(const std::string& id) const {
  return root_ / layout_.folder / id;
}

std::string FolderStore::next_id() {
  std::lock_guard lock(mu_);
  return index_.next_id();
}

std::uint64_t FolderStore::number(const std::string& id) const {
  return index_.number(id);  // a pure function of the id: no lock
}

fs::path stage_folder(const fs::path& tmp_dir, const std::string& name) {
  const fs::path tmp = tmp_dir / (name + "." + random_suffix());
  std::error_code ec;
  fs::create_directories(tmp, ec);
  if (ec) throw io_error(tmp, "create");
  failpoint("store.stage");
  return tmp;
}

void publish_folder(const fs::path& staged, const fs::path& final_dir) {
  std::error_code ec;
  failpoint("store.publish.before_rename");
  fs::rename(staged, final_dir, ec);
  if (ec) throw io_error(final_dir, "rename into");
  failpoint("store.publish.after_rename");
  fsync_path(final_dir.parent_path());
}

void remove_folder(const fs::path& dir, const fs::path& gone) {
  std::error_code ec;
  fs::rename(dir, gone, ec);
  if (ec) throw io_error(dir, "remove");
  failpoint("store.remove.after_rename");
  fs::remove_all(gone, ec);
}

fs::path FolderStore::stage(const std::string& id) const {
  return stage_folder(root_ / "tmp", layout_.noun + "." + id);
}

void FolderStore::publish(const std::string& id, const fs::path& staged, nlohmann::json meta) {
  publish_folder(staged, dir(id));
  std::lock_guard lock(mu_);
  index_.add(id, std::move(meta));
}

void FolderStore::remove(const std::string& id) {
  std::lock_guard lock(mu_);
  index_.check(id, layout_.noun);
  remove_folder(dir(id), root_ / "tmp" / (layout_.noun + "." + id + ".deleted." + random_suffix()));
  index_.erase(id);
}

FolderStore::ReadMeta manifest_meta(std::string magic, int version, std::vector<std::string> private_keys) {
  return [magic = std::move(magic), version, keys = std::move(private_keys)](const fs::path& dir) {
    nlohmann::json m = read_manifest(dir);
    if (m.value("magic", "") != magic || m.value("version", 0) != version)
      throw io_error(dir, "recognise the format of");
    m.erase("magic"), m.erase("version");
    for (const std::string& k : keys) m.erase(k);
    return m;
  };
}

}  // namespace trailscope::server
