// The read-ahead byte source: zlib's gz* functions read plain and gzip files alike (a plain file is
// copied through), and a helper thread keeps up to two blocks decompressed ahead of the parser.
#include <zlib.h>

#include <climits>
#include <cstring>
#include <filesystem>
#include <system_error>

#include "ingest/detail.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/ingest/format.hpp"

namespace trailscope::ingest::detail {
namespace {
constexpr int kBuffers = 3;  // one being parsed, up to two read ahead

Error gzip_error(gzFile gz, const std::string& path, std::uint64_t offset) {
  int code = Z_OK;
  const char* msg = gzerror(gz, &code);
  if (code == Z_ERRNO)
    return Error(Error::Kind::internal, "path",
                 "cannot read '" + path + "': " + std::generic_category().message(errno));
  std::string what = code == Z_BUF_ERROR ? "the gzip stream is truncated (" + std::string(msg) + ")"
                                         : "the gzip stream is corrupt (" + std::string(msg ? msg : "") + ")";
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
  gzFile gz = gzopen(path.c_str(), "rb");
  if (!gz)
    throw Error(Error::Kind::internal, "path",
                "cannot open '" + path + "': " + std::generic_category().message(errno));
  gz_ = gz;
  gzbuffer(gz, 1u << 20);  // fewer, larger read() calls; must precede the first read
  try {
    head_.resize(kDetectHeadBytes);
    std::size_t have = 0;
    while (have < head_.size()) {
      const std::size_t n = read_some(head_.data() + have, head_.size() - have);
      if (n == 0) break;
      have += n;
    }
    head_.resize(have);
  } catch (...) {
    gzclose(gz);
    gz_ = nullptr;
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
  if (gz_) gzclose(static_cast<gzFile>(gz_));
}

std::size_t ByteSource::read_some(char* dst, std::size_t n) {
  gzFile gz = static_cast<gzFile>(gz_);
  const int got = gzread(gz, dst, static_cast<unsigned>(std::min<std::size_t>(n, INT_MAX)));
  if (got < 0) throw gzip_error(gz, path_, static_cast<std::uint64_t>(gzoffset(gz)));
  if (got == 0) {
    // gzread() reports a truncated stream as a plain end of file; only gzerror() tells them apart.
    int code = Z_OK;
    gzerror(gz, &code);
    if (code != Z_OK) throw gzip_error(gz, path_, static_cast<std::uint64_t>(gzoffset(gz)));
  }
  return static_cast<std::size_t>(got);
}

void ByteSource::start(bool line_aligned) {
  if (started_) return;
  started_ = true;
  for (int i = 0; i < kBuffers; ++i) free_.emplace_back();
  thread_ = std::thread([this, line_aligned] { produce(line_aligned); });
}

void ByteSource::produce(bool line_aligned) {
  std::string carry = head_;  // the head is the first bytes of the stream
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
      buf.assign(carry);
      carry.clear();
      std::size_t scan_from = 0;  // where to look for the last newline
      std::size_t want = std::max(kBlockBytes, buf.size() + (1u << 16));
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
        if (eof || !line_aligned) break;
        const void* nl = nullptr;
        for (std::size_t i = have; i > scan_from; --i)
          if (buf[i - 1] == '\n') {
            nl = &buf[i - 1];
            break;
          }
        if (nl) {
          const std::size_t cut = static_cast<const char*>(nl) - buf.data() + 1;
          carry.assign(buf, cut, std::string::npos);
          buf.resize(cut);
          break;
        }
        scan_from = have;  // one line longer than the block: grow and read on
        want *= 2;
      }
      const auto offset = static_cast<std::uint64_t>(gzoffset(static_cast<gzFile>(gz_)));
      {
        std::lock_guard lock(mutex_);
        full_.push_back(Block{std::move(buf), eof ? file_size_ : offset});
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
