// readsb "trace_full" JSON (adsb.lol / ADS-B Exchange globe_history): one aircraft, a base time and an
// array of compact rows. Such files hold one aircraft-day (a few MB), so a DOM parse is simplest.
#include <istream>

#include <nlohmann/json.hpp>

#include "ingest/detail.hpp"
#include "trailscope/core/error.hpp"

namespace trailscope::ingest::detail {
namespace {

using json = nlohmann::json;

// Row layout (readsb README-json.md, "trace" arrays).
enum : std::size_t {
  kDt = 0,
  kLat,
  kLon,
  kAlt,
  kGs,
  kTrack,
  kFlags,
  kRate,
  kDetails,
  kSource,
  kGeomAlt,
  kGeomRate
};

const json& at(const json& row, std::size_t i) {
  static const json null_value;
  return i < row.size() ? row[i] : null_value;
}

// The callsign in a details object, trimmed; empty when absent or null.
std::string_view flight_of(const json& details) {
  if (!details.is_object()) return {};
  const auto it = details.find("flight");
  if (it == details.end() || !it->is_string()) return {};
  return trim(it->get_ref<const std::string&>());
}

}  // namespace

void read_readsb_trace(ReadContext& ctx) {
  ctx.src.start(/*line_aligned=*/false);
  SourceStreambuf buf(ctx.src);
  std::istream in(&buf);
  json doc;
  try {
    doc = json::parse(in);
  } catch (const json::exception& e) {
    // parse_error for bad syntax, out_of_range for a number beyond double's range ("1e999").
    throw Error(Error::Kind::unprocessable, "file", std::string("invalid JSON in readsb trace: ") + e.what());
  }
  if (ctx.opts.cancel) ctx.opts.cancel->throw_if_cancelled();
  const auto need = [&](const char* key, bool ok) {
    if (!ok)
      throw Error(Error::Kind::unsupported_format, "format",
                  std::string("not a readsb trace_full: '") + key + "' is missing or has the wrong type");
  };
  need("icao", doc.is_object() && doc.contains("icao") && doc["icao"].is_string());
  need("timestamp", doc.contains("timestamp") && doc["timestamp"].is_number());
  need("trace", doc.contains("trace") && doc["trace"].is_array());

  std::string_view icao = doc["icao"].get_ref<const std::string&>();
  if (!icao.empty() && icao.front() == '~') icao.remove_prefix(1);  // readsb: non-ICAO (e.g. TIS-B) address
  if (!is_icao24(icao))
    throw Error(Error::Kind::unprocessable, "file",
                "the readsb trace's icao " + quote(icao) + " is not a 24-bit address (6 hex digits)");
  const double base = doc["timestamp"].get<double>();
  const json& trace = doc["trace"];

  // Details objects come only when something changes or once a minute; rows before the first one belong
  // to the same flight, so they take the first callsign of the trace.
  std::string callsign;
  for (const json& row : trace)
    if (row.is_array())
      if (const std::string_view f = flight_of(at(row, kDetails)); !f.empty()) {
        callsign.assign(f);
        break;
      }

  std::size_t index = 0;
  for (const json& row : trace) {
    ++index;
    ctx.row();
    if (!row.is_array()) {
      ctx.reject(index, [] { return "trace entry is not an array"; });
      continue;
    }
    if (const std::string_view f = flight_of(at(row, kDetails)); !f.empty()) callsign.assign(f);
    const json &dt = at(row, kDt), &lat = at(row, kLat), &lon = at(row, kLon), &alt = at(row, kAlt);
    if (!dt.is_number()) {
      ctx.reject(index, [] { return "time missing (trace entry element 0)"; });
      continue;
    }
    if (!lat.is_number() || !lon.is_number()) {
      ctx.reject(index, [] { return "missing position (trace entry elements 1, 2)"; });
      continue;
    }
    Sample s;
    s.t = base + dt.get<double>();
    s.lat = lat.get<float>(), s.lon = lon.get<float>();
    if (alt.is_number()) {
      s.alt = static_cast<float>(alt.get<double>() * kFeet);
    } else if (alt.is_string() && alt.get_ref<const std::string&>() == "ground") {
      s.on_ground = true;  // readsb sends no altitude on the ground; NaN rather than a false sea level
    } else if (!alt.is_null()) {
      ctx.reject(index, [&] { return "bad altitude " + quote(alt.dump()); });
      continue;
    }
    const json &gs = at(row, kGs), &track = at(row, kTrack);
    if (gs.is_number()) s.speed = static_cast<float>(gs.get<double>() * kKnot);
    if (track.is_number()) s.track = track.get<float>();
    const json& rate = at(row, kRate).is_number() ? at(row, kRate) : at(row, kGeomRate);
    if (rate.is_number()) s.vrate = static_cast<float>(rate.get<double>() * kFeetPerMinute);
    ctx.accept(index, icao, callsign, s);
  }
}

}  // namespace trailscope::ingest::detail
