#pragma once
// Private plumbing of the ingest readers: the read-ahead byte source, number and time parsing that never
// allocates, and the per-ingest context through which every reader validates and reports rows.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <mutex>
#include <streambuf>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "trailscope/core/limits.hpp"
#include "trailscope/ingest/ingest.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::ingest::detail {

// --- byte source ---------------------------------------------------------------------------------------

/// Sequential decompressed bytes of a plain or gzip input: a file, or bytes already in memory (an upload
/// held in a buffer, a fuzzer's input). Both go through the same inflater and the same block cutting; they
/// differ only in where the compressed bytes come from. The constructor reads the head synchronously (for
/// detection). For a file, start() then launches a helper thread that decompresses ahead while the caller
/// parses, so inflate and parsing overlap on two cores; bytes in memory are cut into blocks on the caller's
/// thread when next() asks (no thread, and blocks no larger than the input needs).
class ByteSource {
 public:
  /// Bytes per block handed to the parser (a block grows beyond this only to hold one very long line).
  static constexpr std::size_t kBlockBytes = 4u << 20;

  /// Throws Error(not_found, "path") when the file is missing, Error(internal, "path") when unreadable,
  /// Error(unprocessable, "file") when its gzip stream is corrupt within the head.
  explicit ByteSource(const std::string& path);
  /// Reads `bytes` (not copied: they must outlive the source); `name` stands for the path in messages.
  /// Throws Error(unprocessable, "file") when its gzip stream is corrupt within the head.
  ByteSource(std::string_view bytes, std::string name);
  ~ByteSource();
  ByteSource(const ByteSource&) = delete;
  ByteSource& operator=(const ByteSource&) = delete;

  /// The first decompressed bytes (at most kDetectHeadBytes; all of a shorter input).
  std::string_view head() const { return head_; }
  /// The file's path, or the name given with bytes in memory.
  const std::string& path() const { return path_; }

  /// Starts reading ahead. With `line_aligned`, every block but the last ends with '\n', so a line never
  /// straddles two blocks (text formats); without, blocks end anywhere (JSON, whose arrays are often one
  /// line of hundreds of megabytes).
  void start(bool line_aligned);
  /// The next block, starting with the head's bytes; empty at the end. The view is valid until the next
  /// call. Rethrows, in order, the read error that ended the stream (truncated gzip, I/O error).
  std::string_view next();
  /// Fraction of the input (compressed bytes) consumed by the blocks returned so far, in [0, 1].
  double fraction() const { return file_size_ ? std::min(1.0, double(offset_) / double(file_size_)) : 1.0; }

 private:
  struct Block {
    std::string data;
    std::uint64_t offset = 0;  // compressed bytes consumed once this block was read
  };
  void open_inflater();  // after the input is set: looks for the gzip magic, reads the head
  void produce();        // the helper thread: fill() until the end
  // Cuts the next block into `buf` (starting with carry_); returns whether the input is exhausted.
  bool fill(std::string& buf);
  // Reads up to `n` decompressed bytes into `dst`; returns 0 at the end. Throws on a gzip or I/O error.
  std::size_t read_some(char* dst, std::size_t n);
  // Makes at least `want` raw (compressed) bytes available at in_ when the input has them; returns how
  // many are available.
  std::size_t raw_available(std::size_t want);

  std::string path_;
  int fd_ = -1;                 // the file, or -1 for bytes in memory
  std::string_view in_;         // raw bytes not yet consumed (into raw_ for a file, into the caller's bytes)
  std::string raw_;             // a file's read buffer
  bool raw_eof_ = false;        // the file has no more raw bytes
  void* zs_ = nullptr;          // z_stream while inside a gzip member; void* keeps zlib.h out of this header
  bool gzip_ = false;           // the input starts with the gzip magic
  bool member_done_ = false;    // the current gzip member ended (the next may follow)
  std::uint64_t consumed_ = 0;  // raw bytes consumed so far
  std::uint64_t file_size_ = 0, offset_ = 0;
  std::size_t block_bytes_ = kBlockBytes;
  std::string head_;
  std::string carry_;  // bytes of a line cut at the end of the previous block
  bool line_aligned_ = true;
  bool eof_of_gzip_ = false;  // the last gzip member ended and no other follows

  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<Block> full_;
  std::vector<std::string> free_;
  std::string current_;
  bool done_ = false, stop_ = false, started_ = false, has_current_ = false;
  std::exception_ptr error_;
};

/// std::streambuf over a ByteSource, for nlohmann's stream parser (it pulls one char at a time through
/// sbumpc(), which stays inline while a block lasts).
class SourceStreambuf : public std::streambuf {
 public:
  explicit SourceStreambuf(ByteSource& src) : src_(src) {}

 protected:
  int_type underflow() override;

 private:
  ByteSource& src_;
};

// --- text and number parsing ------------------------------------------------------------------------------

inline std::string_view trim(std::string_view s) noexcept {
  std::size_t b = 0, e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\t' || s[b] == '\r')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\r')) --e;
  return s.substr(b, e - b);
}

/// Tokens that mean "no value" in the CSV exports we meet (pandas, Trino, MySQL/ClickHouse `\N`).
inline bool is_null_token(std::string_view s) noexcept {
  switch (s.size()) {
    case 0:
      return true;
    case 2:
      return s == "\\N";
    case 3:
      return s == "NaN" || s == "nan" || s == "NAN";
    case 4:
      return s == "null" || s == "NULL" || s == "Null" || s == "None";
    default:
      return false;
  }
}

enum class Num { ok, null, bad };

/// Parses a whole field as a finite float/double (surrounding blanks and a leading '+' allowed). Null
/// tokens give Num::null; trailing garbage, inf and nan give Num::bad.
template <class T>
inline Num parse_number(std::string_view s, T& out) noexcept {
  if (!s.empty() && (s.front() == ' ' || s.back() == ' ' || s.front() == '\t' || s.back() == '\r'))
    s = trim(s);
  if (is_null_token(s)) return Num::null;
  if (s.front() == '+') s.remove_prefix(1);
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(out)) return Num::bad;
  return Num::ok;
}

/// Days from 1970-01-01 to the civil date y-m-d (proleptic Gregorian; H. Hinnant's algorithm).
constexpr std::int64_t days_from_civil(std::int64_t y, unsigned m, unsigned d) noexcept {
  y -= m <= 2;
  const std::int64_t era = (y >= 0 ? y : y - 399) / 400;
  const unsigned yoe = static_cast<unsigned>(y - era * 400);
  const unsigned doy = (153 * (m > 2 ? m - 3 : m + 9) + 2) / 5 + d - 1;
  const unsigned doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  return era * 146097 + static_cast<std::int64_t>(doe) - 719468;
}

/// Parses "YYYY-MM-DD[(T| )hh:mm[:ss[.fff]]][Z|±hh[:mm]]" (no zone = UTC) into Unix seconds.
bool parse_iso8601(std::string_view s, double& t) noexcept;

/// `s` in single quotes for a message, cut to `max` characters (with "...") and with control bytes shown
/// as '?', so that a reason never carries a whole line or binary garbage.
std::string quote(std::string_view s, std::size_t max = 40);

/// Splits one CSV line into fields: commas separate, a field may be "quoted" (commas inside are kept;
/// "" is an escaped quote, left as is since we never need quoted text verbatim). Returned views point into
/// `line` (without the quotes). A malformed quote ends the field at the end of the line.
void split_csv(std::string_view line, std::vector<std::string_view>& fields);

/// The column names of a CSV header line: trimmed, unquoted, lower-cased, a UTF-8 BOM dropped.
std::vector<std::string> csv_header_names(std::string_view line);

/// The first line of `text` without its end of line ("\n" or "\r\n").
std::string_view first_line(std::string_view text) noexcept;

// --- SO6 lines --------------------------------------------------------------------------------------------

/// One parsed SO6 m3 segment line (views point into the line).
struct So6Segment {
  std::string_view callsign, flight_id;
  double t_begin = 0, t_end = 0;        // Unix seconds
  double lat_begin = 0, lon_begin = 0;  // degrees (the file has decimal minutes)
  double lat_end = 0, lon_end = 0;
  float alt_begin = 0, alt_end = 0;  // metres (the file has flight levels)
};

/// Parses one SO6 line (20 fields separated by blanks). Returns nullptr and fills `seg`, or returns a
/// static reason ("expected 20 space-separated fields", "bad time (hhmmss) in field 5", ...). Coordinates
/// are converted but not range-checked (check_sample does that).
const char* parse_so6_line(std::string_view line, So6Segment& seg) noexcept;

// --- the per-ingest context -------------------------------------------------------------------------------

struct ReadContext {
  ReadContext(ByteSource& s, TrailSetBuilder& b, IngestReport& r, const IngestOptions& o)
      : src(s), builder(b), report(r), opts(o), gap_seconds(o.gap_seconds) {}

  ByteSource& src;
  TrailSetBuilder& builder;
  IngestReport& report;
  const IngestOptions& opts;
  /// Gap for TrailSetBuilder::build(); a reader may change it (SO6 sets +inf).
  double gap_seconds;
  /// Duplicates a reader dropped itself before the builder saw them (SO6).
  std::size_t reader_duplicates = 0;

  /// Counts a data row; every kCheckEvery rows checks cancellation and reports progress.
  void row() {
    ++report.rows;
    if (++since_check_ == kCheckEvery) {
      since_check_ = 0;
      checkpoint();
    }
  }
  /// Records a rejected row. `reason` is a callable returning something convertible to std::string; it
  /// runs only while the report still lists rejects, so mass rejections cost no allocations.
  template <class F>
  void reject(std::size_t line, F&& reason) {
    ++report.rejected;
    if (report.rejects.size() < limits::kMaxReportedRejects)
      report.rejects.push_back({line, std::string(reason())});
  }
  /// Normalises and validates `s`; adds it to the builder, or records the reject. Returns whether added.
  bool accept(std::size_t line, std::string_view icao24, std::string_view callsign, Sample& s) {
    normalise_sample(s);
    if (const char* why = check_sample(s)) {
      reject(line, [why] { return why; });
      return false;
    }
    builder.add(icao24, callsign, s);
    ++report.accepted;
    return true;
  }
  /// Cancellation check and "parse" progress report.
  void checkpoint();

  static constexpr std::size_t kCheckEvery = 65536;

 private:
  std::size_t since_check_ = 0;
};

/// The readers. Each consumes ctx.src from its start (the head included), counts rows, rejects and adds
/// samples; a content that does not fit the format throws Error(unsupported_format, "format").
void read_opensky_csv(ReadContext& ctx);
void read_traffic_json(ReadContext& ctx);
void read_so6(ReadContext& ctx);
void read_readsb_trace(ReadContext& ctx);

/// Conversion factors to SI.
inline constexpr double kFeet = 0.3048;                  // ft → m
inline constexpr double kKnot = 1852.0 / 3600.0;         // kt → m/s
inline constexpr double kFeetPerMinute = 0.3048 / 60.0;  // ft/min → m/s

}  // namespace trailscope::ingest::detail
