// OpenSky CSV writer. Shortest round-trip number formatting (core/text.hpp) keeps the file small and
// makes write → ingest exact.
#include "trailscope/ingest/opensky_csv_writer.hpp"

#include <zlib.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "trailscope/core/error.hpp"
#include "trailscope/core/text.hpp"
#include "trailscope/ingest/reject.hpp"

namespace trailscope::ingest {
namespace {

// Plain or gzip output behind one interface; close() reports errors, the destructor only cleans up.
class Sink {
 public:
  Sink(const std::string& path, bool gzip) : path_(path), gzip_(gzip) {
    if (gzip) {
      gz_ = gzopen(path.c_str(), "wb1");
      if (gz_) gzbuffer(gz_, 1u << 20);
    } else {
      file_ = std::fopen(path.c_str(), "wb");
    }
    if (!gz_ && !file_)
      throw Error(Error::Kind::internal, "path",
                  "cannot create '" + path + "': " + std::generic_category().message(errno));
  }
  ~Sink() {
    if (gz_) gzclose(gz_);
    if (file_) std::fclose(file_);
  }
  void write(const std::string& data) {
    if (data.empty()) return;
    const bool ok = gzip_ ? gzwrite(gz_, data.data(), static_cast<unsigned>(data.size())) == int(data.size())
                          : std::fwrite(data.data(), 1, data.size(), file_) == data.size();
    if (!ok) fail("write");
  }
  void close() {
    const bool ok = gzip_ ? gzclose(gz_) == Z_OK : std::fclose(file_) == 0;
    gz_ = nullptr, file_ = nullptr;
    if (!ok) fail("close");
  }

 private:
  [[noreturn]] void fail(const char* what) {
    throw Error(
        Error::Kind::internal, "path",
        std::string("cannot ") + what + " '" + path_ + "': " + std::generic_category().message(errno));
  }
  std::string path_;
  bool gzip_;
  gzFile gz_ = nullptr;
  std::FILE* file_ = nullptr;
};

void put_number(std::string& out, float v) {
  if (!std::isnan(v)) append_shortest(out, v);  // unknown → empty field
}

}  // namespace

void write_opensky_csv(const TrailSet& set, const std::string& path, bool gzip) {
  const auto& flights = set.flights();
  for (std::size_t i = 0; i < flights.size(); ++i)
    if (!is_icao24(flights[i].icao24))
      throw invalid_argument("dataset", "flight " + std::to_string(i) + " (callsign '" + flights[i].callsign +
                                            "') has no valid icao24; OpenSky CSV rows are keyed by icao24");

  const std::string tmp = path + ".part";
  constexpr std::size_t kFlushBytes = 4u << 20;
  try {
    Sink sink(tmp, gzip);
    std::string out;
    out.reserve(kFlushBytes + 4096);
    out += kOpenSkyCsvHeader;
    out += '\n';
    const PointColumns& p = set.points();
    std::string time;
    std::string callsign;
    for (const Flight& f : flights) {
      // Callsigns are A-Z0-9 in practice; quote anything that would break the row.
      callsign = f.callsign;
      if (callsign.find_first_of(",\"\n") != std::string::npos) {
        std::string q = "\"";
        for (char c : callsign) q += c == '"' ? std::string("\"\"") : std::string(1, c == '\n' ? ' ' : c);
        callsign = q + "\"";
      }
      for (std::uint32_t i = f.begin; i < f.end; ++i) {
        time.clear();
        append_shortest(time, p.t[i]);
        out += time;
        out += ',';
        out += f.icao24;
        out += ',';
        put_number(out, p.lat[i]);
        out += ',';
        put_number(out, p.lon[i]);
        out += ',';
        put_number(out, p.speed[i]);
        out += ',';
        put_number(out, p.track[i]);
        out += ',';
        put_number(out, p.vrate[i]);
        out += ',';
        out += callsign;
        out += p.on_ground[i] ? ",true,false,false,," : ",false,false,false,,";
        put_number(out, p.alt[i]);
        out += ",,";
        out += time;
        out += ',';
        out += time;
        out += '\n';
        if (out.size() >= kFlushBytes) {
          sink.write(out);
          out.clear();
        }
      }
    }
    sink.write(out);
    sink.close();
    std::error_code ec;
    std::filesystem::rename(tmp, path, ec);
    if (ec)
      throw Error(Error::Kind::internal, "path",
                  "cannot rename '" + tmp + "' to '" + path + "': " + ec.message());
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    throw;
  }
}

}  // namespace trailscope::ingest
