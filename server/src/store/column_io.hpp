#pragma once
// File helpers shared by the stores (datasets, graphs, bundles, videos, runs, MOT files, sweeps): one binary
// file per column, fsync before a rename publishes a folder or a file, and random suffixes for temporaries.
// Every store writes a folder into <root>/tmp/ and renames it into place, so a reader after a crash sees all
// of it or none of it.
#include <fcntl.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "store/failpoint.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"

namespace trailscope::server::column_io {

inline Error io_error(const std::filesystem::path& p, const std::string& what) {
  return Error(Error::Kind::internal, "", "store: cannot " + what + " " + p.string());
}

/// Flushes a file or folder to disk, so that a rename that follows cannot be seen before the data.
inline void fsync_path(const std::filesystem::path& p) {
  const int fd = ::open(p.c_str(), O_RDONLY);
  if (fd < 0) throw io_error(p, "open for fsync");
  const int rc = ::fsync(fd);
  ::close(fd);
  if (rc != 0) throw io_error(p, "fsync");
}

/// Writes `v` raw (host byte order: the files never leave the machine that wrote them) to dir/name.bin.
template <typename T>
void write_column(const std::filesystem::path& dir, const char* name, const std::vector<T>& v) {
  const std::filesystem::path p = dir / (std::string(name) + ".bin");
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(v.data()), static_cast<std::streamsize>(v.size() * sizeof(T)));
  out.close();
  if (!out) throw io_error(p, "write");
  fsync_path(p);
  failpoint("store.write.column");
}

/// Reads dir/name.bin into `v`, which must hold exactly `n` values (a size mismatch is a damaged file).
template <typename T>
void read_column(const std::filesystem::path& dir, const char* name, std::vector<T>& v, std::size_t n) {
  const std::filesystem::path p = dir / (std::string(name) + ".bin");
  std::error_code ec;
  const auto size = std::filesystem::file_size(p, ec);
  if (ec || size != n * sizeof(T)) throw io_error(p, "read (size mismatch)");
  v.resize(n);
  std::ifstream in(p, std::ios::binary);
  in.read(reinterpret_cast<char*>(v.data()), static_cast<std::streamsize>(size));
  if (!in) throw io_error(p, "read");
}

/// Writes the manifest last, then flushes it and its folder: a folder without a manifest is incomplete.
inline void write_manifest(const std::filesystem::path& dir, const nlohmann::json& manifest) {
  failpoint("store.write.before_manifest");
  const std::filesystem::path mp = dir / "manifest.json";
  std::ofstream out(mp, std::ios::trunc);
  out << json_text(manifest);
  out.close();
  if (!out) throw io_error(mp, "write");
  fsync_path(mp);
  fsync_path(dir);
}

inline nlohmann::json read_manifest(const std::filesystem::path& dir) {
  std::ifstream in(dir / "manifest.json");
  if (!in) throw io_error(dir / "manifest.json", "open");
  return nlohmann::json::parse(in);
}

inline std::string random_suffix() {
  std::random_device rd;
  char buf[17];
  std::snprintf(buf, sizeof buf, "%08x%08x", rd(), rd());
  return buf;
}

/// Publishes `bytes` as `dest` atomically: written to dest.tmp.<random> beside it, flushed, renamed over
/// `dest`. A crash leaves the old file or the new one, never half of either; the temporary file of a
/// failed write is removed (and a store's start-up removes any "*.tmp.*" a crash left behind). With
/// `owner_only` the file is made readable by its owner alone before any byte is written (secrets' hashes).
inline void write_file_atomic(const std::filesystem::path& dest, const std::string& bytes,
                              bool owner_only = false) {
  const std::filesystem::path tmp =
      dest.parent_path() / (dest.filename().string() + ".tmp." + random_suffix());
  std::error_code ec;
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    // Before any byte is written, so that neither the temporary file nor (after the rename) the
    // destination is ever readable by others, whenever the process dies.
    if (owner_only) {
      std::filesystem::permissions(
          tmp, std::filesystem::perms::owner_read | std::filesystem::perms::owner_write, ec);
      if (ec) {
        std::filesystem::remove(tmp, ec);
        throw io_error(tmp, "restrict the permissions of");
      }
    }
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
      std::filesystem::remove(tmp, ec);
      throw io_error(tmp, "write");
    }
  }
  fsync_path(tmp);
  failpoint("store.replace.before_rename", dest.extension().native());
  std::filesystem::rename(tmp, dest, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw io_error(dest, "rename into");
  }
  failpoint("store.replace.after_rename", dest.extension().native());
}

}  // namespace trailscope::server::column_io
