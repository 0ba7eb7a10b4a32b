// Tracker logs <-> protobuf (proto/tracker_log.proto, documented in proto/tracker_log.md). The C++
// types stay free of protobuf; this TU is the only one that converts, and it includes no OpenImageIO
// header (in one TU they clash: OpenImageIO's farmhash.h #undefs glibc's bswap_32/bswap_64, which
// protobuf's stubs/port.h then fails to find). JSON is protobuf's own canonical mapping, so
// the JSON files, frame_to_json and header_to_json can never drift apart.
#include "tracker_log.pb.h"

#include <google/protobuf/util/json_util.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <limits>
#include <random>
#include <system_error>

#include "trailscope/core/error.hpp"
#include "trailscope/core/json_text.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/tracker/tracker_log.hpp"

namespace trailscope::tracker {
namespace fs = std::filesystem;
using google::protobuf::RepeatedField;

namespace {

/// A structural fault of a log; the message names the field (JSON names) and the frame.
Error fault(const std::string& detail) {
  return Error(Error::Kind::invalid_argument, "log", "log: " + detail);
}

std::string at(const char* array, std::size_t i) {
  return std::string(array) + "[" + std::to_string(i) + "]";
}

// --- C++ -> protobuf ---------------------------------------------------------------------------------

template <std::size_t N>
void put(RepeatedField<double>* out, const std::array<double, N>& a) {
  out->Add(a.begin(), a.end());
}

v1::State to_pb(State s) {
  switch (s) {
    case State::search:
      return v1::STATE_SEARCH;
    case State::track:
      return v1::STATE_TRACK;
    case State::lost:
      return v1::STATE_LOST;
  }
  return v1::STATE_UNSPECIFIED;
}

void to_pb(const RunHeader& h, v1::RunHeader* out) {
  out->set_version(h.version);
  out->set_run_id(h.run_id);
  out->set_video_id(h.video_id);
  out->set_tracker_version(h.tracker_version);
  for (const auto& p : h.params) {
    auto* q = out->add_params();
    q->set_name(p.name);
    q->set_value(p.value);
  }
  for (const auto& t : h.template_bank) {
    auto* q = out->add_template_bank();
    q->set_radius_px(t.radius_px);
    q->set_size_px(t.size_px);
  }
  auto* in = out->mutable_intrinsics();
  in->set_fx(h.intrinsics.fx);
  in->set_fy(h.intrinsics.fy);
  in->set_cx(h.intrinsics.cx);
  in->set_cy(h.intrinsics.cy);
  in->set_width(h.intrinsics.width);
  in->set_height(h.intrinsics.height);
  in->set_defaulted(h.intrinsics.defaulted);
  out->set_fps(h.fps);
  if (h.frame_count > static_cast<std::size_t>(limits::kMaxRunFrames))
    throw Error(Error::Kind::payload_too_large, "log",
                "log: " + std::to_string(h.frame_count) + " frames exceed the limit of " +
                    std::to_string(limits::kMaxRunFrames));
  out->set_frame_count(static_cast<std::uint32_t>(h.frame_count));
  out->set_created_utc(h.created_utc);
  out->set_video_source_json(json_text(h.video_source));
}

void to_pb(const FrameLog& f, v1::Frame* out) {
  // Frame indices are video frame numbers, bounded by limits::kMaxVideoFrames; uint32 keeps them JSON
  // numbers (protobuf's JSON mapping writes 64-bit integers as strings).
  if (f.index > std::numeric_limits<std::uint32_t>::max())
    throw fault("frame index " + std::to_string(f.index) + " does not fit 32 bits");
  out->set_index(static_cast<std::uint32_t>(f.index));
  out->set_timestamp_s(f.timestamp_s);
  out->set_valid_pixels(f.valid_pixels);
  out->set_flying_pixels(f.flying_pixels);
  out->set_matches(f.matches);
  out->set_verified(f.verified);
  for (const auto& c : f.candidates) {
    auto* q = out->add_candidates();
    q->set_u(c.u);
    q->set_v(c.v);
    q->set_ncc(c.ncc);
    q->set_template_index(c.template_index);
    q->set_verified(c.verified);
    put(q->mutable_tip_mm(), c.tip_mm);
    put(q->mutable_axis(), c.axis);
    q->set_radius_mm(c.radius_mm);
    q->set_fit_rms_mm(c.fit_rms_mm);
    q->set_points(c.points);
    q->set_teat(c.teat);
  }
  auto* m = out->mutable_model();
  put(m->mutable_pair_mm(), f.model.pair_mm);
  put(m->mutable_pair_error_mm(), f.model.pair_error_mm);
  m->set_shape_cost(f.model.shape_cost);
  m->set_ncc_cost(f.model.ncc_cost);
  m->set_cost(f.model.cost);
  m->set_teats_matched(f.model.teats_matched);
  out->set_state(to_pb(f.state));
  for (const auto& t : f.teats) {
    auto* q = out->add_teats();
    put(q->mutable_tip_mm(), t.tip_mm);
    put(q->mutable_tip_px(), t.tip_px);
    q->set_visible(t.visible);
    q->set_tracked(t.tracked);
    q->set_confidence(t.confidence);
    q->set_radius_mm(t.radius_mm);
  }
  auto* s = out->mutable_times();
  s->set_preprocess_us(f.times.preprocess_us);
  s->set_detect_us(f.times.detect_us);
  s->set_verify_us(f.times.verify_us);
  s->set_model_us(f.times.model_us);
}

void to_pb(const std::optional<tof::FrameTruth>& truth, v1::FrameTruthEntry* out) {
  out->set_has_truth(truth.has_value());
  if (!truth) return;
  auto* ft = out->mutable_value();
  for (const auto& t : truth->teats) {
    auto* q = ft->add_teats();
    put(q->mutable_tip_mm(), t.tip_mm);
    if (t.tip_px) put(q->mutable_tip_px(), *t.tip_px);
    q->set_visible(t.visible);
    if (t.box_px) {
      auto* b = q->mutable_box_px();
      b->set_x(t.box_px->x);
      b->set_y(t.box_px->y);
      b->set_w(t.box_px->w);
      b->set_h(t.box_px->h);
    }
    q->set_visible_fraction(t.visible_fraction);
    q->set_cup_attached(t.cup_attached);
  }
}

v1::TrackerLog to_pb(const TrackerLog& log) {
  if (log.header.frame_count != log.frames.size())
    throw fault("header.frameCount is " + std::to_string(log.header.frame_count) + " but the log has " +
                std::to_string(log.frames.size()) + " frames");
  if (!log.truth.empty() && log.truth.size() != log.frames.size())
    throw fault("truth has " + std::to_string(log.truth.size()) + " entries for " +
                std::to_string(log.frames.size()) + " frames");
  v1::TrackerLog out;
  to_pb(log.header, out.mutable_header());
  out.mutable_frames()->Reserve(static_cast<int>(log.frames.size()));
  for (const auto& f : log.frames) to_pb(f, out.add_frames());
  for (const auto& t : log.truth) to_pb(t, out.add_truth());
  return out;
}

// --- protobuf -> C++ (every structural check happens here, for both encodings) ---------------------

template <std::size_t N>
std::array<double, N> take(const RepeatedField<double>& r, const std::string& where) {
  if (r.size() != static_cast<int>(N))
    throw fault(where + " has " + std::to_string(r.size()) + " values, expected " + std::to_string(N));
  std::array<double, N> a{};
  std::copy(r.begin(), r.end(), a.begin());
  return a;
}

State from_pb(v1::State s, const std::string& where) {
  switch (s) {
    case v1::STATE_SEARCH:
      return State::search;
    case v1::STATE_TRACK:
      return State::track;
    case v1::STATE_LOST:
      return State::lost;
    default:  // STATE_UNSPECIFIED (a missing state) or a number this version does not know
      throw fault(where + " is an unknown state (" + std::to_string(static_cast<int>(s)) + ")");
  }
}

RunHeader from_pb(const v1::RunHeader& h) {
  RunHeader out;
  out.version = h.version();
  if (out.version > kTrackerLogVersion)
    throw fault("version " + std::to_string(out.version) + " is newer than this reader's " +
                std::to_string(kTrackerLogVersion));
  if (out.version < 1) throw fault("header.version " + std::to_string(out.version) + " is not a version");
  out.run_id = h.run_id();
  out.video_id = h.video_id();
  out.tracker_version = h.tracker_version();
  for (const auto& p : h.params()) out.params.push_back({p.name(), p.value()});
  for (const auto& t : h.template_bank()) out.template_bank.push_back({t.radius_px(), t.size_px()});
  const auto& in = h.intrinsics();
  out.intrinsics = {in.fx(), in.fy(), in.cx(), in.cy(), in.width(), in.height(), in.defaulted()};
  out.fps = h.fps();
  out.frame_count = h.frame_count();
  out.created_utc = h.created_utc();
  if (!h.video_source_json().empty()) {
    out.video_source = nlohmann::json::parse(h.video_source_json(), nullptr, false);
    if (out.video_source.is_discarded()) throw fault("header.videoSourceJson is not JSON text");
  }
  return out;
}

FrameLog from_pb(const v1::Frame& f, std::size_t i, std::size_t templates) {
  const std::string where = at("frames", i);
  FrameLog out;
  out.index = f.index();
  out.timestamp_s = f.timestamp_s();
  out.valid_pixels = f.valid_pixels();
  out.flying_pixels = f.flying_pixels();
  out.matches = f.matches();
  out.verified = f.verified();
  out.candidates.reserve(f.candidates_size());
  for (int k = 0; k < f.candidates_size(); ++k) {
    const auto& c = f.candidates(k);
    const std::string cw = where + "." + at("candidates", k);
    // Consumers index the template bank and the teat arrays with these, so they are checked here.
    if (c.template_index() < 0 || static_cast<std::size_t>(c.template_index()) >= templates)
      throw fault(cw + ".templateIndex " + std::to_string(c.template_index()) + " is not in the bank of " +
                  std::to_string(templates));
    if (c.teat() < -1 || c.teat() >= tof::kTeatCount)
      throw fault(cw + ".teat " + std::to_string(c.teat()) + " is not -1..3");
    out.candidates.push_back({c.u(), c.v(), c.ncc(), c.template_index(), c.verified(),
                              take<3>(c.tip_mm(), cw + ".tipMm"), take<3>(c.axis(), cw + ".axis"),
                              c.radius_mm(), c.fit_rms_mm(), c.points(), c.teat()});
  }
  const auto& m = f.model();
  out.model.pair_mm = take<6>(m.pair_mm(), where + ".model.pairMm");
  out.model.pair_error_mm = take<6>(m.pair_error_mm(), where + ".model.pairErrorMm");
  out.model.shape_cost = m.shape_cost();
  out.model.ncc_cost = m.ncc_cost();
  out.model.cost = m.cost();
  out.model.teats_matched = m.teats_matched();
  out.state = from_pb(f.state(), where + ".state");
  if (f.teats_size() != tof::kTeatCount)
    throw fault(where + ".teats has " + std::to_string(f.teats_size()) + " entries, expected 4");
  for (int t = 0; t < tof::kTeatCount; ++t) {
    const auto& q = f.teats(t);
    const std::string tw = where + "." + at("teats", t);
    out.teats[t] = {take<3>(q.tip_mm(), tw + ".tipMm"),
                    take<2>(q.tip_px(), tw + ".tipPx"),
                    q.visible(),
                    q.tracked(),
                    q.confidence(),
                    q.radius_mm()};
  }
  out.times = {f.times().preprocess_us(), f.times().detect_us(), f.times().verify_us(), f.times().model_us()};
  return out;
}

std::optional<tof::FrameTruth> from_pb(const v1::FrameTruthEntry& e, std::size_t i) {
  if (!e.has_truth()) return std::nullopt;
  const std::string where = at("truth", i) + ".value";
  if (e.value().teats_size() != tof::kTeatCount)
    throw fault(where + ".teats has " + std::to_string(e.value().teats_size()) + " entries, expected 4");
  tof::FrameTruth out;
  for (int t = 0; t < tof::kTeatCount; ++t) {
    const auto& q = e.value().teats(t);
    const std::string tw = where + "." + at("teats", t);
    auto& o = out.teats[t];
    o.tip_mm = take<3>(q.tip_mm(), tw + ".tipMm");
    if (q.tip_px_size() != 0) o.tip_px = take<2>(q.tip_px(), tw + ".tipPx");
    o.visible = q.visible();
    if (q.has_box_px()) o.box_px = tof::BoxPx{q.box_px().x(), q.box_px().y(), q.box_px().w(), q.box_px().h()};
    o.visible_fraction = q.visible_fraction();
    o.cup_attached = q.cup_attached();
  }
  return out;
}

TrackerLog from_pb(const v1::TrackerLog& in) {
  if (!in.has_header())
    throw Error(Error::Kind::unsupported_format, "log", "log: not a tracker log (no header)");
  TrackerLog out;
  out.header = from_pb(in.header());
  const std::size_t n = in.frames_size();
  if (n > static_cast<std::size_t>(limits::kMaxRunFrames))
    throw Error(
        Error::Kind::payload_too_large, "log",
        "log: " + std::to_string(n) + " frames exceed the limit of " + std::to_string(limits::kMaxRunFrames));
  // A binary cut at a field boundary parses cleanly; the header's count is what catches it.
  if (out.header.frame_count != n)
    throw fault("header.frameCount is " + std::to_string(out.header.frame_count) + " but the log has " +
                std::to_string(n) + " frames");
  if (in.truth_size() != 0 && static_cast<std::size_t>(in.truth_size()) != n)
    throw fault("truth has " + std::to_string(in.truth_size()) + " entries for " + std::to_string(n) +
                " frames");
  out.frames.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
    out.frames.push_back(from_pb(in.frames(static_cast<int>(i)), i, out.header.template_bank.size()));
  out.truth.reserve(in.truth_size());
  for (int i = 0; i < in.truth_size(); ++i) out.truth.push_back(from_pb(in.truth(i), i));
  return out;
}

// --- JSON ----------------------------------------------------------------------------------------------

/// The one set of printer options: every scalar printed (the web reads fields without defaults), enum
/// names, lowerCamelCase. frame_to_json and the whole-log JSON share it, hence their byte equality.
std::string to_json_text(const google::protobuf::Message& m) {
  google::protobuf::util::JsonPrintOptions o;
  o.add_whitespace = false;
  o.always_print_primitive_fields = true;
  o.always_print_enums_as_ints = false;
  o.preserve_proto_field_names = false;
  std::string s;
  const auto status = google::protobuf::util::MessageToJsonString(m, &s, o);
  if (!status.ok())
    throw Error(Error::Kind::internal, "log", "log: JSON printing failed: " + status.ToString());
  return s;
}

std::size_t first_non_blank(std::string_view bytes) {
  std::size_t i = 0;
  while (i < bytes.size() && (bytes[i] == ' ' || bytes[i] == '\t' || bytes[i] == '\n' || bytes[i] == '\r'))
    ++i;
  return i;
}

bool ends_with_json(const fs::path& p) {
  std::string ext = p.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return ext == ".json";
}

}  // namespace

std::string encode_log(const TrackerLog& log, LogEncoding encoding) {
  const v1::TrackerLog pb = to_pb(log);
  std::string out;
  if (encoding == LogEncoding::binary) {
    if (pb.ByteSizeLong() > limits::kMaxRunBytes)
      throw Error(Error::Kind::payload_too_large, "log",
                  "log: " + std::to_string(pb.ByteSizeLong()) + " bytes exceed the limit of " +
                      std::to_string(limits::kMaxRunBytes));
    if (!pb.SerializeToString(&out)) throw Error(Error::Kind::internal, "log", "log: serialisation failed");
  } else {
    out = to_json_text(pb);
  }
  // Never produce what decode_log would refuse.
  if (out.size() > limits::kMaxRunBytes)
    throw Error(Error::Kind::payload_too_large, "log",
                "log: " + std::to_string(out.size()) + " bytes exceed the limit of " +
                    std::to_string(limits::kMaxRunBytes));
  return out;
}

TrackerLog decode_log(std::string_view bytes) {
  if (bytes.size() > limits::kMaxRunBytes)
    throw Error(Error::Kind::payload_too_large, "log",
                "log: " + std::to_string(bytes.size()) + " bytes exceed the limit of " +
                    std::to_string(limits::kMaxRunBytes));
  const std::size_t start = first_non_blank(bytes);
  if (start == bytes.size()) throw Error(Error::Kind::unsupported_format, "log", "log: empty input");
  v1::TrackerLog pb;
  if (bytes[start] == '{') {
    google::protobuf::util::JsonParseOptions o;
    o.ignore_unknown_fields = false;  // a name this version does not know is a typo or a newer log
    const auto status = google::protobuf::util::JsonStringToMessage(
        google::protobuf::StringPiece(bytes.data(), bytes.size()), &pb, o);
    if (!status.ok()) {
      // Classify only on failure, so the happy path parses the text once.
      if (!nlohmann::json::accept(bytes))
        throw Error(Error::Kind::unsupported_format, "log", "log: not JSON text");
      throw fault("JSON does not fit the schema: " + std::string(status.message()));
    }
  } else if (!pb.ParseFromArray(bytes.data(), static_cast<int>(bytes.size()))) {
    throw Error(Error::Kind::unsupported_format, "log",
                "log: neither JSON nor a binary tracker log (or a truncated one)");
  }
  return from_pb(pb);
}

void write_log(const TrackerLog& log, const fs::path& path, bool overwrite) {
  if (!overwrite && fs::exists(path))
    throw Error(Error::Kind::conflict, "output", "output: " + path.string() + " exists");
  const std::string bytes = encode_log(log, ends_with_json(path) ? LogEncoding::json : LogEncoding::binary);
  // Hidden, random temporary name in the target's folder: rename() is atomic only within a filesystem,
  // and concurrent writers of one target never share a temporary file.
  std::random_device rd;
  char suffix[16];
  std::snprintf(suffix, sizeof suffix, ".tmp-%08x", static_cast<unsigned>(rd()));
  const fs::path temp = path.parent_path() / ("." + path.filename().string() + suffix);
  {
    std::ofstream out(temp, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
      std::error_code ec;
      fs::remove(temp, ec);
      throw Error(Error::Kind::internal, "output", "output: cannot write " + temp.string());
    }
  }
  std::error_code ec;
  fs::rename(temp, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(temp, ignored);
    throw Error(Error::Kind::internal, "output",
                "output: cannot rename to " + path.string() + ": " + ec.message());
  }
}

TrackerLog read_log(const fs::path& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw Error(Error::Kind::not_found, "log", "log: no such file " + path.string());
  const auto size = fs::file_size(path, ec);
  if (ec)
    throw Error(Error::Kind::internal, "log", "log: cannot read " + path.string() + ": " + ec.message());
  if (size > limits::kMaxRunBytes)
    throw Error(Error::Kind::payload_too_large, "log",
                "log: " + path.string() + " has " + std::to_string(size) + " bytes, more than the limit of " +
                    std::to_string(limits::kMaxRunBytes));
  std::ifstream in(path, std::ios::binary);
  std::string bytes(size, '\0');
  in.read(bytes.data(), static_cast<std::streamsize>(size));
  if (!in) throw Error(Error::Kind::internal, "log", "log: cannot read " + path.string());
  try {
    return decode_log(bytes);
  } catch (const Error& e) {
    throw Error(e.kind(), e.param(), path.string() + ": " + e.what());
  }
}

nlohmann::json frame_to_json(const FrameLog& frame) {
  v1::Frame pb;
  to_pb(frame, &pb);
  return nlohmann::json::parse(to_json_text(pb));
}

nlohmann::json header_to_json(const RunHeader& header) {
  v1::RunHeader pb;
  to_pb(header, &pb);
  return nlohmann::json::parse(to_json_text(pb));
}

}  // namespace trailscope::tracker
