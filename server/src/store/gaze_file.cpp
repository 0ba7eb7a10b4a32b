#include "store/gaze_file.hpp"

#include <bit>
#include <cstring>

#include "limits.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::server {
namespace {
static_assert(std::endian::native == std::endian::little,
              "the gaze file is little-endian and written as the host lays values out");

constexpr std::uint64_t kRecordingFixedBytes = 4 * 4 + 1 + 6 * 8 + 8 + 4 + 4;  // text lengths .. counts
constexpr std::uint64_t kBytesPerSample = 8 + 8 + 8 + 1;
constexpr std::uint64_t kBytesPerEvent = 1 + 1 + 8 + 8;

class Writer {
 public:
  explicit Writer(std::uint64_t size) { out_.reserve(size); }
  template <typename T>
  void put(T v) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    out_.append(b, sizeof(T));
  }
  template <typename T>
  void column(const std::vector<T>& v) {
    out_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void text(const std::string& s) {
    if (s.size() > kGazeFileMaxText)
      throw invalid_argument("file", "a gaze tag is longer than " + std::to_string(kGazeFileMaxText) +
                                         " bytes: '" + s.substr(0, 64) + "...'");
    put(std::uint32_t(s.size()));
    out_ += s;
  }
  std::string take() { return std::move(out_); }

 private:
  std::string out_;
};

class Reader {
 public:
  explicit Reader(std::string_view b) : b_(b) {}
  [[noreturn]] void fail(const std::string& what) const {
    throw Error(Error::Kind::unprocessable, "gaze_file",
                "gaze file: byte " + std::to_string(at_) + ": " + what);
  }
  void need(std::uint64_t n, const char* what) const {
    if (n > b_.size() - at_) fail(std::string("truncated: ") + what + " runs past the end of the file");
  }
  template <typename T>
  T get(const char* what) {
    need(sizeof(T), what);
    T v;
    std::memcpy(&v, b_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return v;
  }
  template <typename T>
  void column(std::vector<T>& v, std::uint64_t n, const char* what) {
    need(n * sizeof(T), what);  // n <= kMaxGazeSamples: no overflow
    v.resize(n);
    if (n == 0)
      return;  // an empty vector's data() may be null, and memcpy of null is undefined even for 0 bytes
    std::memcpy(v.data(), b_.data() + at_, n * sizeof(T));
    at_ += n * sizeof(T);
  }
  std::string text(const char* what) {
    const auto n = get<std::uint32_t>(what);
    if (n > kGazeFileMaxText)
      fail(std::string(what) + " is " + std::to_string(n) + " bytes long, more than " +
           std::to_string(kGazeFileMaxText));
    need(n, what);
    std::string s(b_.substr(at_, n));
    at_ += n;
    return s;
  }
  bool done() const { return at_ == b_.size(); }

 private:
  std::string_view b_;
  std::uint64_t at_ = 0;
};
}  // namespace

std::uint64_t gaze_file_size(const gaze::GazeDataset& ds) {
  std::uint64_t n = 4 + 4 + 4;
  for (const gaze::Recording& r : ds.recordings) {
    n += kRecordingFixedBytes + r.participant.size() + r.stimulus.size() + r.trial.size() + r.format.size();
    n += r.size() * kBytesPerSample + r.tracker_events.size() * kBytesPerEvent;
    for (const auto& [name, values] : r.annotations) n += 4 + name.size() + values.size() * 4;
  }
  return n;
}

std::string encode_gaze_file(const gaze::GazeDataset& ds) {
  Writer w(gaze_file_size(ds));
  w.put(std::uint32_t(0));  // magic, below
  w.put(kGazeFileVersion);
  w.put(std::uint32_t(ds.recordings.size()));
  for (const gaze::Recording& r : ds.recordings) {
    const std::size_t n = r.size();
    if (r.x.size() != n || r.y.size() != n || r.valid.size() != n)
      throw invalid_argument("file", "a recording's columns differ in length");
    if (r.annotations.size() > kGazeFileMaxAnnotations)
      throw invalid_argument(
          "file", "a recording has more than " + std::to_string(kGazeFileMaxAnnotations) + " label columns");
    w.text(r.participant), w.text(r.stimulus), w.text(r.trial), w.text(r.format);
    w.put(std::uint8_t(r.units));
    for (double v : {r.geometry.width_px, r.geometry.height_px, r.geometry.width_cm, r.geometry.height_cm,
                     r.geometry.distance_cm, r.rate_hz})
      w.put(v);
    w.put(std::uint64_t(n));
    w.column(r.t_ms), w.column(r.x), w.column(r.y), w.column(r.valid);
    w.put(std::uint32_t(r.tracker_events.size()));
    for (const gaze::GazeEvent& e : r.tracker_events) {
      w.put(std::uint8_t(e.type)), w.put(std::uint8_t(e.eye));
      w.put(e.t_start_ms), w.put(e.t_end_ms);
    }
    w.put(std::uint32_t(r.annotations.size()));
    for (const auto& [name, values] : r.annotations) {
      if (values.size() != n) throw invalid_argument("file", "label column '" + name + "' differs in length");
      w.text(name);
      w.column(values);
    }
  }
  std::string out = w.take();
  std::memcpy(out.data(), kGazeFileMagic, 4);
  return out;
}

gaze::GazeDataset decode_gaze_file(std::string_view bytes) {
  Reader in(bytes);
  in.need(4, "the magic");
  if (bytes.substr(0, 4) != std::string_view(kGazeFileMagic, 4)) in.fail("not a gaze file (no TSGZ magic)");
  (void)in.get<std::uint32_t>("the magic");
  if (const auto v = in.get<std::uint32_t>("the version"); v != kGazeFileVersion)
    in.fail("version " + std::to_string(v) + " is not " + std::to_string(kGazeFileVersion));
  const auto count = in.get<std::uint32_t>("the recording count");
  if (count > limits::kMaxGazeRecordings)
    in.fail(std::to_string(count) + " recordings, more than " + std::to_string(limits::kMaxGazeRecordings));
  gaze::GazeDataset ds;
  std::uint64_t samples = 0;
  for (std::uint32_t i = 0; i < count; ++i) {
    gaze::Recording r;
    r.participant = in.text("a participant");
    r.stimulus = in.text("a stimulus");
    r.trial = in.text("a trial");
    r.format = in.text("a format");
    const auto units = in.get<std::uint8_t>("the units");
    if (units > std::uint8_t(gaze::Units::deg)) in.fail("unknown units code " + std::to_string(units));
    r.units = gaze::Units(units);
    r.geometry.width_px = in.get<double>("the geometry");
    r.geometry.height_px = in.get<double>("the geometry");
    r.geometry.width_cm = in.get<double>("the geometry");
    r.geometry.height_cm = in.get<double>("the geometry");
    r.geometry.distance_cm = in.get<double>("the geometry");
    r.rate_hz = in.get<double>("the rate");
    const auto n = in.get<std::uint64_t>("the sample count");
    if (n > limits::kMaxGazeSamples - samples)
      in.fail("more than " + std::to_string(limits::kMaxGazeSamples) + " samples");
    samples += n;
    in.need(n * kBytesPerSample, "the samples");
    in.column(r.t_ms, n, "the times");
    in.column(r.x, n, "the x column");
    in.column(r.y, n, "the y column");
    in.column(r.valid, n, "the validity column");
    for (std::uint8_t v : r.valid)
      if (v > 1) in.fail("a validity code other than 0 or 1");
    const auto events = in.get<std::uint32_t>("the tracker event count");
    in.need(std::uint64_t(events) * kBytesPerEvent, "the tracker events");
    r.tracker_events.resize(events);
    for (gaze::GazeEvent& e : r.tracker_events) {
      const auto type = in.get<std::uint8_t>("an event type");
      const auto eye = in.get<std::uint8_t>("an event eye");
      if (type > std::uint8_t(gaze::EventType::undefined))
        in.fail("unknown event type " + std::to_string(type));
      if (eye != 0 && eye != 'L' && eye != 'R') in.fail("unknown eye code " + std::to_string(eye));
      e.type = gaze::EventType(type), e.eye = char(eye);
      e.t_start_ms = in.get<double>("an event start");
      e.t_end_ms = in.get<double>("an event end");
    }
    const auto columns = in.get<std::uint32_t>("the label column count");
    if (columns > kGazeFileMaxAnnotations)
      in.fail(std::to_string(columns) + " label columns, more than " +
              std::to_string(kGazeFileMaxAnnotations));
    for (std::uint32_t c = 0; c < columns; ++c) {
      std::string name = in.text("a label column name");
      std::vector<int> values;
      in.column(values, n, "a label column");
      r.annotations.emplace_back(std::move(name), std::move(values));
    }
    ds.recordings.push_back(std::move(r));
  }
  if (!in.done()) in.fail("bytes after the last recording");
  return ds;
}

}  // namespace trailscope::server
