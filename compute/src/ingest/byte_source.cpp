// The byte source: one inflater (zlib's inflate over gzip members, or a plain copy) over raw bytes that come
// from a file, read in 1 MiB pieces, or from memory; a helper thread keeps up to two blocks of a file
// decompressed ahead of the parser. It behaves as zlib's gzread() does: a plain input is copied through,
// concatenated gzip members are read as one stream, and bytes after a member that do not start another
// are ignored.
#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <climits>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "ingest/detail.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/ingest/format.hpp"

namespace trailscope::ingest::detail {
namespace {
constexpr int kBuffers = 3;                    // one being parsed, up to two read ahead
constexpr std::size_t kRawBytes = 1u << 20;    // a file's read() size: fewer, larger reads
constexpr std::size_t kMinGrowth = 1u << 16;   // a block holding a long line grows by at least this
constexpr std::size_t kMinMemoryBlock = 4096;  // the smallest block cut from bytes in memory

bool gzip_magic(std::string_view s) {
  return s.size() >= 2 && static_cast<unsigned char>(s[0]) == 0x1f &&
         static_cast<unsigned char>(s[1]) == 0x8b;
}

Error gzip_error(const std::string& what, const std::string& path, std::uint64_t offset) {
  return Error(Error::Kind::unprocessable, "file",
               what + " after " + std::to_string(offset) + " compressed bytes of '" + path + "'");
}
}  // namespace

ByteSource::ByteSource(const std::string& path) : path_(path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (!fs::exists(status)) throw not_found("path", "no such file: '" + path + "'");
  if (fs::is_directory(status))
    throw Error(Error::Kind::internal, "path", "'" + path + "' is a directory, not a file");
  file_size_ = fs::file_size(path, ec);
  if (ec) file_size_ = 0;
  fd_ = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd_ < 0)
    throw Error(Error::Kind::internal, "path",
                "cannot open '" + path + "': " + std::generic_category().message(errno));
  raw_.resize(kRawBytes);
  try {
    open_inflater();
  } catch (...) {
    ::close(fd_);
    fd_ = -1;
    throw;
  }
}

ByteSource::ByteSource(std::string_view bytes, std::string name) : path_(std::move(name)) {
  in_ = bytes;
  raw_eof_ = true;
  file_size_ = bytes.size();
  open_inflater();
  // Blocks sized to the input: a plain input is one block; a gzip one starts from eight times its size
  // (blocks end where the output does, whatever their size, so this only saves allocations).
  block_bytes_ =
      std::clamp<std::size_t>(gzip_ ? 8 * bytes.size() : bytes.size() + 1, kMinMemoryBlock, kBlockBytes);
}

void ByteSource::open_inflater() {
  gzip_ = gzip_magic(in_.substr(0, raw_available(2)));
  try {
    // A plain input in memory has a known size: a head no longer than it (no 64 KiB per small input).
    head_.resize(fd_ < 0 && !gzip_ ? std::min(kDetectHeadBytes, in_.size()) : kDetectHeadBytes);
    std::size_t have = 0;
    while (have < head_.size()) {
      const std::size_t n = read_some(head_.data() + have, head_.size() - have);
      if (n == 0) break;
      have += n;
    }
    head_.resize(have);
  } catch (...) {
    if (zs_) {
      inflateEnd(static_cast<z_stream*>(zs_));
      delete static_cast<z_stream*>(zs_);
      zs_ = nullptr;
    }
    throw;
  }
}

ByteSource::~ByteSource() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  cv_.notify_all();
  if (thread_.joinable()) thread_.join();
  if (zs_) {
    inflateEnd(static_cast<z_stream*>(zs_));
    delete static_cast<z_stream*>(zs_);
  }
  if (fd_ >= 0) ::close(fd_);
}

std::size_t ByteSource::raw_available(std::size_t want) {
  if (in_.size() >= want || raw_eof_) return in_.size();
  // A file: move what is left to the front of the buffer and read more behind it.
  const std::size_t keep = in_.size();
  // Nothing to keep on the first read: in_ may then be an empty view with a null data(), which memmove
  // must not be given even for 0 bytes.
  if (keep > 0) std::memmove(raw_.data(), in_.data(), keep);
  std::size_t have = keep;
  while (have < want && !raw_eof_) {
    const ssize_t n = ::read(fd_, raw_.data() + have, raw_.size() - have);
    if (n < 0) {
      if (errno == EINTR) continue;
      throw Error(Error::Kind::internal, "path",
                  "cannot read '" + path_ + "': " + std::generic_category().message(errno));
    }
    if (n == 0) raw_eof_ = true;
    have += static_cast<std::size_t>(n);
  }
  in_ = std::string_view(raw_.data(), have);
  return have;
}

std::size_t ByteSource::read_some(char* dst, std::size_t n) {
  std::size_t got = 0;
  if (!gzip_) {
    while (got < n) {
      const std::size_t a = raw_available(1);
      if (a == 0) break;
      const std::size_t k = std::min(a, n - got);
      std::memcpy(dst + got, in_.data(), k);
      in_.remove_prefix(k);
      consumed_ += k;
      got += k;
    }
    return got;
  }
  while (got < n && !eof_of_gzip_) {
    if (!zs_) {
      // A member starts here: the first one, or one after the last member's end. What follows a member and
      // is not another gzip header is ignored (zlib's gzread does the same).
      if (member_done_ && !gzip_magic(in_.substr(0, raw_available(2)))) {
        eof_of_gzip_ = true;
        break;
      }
      auto* zs = new z_stream{};
      if (inflateInit2(zs, 16 + MAX_WBITS) != Z_OK) {
        delete zs;
        throw Error(Error::Kind::internal, "file", "cannot start zlib's inflate for '" + path_ + "'");
      }
      zs_ = zs;
      member_done_ = false;
    }
    auto* zs = static_cast<z_stream*>(zs_);
    if (raw_available(1) == 0) {
      if (got) break;  // the bytes so far first; the next call reports the truncation
      throw gzip_error("the gzip stream is truncated (unexpected end of file)", path_, consumed_);
    }
    const std::size_t in_now = std::min<std::size_t>(in_.size(), UINT_MAX);
    const std::size_t out_now = std::min<std::size_t>(n - got, UINT_MAX);
    zs->next_in = reinterpret_cast<Bytef*>(const_cast<char*>(in_.data()));
    zs->avail_in = static_cast<uInt>(in_now);
    zs->next_out = reinterpret_cast<Bytef*>(dst + got);
    zs->avail_out = static_cast<uInt>(out_now);
    const int rc = inflate(zs, Z_NO_FLUSH);
    const std::size_t used = in_now - zs->avail_in;
    in_.remove_prefix(used);
    consumed_ += used;
    got += out_now - zs->avail_out;
    if (rc == Z_STREAM_END) {
      inflateEnd(zs);
      delete zs;
      zs_ = nullptr;
      member_done_ = true;
    } else if (rc == Z_MEM_ERROR) {
      throw std::bad_alloc();
    } else if (rc != Z_OK && rc != Z_BUF_ERROR) {
      throw gzip_error(std::string("the gzip stream is corrupt (") + (zs->msg ? zs->msg : "bad data") + ")",
                       path_, consumed_);
    }
  }
  return got;
}

void ByteSource::start(bool line_aligned) {
  if (started_) return;
  started_ = true;
  line_aligned_ = line_aligned;
  carry_ = head_;       // the head is the first bytes of the stream
  if (fd_ < 0) return;  // bytes in memory: next() cuts the blocks itself
  for (int i = 0; i < kBuffers; ++i) free_.emplace_back();
  thread_ = std::thread([this] { produce(); });
}

bool ByteSource::fill(std::string& buf) {
  buf.assign(carry_);
  carry_.clear();
  bool eof = false;
  std::size_t scan_from = 0;  // where to look for the last newline
  std::size_t want = std::max(block_bytes_, buf.size() + std::min(block_bytes_, kMinGrowth));
  for (;;) {
    std::size_t have = buf.size();
    buf.resize(want);
    while (have < want) {
      const std::size_t n = read_some(buf.data() + have, want - have);
      if (n == 0) {
        eof = true;
        break;
      }
      have += n;
    }
    buf.resize(have);
    if (eof || !line_aligned_) break;
    const void* nl = nullptr;
    for (std::size_t i = have; i > scan_from; --i)
      if (buf[i - 1] == '\n') {
        nl = &buf[i - 1];
        break;
      }
    if (nl) {
      const std::size_t cut = static_cast<const char*>(nl) - buf.data() + 1;
      carry_.assign(buf, cut, std::string::npos);
      buf.resize(cut);
      break;
    }
    scan_from = have;  // one line longer than the block: grow and read on
    want *= 2;
  }
  return eof;
}

void ByteSource::produce() {
  bool eof = false;
  try {
    while (!eof) {
      std::string buf;
      {
        std::unique_lock lock(mutex_);
        cv_.wait(lock, [&] { return stop_ || !free_.empty(); });
        if (stop_) return;
        buf = std::move(free_.back());
        free_.pop_back();
      }
      eof = fill(buf);
      {
        std::lock_guard lock(mutex_);
        full_.push_back(Block{std::move(buf), eof ? file_size_ : consumed_});
      }
      cv_.notify_all();
    }
  } catch (...) {
    std::lock_guard lock(mutex_);
    error_ = std::current_exception();
  }
  {
    std::lock_guard lock(mutex_);
    done_ = true;
  }
  cv_.notify_all();
}

std::string_view ByteSource::next() {
  if (!started_) start(true);
  if (fd_ < 0) {
    // Bytes in memory: the same blocks, cut on this thread.
    if (done_) return {};
    done_ = fill(current_);
    offset_ = done_ ? file_size_ : consumed_;
    return current_;
  }
  std::unique_lock lock(mutex_);
  if (has_current_) {
    free_.push_back(std::move(current_));
    current_ = std::string();
    has_current_ = false;
    cv_.notify_all();
  }
  cv_.wait(lock, [&] { return !full_.empty() || done_; });
  if (full_.empty()) {
    if (error_) std::rethrow_exception(error_);
    return {};
  }
  current_ = std::move(full_.front().data);
  has_current_ = true;
  offset_ = full_.front().offset;
  full_.pop_front();
  return current_;
}

SourceStreambuf::int_type SourceStreambuf::underflow() {
  const std::string_view b = src_.next();  // blocks are never empty before the end
  if (b.empty()) return traits_type::eof();
  char* p = const_cast<char*>(b.data());
  setg(p, p, p + b.size());
  return traits_type::to_int_type(*p);
}

}  // namespace trailscope::ingest::detail
