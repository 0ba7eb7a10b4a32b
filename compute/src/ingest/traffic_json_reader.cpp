// traffic (X. Olive) JSON records, as pandas writes them (`orient="records"`): a JSON array, often a
// single line of hundreds of megabytes, or JSON Lines. The array is parsed with nlohmann's SAX interface
// straight from the decompressing stream, so memory stays flat whatever the file size.
#include <istream>

#include <nlohmann/json.hpp>

#include "ingest/detail.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::ingest::detail {
namespace {

using json = nlohmann::json;

enum class Field {
  none,
  timestamp,
  icao24,
  callsign,
  latitude,
  longitude,
  altitude,
  geoaltitude,
  groundspeed,
  track,
  vertical_rate,
  onground
};

Field field_of(const std::string& k) {
  switch (k.size()) {
    case 5:
      return k == "track" ? Field::track : Field::none;
    case 6:
      return k == "icao24" ? Field::icao24 : Field::none;
    case 8:
      if (k == "latitude") return Field::latitude;
      if (k == "altitude") return Field::altitude;
      if (k == "callsign") return Field::callsign;
      if (k == "onground") return Field::onground;
      return Field::none;
    case 9:
      if (k == "timestamp") return Field::timestamp;
      if (k == "longitude") return Field::longitude;
      return Field::none;
    case 11:
      if (k == "groundspeed") return Field::groundspeed;
      if (k == "geoaltitude") return Field::geoaltitude;
      return Field::none;
    case 13:
      return k == "vertical_rate" ? Field::vertical_rate : Field::none;
    default:
      return Field::none;
  }
}

const char* field_name(Field f) {
  constexpr const char* names[] = {
      "",         "timestamp",   "icao24",      "callsign", "latitude",      "longitude",
      "altitude", "geoaltitude", "groundspeed", "track",    "vertical_rate", "onground"};
  return names[static_cast<int>(f)];
}

// Unix milliseconds (pandas' default) or seconds: no real trail is from 1973, when ms pass 1e11.
double epoch_seconds(double v) {
  return std::fabs(v) >= 1e11 ? v / 1000.0 : v;
}

class RecordSax : public json::json_sax_t {
 public:
  // `record_depth` is the nesting depth of a record object: 2 inside a top-level array, 1 for JSON Lines.
  // With `deferred` (JSON Lines) a record is only validated by finish(), once its whole line has parsed:
  // a line such as `{...} garbage` must be one rejected row, not an accepted record plus an error.
  RecordSax(ReadContext& ctx, int record_depth, bool deferred)
      : ctx_(ctx), record_depth_(record_depth), deferred_(deferred) {}

  /// 1-based record index (array) or line number (JSON Lines) used in rejects.
  std::size_t index = 0;
  bool syntax_error = false;
  std::string error_message;
  std::size_t error_position = 0;

  void reset() {
    depth_ = 0;
    in_record_ = false;
    syntax_error = false;
    pending_ = Pending::nothing;
  }
  /// JSON Lines: counts and validates the line's record after sax_parse() returned.
  void finish(std::size_t line_no) {
    index = line_no;
    const Pending p = pending_;
    pending_ = Pending::nothing;
    if (syntax_error) {
      ctx_.row();
      ctx_.reject(line_no, [&] { return "invalid JSON: " + error_message; });
    } else if (p == Pending::record) {
      validate();
    } else if (p == Pending::not_record) {
      ctx_.row();
      ctx_.reject(line_no, [] { return "record is not a JSON object"; });
    }
  }

  bool null() override {
    // A null value leaves its field unknown; a missing time or position is reported by validate().
    if (!at_value() && at_element()) not_a_record();
    return true;
  }
  bool boolean(bool v) override {
    if (at_value()) {
      if (field_ == Field::onground)
        onground_ = v;
      else if (field_ != Field::none && field_ != Field::callsign)
        bad_value();
    } else if (at_element()) {
      not_a_record();
    }
    return true;
  }
  bool number_integer(number_integer_t v) override {
    return number(static_cast<double>(v), v >= 0, static_cast<std::uint64_t>(v));
  }
  bool number_unsigned(number_unsigned_t v) override { return number(static_cast<double>(v), true, v); }
  bool number_float(number_float_t v, const string_t&) override { return number(v, false, 0); }
  bool string(string_t& v) override {
    if (at_value()) {
      switch (field_) {
        case Field::none:
          break;
        case Field::icao24:
          icao_.assign(v);
          break;
        case Field::callsign:
          callsign_.assign(v);
          break;
        case Field::timestamp: {
          double t;
          if (parse_iso8601(v, t))
            has_time_ = true, t_ = t;
          else if (parse_number(std::string_view(v), t) == Num::ok)
            has_time_ = true, t_ = epoch_seconds(t);
          else if (!is_null_token(trim(v)))
            bad_value(v);
          break;
        }
        case Field::onground:
          if (v == "true" || v == "True")
            onground_ = true;
          else if (v == "false" || v == "False" || v.empty())
            onground_ = false;
          else
            bad_value(v);
          break;
        default: {  // a number written as a string
          double d;
          const Num n = parse_number(std::string_view(v), d);
          if (n == Num::ok)
            set_number(d);
          else if (n == Num::bad)
            bad_value(v);
        }
      }
    } else if (at_element()) {
      not_a_record();
    }
    return true;
  }
  bool binary(binary_t&) override { return true; }
  bool start_object(std::size_t) override {
    if (depth_ == record_depth_ - 1)
      begin_record();
    else if (at_value())
      bad_value();
    ++depth_;
    return true;
  }
  bool key(string_t& k) override {
    if (in_record_ && depth_ == record_depth_) field_ = field_of(k);
    return true;
  }
  bool end_object() override {
    if (--depth_ == record_depth_ - 1 && in_record_) end_record();
    return true;
  }
  bool start_array(std::size_t) override {
    if (depth_ == record_depth_ - 1)
      not_a_record();
    else if (at_value())
      bad_value();
    ++depth_;
    return true;
  }
  bool end_array() override {
    --depth_;
    return true;
  }
  bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& ex) override {
    syntax_error = true;
    error_position = position;
    error_message = ex.what();
    return false;
  }

 private:
  bool at_value() const { return in_record_ && depth_ == record_depth_ && field_ != Field::none; }
  bool at_element() const { return depth_ == record_depth_ - 1; }

  bool number(double d, bool non_negative_integer, std::uint64_t u) {
    if (at_value()) {
      if (field_ == Field::icao24) {
        // pandas may have turned an all-digit address such as "484506" into a number.
        if (non_negative_integer && u <= 999999) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "%06u", static_cast<unsigned>(u));
          icao_.assign(buf);
        } else {
          bad_value(std::to_string(d));
        }
      } else if (field_ == Field::onground) {
        onground_ = d != 0;
      } else if (field_ == Field::callsign) {
        if (non_negative_integer)
          callsign_ = std::to_string(u);
        else
          bad_value();
      } else {
        set_number(d);
      }
    } else if (at_element()) {
      not_a_record();
    }
    return true;
  }
  void set_number(double d) {
    switch (field_) {
      case Field::timestamp:
        has_time_ = true, t_ = epoch_seconds(d);
        break;
      case Field::latitude:
        lat_ = d, has_lat_ = true;
        break;
      case Field::longitude:
        lon_ = d, has_lon_ = true;
        break;
      case Field::altitude:
        alt_ = d;
        break;
      case Field::geoaltitude:
        geoalt_ = d;
        break;
      case Field::groundspeed:
        gs_ = d;
        break;
      case Field::track:
        track_ = d;
        break;
      case Field::vertical_rate:
        vrate_ = d;
        break;
      default:
        break;
    }
  }
  void bad_value(std::string_view v = {}) {
    if (problem_.empty())
      problem_ =
          std::string("bad value for '") + field_name(field_) + "'" + (v.empty() ? "" : ": " + quote(v));
  }
  void not_a_record() {
    if (deferred_) {
      pending_ = Pending::not_record;
      return;
    }
    ++index;
    ctx_.row();
    ctx_.reject(index, [] { return "record is not a JSON object"; });
  }
  void begin_record() {
    in_record_ = true;
    field_ = Field::none;
    has_time_ = has_lat_ = has_lon_ = false;
    onground_ = false;
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();
    alt_ = geoalt_ = gs_ = track_ = vrate_ = nan;
    icao_.clear(), callsign_.clear(), problem_.clear();
  }
  void end_record() {
    in_record_ = false;
    if (deferred_) {
      pending_ = Pending::record;
      return;
    }
    ++index;
    validate();
  }
  void validate() {
    ctx_.row();
    if (!problem_.empty()) return ctx_.reject(index, [&] { return problem_; });
    if (!has_time_) return ctx_.reject(index, [] { return "time missing ('timestamp')"; });
    const std::string_view icao = trim(icao_);
    if (icao.empty()) return ctx_.reject(index, [] { return "icao24 missing"; });
    if (!is_icao24(icao))
      return ctx_.reject(index, [&] { return "bad icao24 " + quote(icao) + " (expected 6 hex digits)"; });
    if (!has_lat_ || !has_lon_)
      return ctx_.reject(index, [] { return "missing position (latitude/longitude)"; });
    Sample s;
    s.t = t_;
    s.lat = static_cast<float>(lat_), s.lon = static_cast<float>(lon_);
    const double alt_ft = std::isnan(alt_) ? geoalt_ : alt_;
    s.alt = static_cast<float>(alt_ft * kFeet);
    s.speed = static_cast<float>(gs_ * kKnot);
    s.track = static_cast<float>(track_);
    s.vrate = static_cast<float>(vrate_ * kFeetPerMinute);
    s.on_ground = onground_;
    ctx_.accept(index, icao, trim(callsign_), s);
  }

  enum class Pending { nothing, record, not_record };
  ReadContext& ctx_;
  const int record_depth_;
  const bool deferred_;
  Pending pending_ = Pending::nothing;
  int depth_ = 0;
  bool in_record_ = false;
  Field field_ = Field::none;
  bool has_time_ = false, has_lat_ = false, has_lon_ = false, onground_ = false;
  double t_ = 0, lat_ = 0, lon_ = 0, alt_ = 0, geoalt_ = 0, gs_ = 0, track_ = 0, vrate_ = 0;
  std::string icao_, callsign_, problem_;
};

}  // namespace

void read_traffic_json(ReadContext& ctx) {
  const std::string_view head = ctx.src.head();
  const std::size_t first = head.find_first_not_of(" \t\r\n\f\xef\xbb\xbf");
  const char c = first == std::string_view::npos ? '\0' : head[first];
  if (c == '[') {
    ctx.src.start(/*line_aligned=*/false);
    SourceStreambuf buf(ctx.src);
    std::istream in(&buf);
    RecordSax sax(ctx, 2, /*deferred=*/false);
    json::sax_parse(in, &sax, json::input_format_t::json, /*strict=*/true);
    if (sax.syntax_error)
      throw Error(Error::Kind::unprocessable, "file",
                  "invalid JSON after record " + std::to_string(sax.index) + " (byte " +
                      std::to_string(sax.error_position) + "): " + sax.error_message);
    return;
  }
  if (c != '{')
    throw Error(Error::Kind::unsupported_format, "format",
                "not traffic JSON: expected a JSON array '[' or JSON Lines objects '{' at the start");
  // JSON Lines: one record per line; a malformed line is a rejected row, not a fatal error.
  ctx.src.start(/*line_aligned=*/true);
  RecordSax sax(ctx, 1, /*deferred=*/true);
  std::size_t line_no = 0;
  for (std::string_view block = ctx.src.next(); !block.empty(); block = ctx.src.next()) {
    std::size_t pos = 0;
    while (pos < block.size()) {
      std::size_t nl = block.find('\n', pos);
      if (nl == std::string_view::npos) nl = block.size();
      const std::string_view line = trim(block.substr(pos, nl - pos));
      pos = nl + 1;
      ++line_no;
      if (line.empty()) continue;
      sax.reset();
      json::sax_parse(line.begin(), line.end(), &sax, json::input_format_t::json, /*strict=*/true);
      sax.finish(line_no);
    }
  }
}

}  // namespace trailscope::ingest::detail
