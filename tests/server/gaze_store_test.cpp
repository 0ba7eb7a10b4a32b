// Stored gaze datasets over the routes (routes/gaze.cpp, store/gaze_store.hpp): real files of the shared
// data ingested through POST /api/v1/gaze with counts made here from the text, events against the
// detectors called directly and against a hand-computed recording, scanpaths, delete, restart, leftovers,
// the binary file's round trip and refusals, stimulus images, and the exact errors.
#include <cmath>
#include <fstream>
#include <sstream>

#include "auth/token_store.hpp"
#include "jobs/job_manager.hpp"
#include "route_fixture.hpp"
#include "store/gaze_file.hpp"
#include "store/gaze_store.hpp"
#include "trailscope/gaze/events.hpp"
#include "trailscope/gaze/ingest.hpp"
#include "trailscope/gaze/query.hpp"

namespace trailscope::server::test_routes {
namespace {
namespace fs = std::filesystem;
using trailscope::test::shared_data;

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Lines of `text` starting with `prefix` (or, with prefix "#digit", with a digit).
std::size_t lines_starting(const std::string& text, const std::string& prefix) {
  std::size_t n = 0;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (prefix == "#digit" ? (!line.empty() && std::isdigit(static_cast<unsigned char>(line[0])))
                           : line.rfind(prefix, 0) == 0)
      ++n;
  return n;
}

std::size_t non_empty_lines(const std::string& text) {
  std::size_t n = 0;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (!line.empty() && line != "\r") ++n;
  return n;
}

/// A recording in degrees at 500 Hz: 100 samples at (0, 0), 19 saccade samples 0.5 deg apart, 100 samples
/// at (10, 0). Computed by hand for I-VT at 30 deg/s (central differences, events.hpp): samples 99 and 119
/// touch the jump (0.5 deg over 4 ms = 125 deg/s), so the saccade is samples 99..119 (198..238 ms), the
/// fixations 0..98 (0..196 ms) at (0, 0) and 120..218 (240..436 ms) at (10, 0).
std::string tiny_csv() {
  std::string out = "time,x_deg,y_deg\n";
  double t = 0;
  const auto add = [&](double x, double y) {
    out += std::to_string(t) + "," + std::to_string(x) + "," + std::to_string(y) + "\n";
    t += 2;
  };
  for (int i = 0; i < 100; ++i) add(0, 0);
  for (int k = 1; k < 20; ++k) add(10.0 * k / 20, 0);
  for (int i = 0; i < 100; ++i) add(10, 0);
  return out;
}

class GazeStoreTest : public RouteFixture {
 protected:
  void SetUp() override {
    writer = TokenStore(tmp.path() / "store" / "tokens.json").create("bob", Role::writer).token;
    open_app();
  }
  /// A request of the writer "bob" (not the admin the router sends by default).
  Response as_writer(const std::string& method, const std::string& path, std::string body = {},
                     std::map<std::string, std::string> query = {}) {
    return send(method, path, std::move(body), std::move(query), {{"authorization", "Bearer " + writer}});
  }
  std::string writer;
  void open_app() {
    router = Router();
    app.reset();
    store = std::make_shared<EmbeddedStore>(tmp.path() / "store");
    app = std::make_unique<App>(store, store->upload_dir(), fs::path(), limits::kTileCacheBytes,
                                tmp.path() / "store");
    router = make_router(*app);
  }
  /// Uploads `content` as gaze dataset `name` and waits for its job.
  JobState upload(const std::string& name, const std::string& content,
                  std::map<std::string, std::string> query = {}) {
    query["name"] = name;
    const Response r = send("POST", "/api/v1/gaze", content, query);
    EXPECT_EQ(r.status, 202) << r.body;
    if (r.status != 202) return {};
    return app->jobs.wait(body(r).at("job").at("id").get<std::string>());
  }
  nlohmann::json uploaded(const std::string& name, const std::string& content,
                          std::map<std::string, std::string> query = {}) {
    const JobState s = upload(name, content, std::move(query));
    EXPECT_EQ(s.state, "done") << s.to_json().dump();
    return s.result;
  }
  static std::map<std::string, std::string> lund_geometry() {
    return {{"width_px", "1024"},
            {"height_px", "768"},
            {"width_cm", "38"},
            {"height_cm", "30"},
            {"distance_cm", "67"}};
  }
};

TEST_F(GazeStoreTest, RealFilesIngestWithTheCountsOfTheirText) {
  // EyeLink: one recording per START block, a sample per line starting with a digit.
  const fs::path asc = shared_data("gaze/eyelinker_sr_research/mono500.asc");
  const std::string asc_text = slurp(asc);
  auto res = uploaded("mono500", asc_text);
  EXPECT_EQ(res.at("gaze"), "mono500");
  EXPECT_EQ(res.at("recordings").get<std::size_t>(), lines_starting(asc_text, "START"));
  EXPECT_EQ(res.at("samples").get<std::size_t>(), lines_starting(asc_text, "#digit"));
  const auto meta = body(get("/api/v1/gaze/mono500"));
  EXPECT_EQ(meta.at("format"), "eyelink_asc");
  EXPECT_EQ(meta.at("owner"), "test-admin");  // the admin token the router sends
  EXPECT_EQ(meta.at("recording_list").size(), lines_starting(asc_text, "START"));
  std::size_t sum = 0;
  for (const auto& r : meta.at("recording_list")) sum += r.at("samples").get<std::size_t>();
  EXPECT_EQ(sum, lines_starting(asc_text, "#digit"));
  EXPECT_EQ(meta.at("recording_list")[0].at("geometry").at("width_px"), 1024);  // DISPLAY_COORDS 0 0 1023 767

  // Lund 2013 TSV: a header and one sample per line.
  const std::string lund = slurp(shared_data("gaze/andersson2017_lund/tsv/TH34_img_Europe.tsv"));
  res = uploaded("lund", lund, lund_geometry());
  EXPECT_EQ(res.at("recordings"), 1);
  EXPECT_EQ(res.at("samples").get<std::size_t>(), non_empty_lines(lund) - 1);

  // Tobii TX300 (I2MC layout): a header and one sample per line; normalised coordinates need the size.
  const std::string tobii = slurp(shared_data("gaze/i2mc_tobii_tx300/participant1/1.txt"));
  res = uploaded("tobii", tobii, {{"width_px", "1920"}, {"height_px", "1080"}, {"participant", "p1"}});
  EXPECT_EQ(res.at("samples").get<std::size_t>(), non_empty_lines(tobii) - 1);
  const auto tmeta = body(get("/api/v1/gaze/tobii"));
  EXPECT_EQ(tmeta.at("format"), "tobii_tsv");
  EXPECT_EQ(tmeta.at("participants"), nlohmann::json::array({"p1"}));

  const auto list = body(get("/api/v1/gaze")).at("datasets");
  ASSERT_EQ(list.size(), 3u);
  EXPECT_EQ(list[0].at("id"), "lund");  // by id
  EXPECT_FALSE(list[0].contains("recording_list"));
  EXPECT_EQ(list[1].at("samples").get<std::size_t>(), lines_starting(asc_text, "#digit"));
}

TEST_F(GazeStoreTest, EventsAreTheDetectorsOnTheFile) {
  const fs::path file = shared_data("gaze/andersson2017_lund/tsv/TH34_img_Europe.tsv");
  uploaded("lund", slurp(file), lund_geometry());
  gaze::GazeIngestOptions o;
  o.geometry = {1024, 768, 38, 30, 67};
  const gaze::Recording rec = gaze::read_gaze_file(file.string(), o).recordings.at(0);
  for (const std::string method : {"ivt", "idt", "adaptive"}) {
    gaze::EventParams p;
    p.method = gaze::parse_method(method);
    const gaze::Detection d = gaze::detect_events(rec, p);
    const auto j = body(get("/api/v1/gaze/lund/events", {{"method", method}}));
    EXPECT_EQ(j.at("method"), method);
    const auto& ev = j.at("events");
    ASSERT_EQ(ev.size(), d.events.size()) << method;
    std::map<std::string, std::size_t> counts;
    std::size_t k = 0;  // sample index walking with the events
    for (std::size_t i = 0; i < ev.size(); ++i) {
      EXPECT_EQ(ev[i].at("type"), gaze::to_string(d.events[i].type));
      EXPECT_EQ(ev[i].at("t_start_ms").get<double>(), d.events[i].t_start_ms);
      EXPECT_EQ(ev[i].at("t_end_ms").get<double>(), d.events[i].t_end_ms);
      EXPECT_EQ(ev[i].at("recording"), 0);
      ++counts[ev[i].at("type").get<std::string>()];
      // The fixation's centroid, summed here over the samples of its time span.
      while (rec.t_ms[k] < d.events[i].t_start_ms) ++k;
      if (d.events[i].type == gaze::EventType::fixation) {
        double sx = 0;
        std::size_t n = 0;
        for (std::size_t s = k; s < rec.size() && rec.t_ms[s] <= d.events[i].t_end_ms; ++s)
          if (rec.valid[s] && d.labels[s] == gaze::EventType::fixation) sx += rec.x[s], ++n;
        ASSERT_GT(n, 0u);
        EXPECT_NEAR(ev[i].at("x").get<double>(), sx / double(n), 1e-9);
        EXPECT_TRUE(ev[i].at("x_end").is_null());
      }
    }
    for (const auto& [type, n] : counts) EXPECT_EQ(j.at("counts").at(type), n) << type;
  }
  // Types and a window: the saccades starting in [1000, 2000) ms after the first sample.
  gaze::EventParams p;
  const gaze::Detection d = gaze::detect_events(rec, p);
  std::size_t want = 0;
  for (const auto& e : d.events)
    want += e.type == gaze::EventType::saccade && e.t_start_ms - rec.t_ms[0] >= 1000 &&
            e.t_start_ms - rec.t_ms[0] < 2000;
  const auto j =
      body(get("/api/v1/gaze/lund/events", {{"type", "saccade"}, {"t0_ms", "1000"}, {"t1_ms", "2000"}}));
  EXPECT_EQ(j.at("events").size(), want);
  EXPECT_EQ(j.at("counts"), nlohmann::json({{"saccade", want}}));
  EXPECT_GT(want, 0u);
}

TEST_F(GazeStoreTest, EventsOfAHandComputedRecording) {
  uploaded("tiny", tiny_csv());
  auto j = body(get("/api/v1/gaze/tiny/events", {{"velocity_threshold", "30"}}));
  const auto& ev = j.at("events");
  ASSERT_EQ(ev.size(), 3u) << j.dump();
  EXPECT_EQ(ev[0], nlohmann::json({{"recording", 0},
                                   {"type", "fixation"},
                                   {"t_start_ms", 0.0},
                                   {"t_end_ms", 196.0},
                                   {"duration_ms", 196.0},
                                   {"x", 0.0},
                                   {"y", 0.0},
                                   {"x_end", nullptr},
                                   {"y_end", nullptr}}));
  EXPECT_EQ(ev[1], nlohmann::json({{"recording", 0},
                                   {"type", "saccade"},
                                   {"t_start_ms", 198.0},
                                   {"t_end_ms", 238.0},
                                   {"duration_ms", 40.0},
                                   {"x", 0.0},
                                   {"y", 0.0},
                                   {"x_end", 10.0},
                                   {"y_end", 0.0}}));
  EXPECT_EQ(ev[2].at("t_start_ms"), 240.0);
  EXPECT_EQ(ev[2].at("t_end_ms"), 436.0);
  EXPECT_EQ(ev[2].at("x"), 10.0);
  EXPECT_EQ(j.at("counts").at("fixation"), 2);
  EXPECT_EQ(j.at("counts").at("saccade"), 1);
  EXPECT_EQ(j.at("counts").at("blink"), 0);
  // The window keeps events by their first sample: from 200 ms only the second fixation.
  j = body(get("/api/v1/gaze/tiny/events", {{"t0_ms", "200"}}));
  ASSERT_EQ(j.at("events").size(), 1u);
  EXPECT_EQ(j.at("events")[0].at("t_start_ms"), 240.0);
  j = body(get("/api/v1/gaze/tiny/events", {{"t1_ms", "198.5"}}));
  EXPECT_EQ(j.at("events").size(), 2u);
  // A threshold above the saccade's 125-250 deg/s: one fixation throughout.
  j = body(get("/api/v1/gaze/tiny/events", {{"velocity_threshold", "300"}}));
  ASSERT_EQ(j.at("events").size(), 1u);
  EXPECT_EQ(j.at("events")[0].at("t_end_ms"), 436.0);
  // Scanpath: the two fixations in order.
  const auto s = body(get("/api/v1/gaze/tiny/scanpaths"));
  ASSERT_EQ(s.at("scanpaths").size(), 1u);
  EXPECT_EQ(s.at("scanpaths")[0].at("participant"), "tiny");  // the file names none: the dataset id
  EXPECT_EQ(s.at("scanpaths")[0].at("fixations"),
            nlohmann::json::parse(R"([{"x":0.0,"y":0.0,"t_start_ms":0.0,"duration_ms":196.0},
                                      {"x":10.0,"y":0.0,"t_start_ms":240.0,"duration_ms":196.0}])"));
}

TEST_F(GazeStoreTest, ScanpathsAreEachRecordingsFixationsInOrder) {
  // 84 START blocks; no geometry in the file, so it is given.
  uploaded("luke", slurp(shared_data("gaze/saccades_luketudge/example_eyelink_events.txt")),
           {{"width_px", "1024"},
            {"height_px", "768"},
            {"width_cm", "38"},
            {"height_cm", "30"},
            {"distance_cm", "60"}});
  const auto meta = body(get("/api/v1/gaze/luke"));
  const std::size_t n = meta.at("recordings");
  ASSERT_GT(n, 10u);
  const auto s = body(get("/api/v1/gaze/luke/scanpaths")).at("scanpaths");
  const auto ev = body(get("/api/v1/gaze/luke/events", {{"type", "fixation"}})).at("events");
  ASSERT_EQ(s.size(), n);
  std::size_t e = 0, total = 0;
  for (std::size_t r = 0; r < n; ++r) {
    EXPECT_EQ(s[r].at("recording"), r);
    EXPECT_EQ(s[r].at("participant"), meta.at("recording_list")[r].at("participant"));
    double last = -INFINITY;
    for (const auto& f : s[r].at("fixations")) {
      EXPECT_GT(f.at("t_start_ms").get<double>(), last);
      last = f.at("t_start_ms").get<double>();
      ASSERT_LT(e, ev.size());
      EXPECT_EQ(ev[e].at("recording"), r);
      EXPECT_EQ(ev[e].at("t_start_ms"), f.at("t_start_ms"));
      EXPECT_EQ(ev[e].at("x"), f.at("x"));
      ++e, ++total;
    }
  }
  EXPECT_EQ(total, ev.size());
  EXPECT_GT(total, n);
  // One recording alone.
  const auto one = body(get("/api/v1/gaze/luke/scanpaths", {{"recording", "3"}})).at("scanpaths");
  ASSERT_EQ(one.size(), 1u);
  EXPECT_EQ(one[0], s[3]);
}

TEST_F(GazeStoreTest, DeleteRestartAndLeftovers) {
  uploaded("tiny", tiny_csv());
  uploaded("gone", tiny_csv());
  const auto before = body(get("/api/v1/gaze/tiny"));
  const auto events = body(get("/api/v1/gaze/tiny/events"));
  EXPECT_EQ(send("DELETE", "/api/v1/gaze/gone").status, 204);
  expect_error(get("/api/v1/gaze/gone"), 404, "not_found", "gaze");
  EXPECT_EQ(body(get("/api/v1/gaze/gone")).at("detail"), "gaze dataset 'gone' does not exist");
  expect_error(get("/api/v1/gaze/gone/events"), 404, "not_found", "gaze");
  expect_error(send("DELETE", "/api/v1/gaze/gone"), 404, "not_found", "gaze");
  EXPECT_FALSE(fs::exists(tmp.path() / "store" / "gaze" / "gone"));
  // A staging folder a killed write left behind, and a finished one without its manifest.
  fs::create_directories(tmp.path() / "store" / "tmp" / "gaze.late.0123abcd");
  fs::create_directories(tmp.path() / "store" / "gaze" / "half");
  // Restart: a new App over the same folder.
  open_app();
  EXPECT_EQ(body(get("/api/v1/gaze/tiny")), before);
  EXPECT_EQ(body(get("/api/v1/gaze/tiny/events")), events);
  EXPECT_EQ(body(get("/api/v1/gaze")).at("datasets").size(), 1u);
  EXPECT_FALSE(fs::exists(tmp.path() / "store" / "tmp" / "gaze.late.0123abcd"));
  expect_error(get("/api/v1/gaze/half"), 404, "not_found", "gaze");
  // The name is free again after a delete.
  uploaded("gone", tiny_csv());
  // A CLI-side store keeps tmp/ (a server may be writing there).
  fs::create_directories(tmp.path() / "store" / "tmp" / "gaze.busy.1");
  GazeStore cli(tmp.path() / "store");
  EXPECT_TRUE(fs::exists(tmp.path() / "store" / "tmp" / "gaze.busy.1"));
  EXPECT_EQ(cli.size(), 2u);
}

TEST_F(GazeStoreTest, OnlyTheOwnerOrAnAdminDeletesOrChangesADataset) {
  uploaded("admins", tiny_csv(), {{"stimulus", "s"}});
  Response r = as_writer("DELETE", "/api/v1/gaze/admins");
  expect_error(r, 403, "forbidden", "gaze");
  EXPECT_EQ(body(r).at("detail"),
            "gaze dataset 'admins' belongs to 'test-admin'; only its owner or an admin may delete it");
  r = as_writer("PUT", "/api/v1/gaze/admins/stimulus", "x");
  expect_error(r, 403, "forbidden", "gaze");
  EXPECT_EQ(body(r).at("detail"),
            "gaze dataset 'admins' belongs to 'test-admin'; only its owner or an admin may change it");
  expect_error(as_writer("DELETE", "/api/v1/gaze/nope"), 404, "not_found", "gaze");  // 404 before 403
  // The writer's own dataset: recorded as bob's, deleted by bob.
  r = as_writer("POST", "/api/v1/gaze", tiny_csv(), {{"name", "bobs"}});
  ASSERT_EQ(r.status, 202) << r.body;
  EXPECT_EQ(app->jobs.wait(body(r).at("job").at("id").get<std::string>()).state, "done");
  EXPECT_EQ(body(get("/api/v1/gaze/bobs")).at("owner"), "bob");
  EXPECT_EQ(as_writer("DELETE", "/api/v1/gaze/bobs").status, 204);
  EXPECT_EQ(send("DELETE", "/api/v1/gaze/admins").status, 204);
}

TEST_F(GazeStoreTest, TheBinaryFileRoundTripsAndRefusesDamage) {
  gaze::GazeIngestOptions o;
  gaze::GazeDataset ds =
      gaze::read_gaze_file(shared_data("gaze/eyelinker_sr_research/mono500.asc").string(), o);
  ds.recordings[0].annotations.push_back({"lab", std::vector<int>(ds.recordings[0].size(), 3)});
  const std::string bytes = encode_gaze_file(ds);
  EXPECT_EQ(bytes.size(), gaze_file_size(ds));
  const gaze::GazeDataset back = decode_gaze_file(bytes);
  ASSERT_EQ(back.recordings.size(), ds.recordings.size());
  for (std::size_t i = 0; i < ds.recordings.size(); ++i) {
    const auto &a = ds.recordings[i], &b = back.recordings[i];
    EXPECT_EQ(a.participant, b.participant);
    EXPECT_EQ(a.trial, b.trial);
    EXPECT_EQ(a.t_ms, b.t_ms);
    EXPECT_EQ(a.valid, b.valid);
    EXPECT_EQ(a.tracker_events.size(), b.tracker_events.size());
    EXPECT_EQ(a.annotations, b.annotations);
    for (std::size_t k = 0; k < a.size(); ++k)
      if (a.valid[k]) ASSERT_EQ(a.x[k], b.x[k]);
  }
  const auto refused = [](std::string_view b) {
    try {
      decode_gaze_file(b);
    } catch (const Error& e) {
      EXPECT_EQ(e.kind(), Error::Kind::unprocessable);
      EXPECT_EQ(e.param(), "gaze_file");
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(refused(std::string_view(bytes).substr(0, bytes.size() - 1)).rfind("gaze file: byte ", 0), 0u);
  EXPECT_NE(refused(bytes + "x").find("bytes after the last recording"), std::string::npos);
  EXPECT_NE(refused("GIF8").find("no TSGZ magic"), std::string::npos);
  std::string huge = bytes;
  huge[8] = '\xff', huge[9] = '\xff', huge[10] = '\xff', huge[11] = '\x7f';  // recording count
  EXPECT_NE(refused(huge).find("recordings, more than"), std::string::npos);
  // A recording of no samples (its columns empty) round-trips too: the fuzz harness gaze_store_file found
  // the decoder copying 0 bytes from a null pointer there (tests/fuzz/regressions/gaze_store_file).
  gaze::GazeDataset empty = ds;
  empty.recordings.resize(1);
  gaze::Recording& r = empty.recordings[0];
  r.t_ms.clear(), r.x.clear(), r.y.clear(), r.valid.clear(), r.tracker_events.clear(), r.annotations.clear();
  const std::string eb = encode_gaze_file(empty);
  EXPECT_EQ(eb.size(), gaze_file_size(empty));
  const gaze::GazeDataset eback = decode_gaze_file(eb);
  ASSERT_EQ(eback.recordings.size(), 1u);
  EXPECT_EQ(eback.recordings[0].size(), 0u);
  EXPECT_EQ(encode_gaze_file(eback), eb);
}

TEST_F(GazeStoreTest, ExactErrors) {
  // Names, before the body is read (the upload's precheck) and by the handler.
  Request r;
  r.method = "POST", r.path = "/api/v1/gaze", r.query = {{"name", "Bad Name"}}, r.principal = principal;
  r.headers["authorization"] = "Bearer " + router.token;
  PathParams pp;
  try {
    router.router.admit(r, pp);
    ADD_FAILURE() << "a bad name passed the precheck";
  } catch (const Error& e) {
    EXPECT_EQ(e.param(), "name");
  }
  expect_error(send("POST", "/api/v1/gaze", "x", {{"name", "Bad Name"}}), 400, "invalid_argument", "name");
  expect_error(send("POST", "/api/v1/gaze", "x"), 400, "invalid_argument", "name");
  uploaded("tiny", tiny_csv());
  const Response taken = send("POST", "/api/v1/gaze", "x", {{"name", "tiny"}});
  expect_error(taken, 409, "conflict", "name");
  EXPECT_EQ(body(taken).at("detail"), "gaze dataset 'tiny' already exists");
  expect_error(send("POST", "/api/v1/gaze", "x", {{"name", "a"}, {"format", "edf"}}), 400, "invalid_argument",
               "format");
  expect_error(send("POST", "/api/v1/gaze", "x", {{"name", "a"}, {"distance_cm", "-3"}}), 400,
               "invalid_argument", "distance_cm");
  expect_error(send("POST", "/api/v1/gaze", "x", {{"name", "a"}, {"bbox", "1"}}), 400, "invalid_argument",
               "bbox");

  // A damaged file fails its job with the reader's line and reason.
  const std::string coord = slurp(shared_data("gaze/sp_tool_test_data/dsf_coord_data_example.coord"));
  std::string cut;
  std::istringstream in(coord);
  std::string line;
  for (int i = 0; i < 50 && std::getline(in, line); ++i) cut += line + "\n";
  cut += "999000 768.2";
  const JobState failed = upload("cut", cut);
  EXPECT_EQ(failed.state, "failed");
  EXPECT_EQ(failed.error,
            nlohmann::json({{"error", "unprocessable"},
                            {"detail", "line 51: coord row has 2 fields, expected at least 4 (truncated?)"},
                            {"param", "file"}}));
  expect_error(get("/api/v1/gaze/cut"), 404, "not_found", "gaze");
  EXPECT_TRUE(fs::is_empty(tmp.path() / "store" / "uploads"));

  // Filters.
  Response e = get("/api/v1/gaze/tiny/events", {{"participant", "nobody"}});
  expect_error(e, 400, "invalid_argument", "participant");
  EXPECT_EQ(body(e).at("detail"),
            "participant 'nobody' is not in this gaze dataset (its participants: 'tiny')");
  e = get("/api/v1/gaze/tiny/events", {{"stimulus", "x.png"}});
  expect_error(e, 400, "invalid_argument", "stimulus");
  EXPECT_EQ(body(e).at("detail"), "stimulus 'x.png' is not in this gaze dataset (its stimuli: none)");
  e = get("/api/v1/gaze/tiny/scanpaths", {{"recording", "1"}});
  expect_error(e, 400, "invalid_argument", "recording");
  EXPECT_EQ(body(e).at("detail"), "recording must lie in 0..0, got 1");
  e = get("/api/v1/gaze/tiny/events", {{"method", "fast"}});
  expect_error(e, 400, "invalid_argument", "method");
  EXPECT_EQ(body(e).at("detail"), "method must be ivt, idt or adaptive, not \"fast\"");
  e = get("/api/v1/gaze/tiny/events", {{"velocity_threshold", "0"}});
  expect_error(e, 400, "invalid_argument", "velocity_threshold");
  EXPECT_EQ(body(e).at("detail"), "velocity_threshold must be in (0, 5000], not 0");
  e = get("/api/v1/gaze/tiny/events", {{"adaptive_min_fixation_ms", "-1"}});
  expect_error(e, 400, "invalid_argument", "adaptive_min_fixation_ms");
  EXPECT_EQ(body(e).at("detail"), "adaptive_min_fixation_ms must be in [0, 10000], not -1");
  e = get("/api/v1/gaze/tiny/events", {{"t0_ms", "50"}, {"t1_ms", "50"}});
  expect_error(e, 400, "invalid_argument", "t1_ms");
  e = get("/api/v1/gaze/tiny/events", {{"type", "fixation,wink"}});
  expect_error(e, 400, "invalid_argument", "type");
  EXPECT_EQ(body(e).at("detail"),
            "type must be fixation, saccade, pso, pursuit, blink or undefined, got 'wink'");
  expect_error(get("/api/v1/gaze/tiny/events", {{"bbox", "1"}}), 400, "invalid_argument", "bbox");
  // Px without a physical screen: the detectors' geometry error.
  uploaded("px", "time,x,y\n0,10,10\n2,11,10\n4,12,10\n");
  expect_error(get("/api/v1/gaze/px/events"), 400, "invalid_argument", "geometry");
}

TEST_F(GazeStoreTest, EventsOverTheLimitAre413) {
  // Two valid samples at one place, then an invalid one, over and over: every pair is a fixation of its
  // own (I-VT, speed 0 between them) and every invalid sample a blink, so 3 m samples hold 2 m events,
  // more than kMaxGazeEvents.
  const std::size_t m = limits::kMaxGazeEvents / 2 + 1, events = 2 * m;
  std::string csv = "time,x_deg,y_deg\n";
  csv.reserve(3 * m * 16);
  for (std::size_t i = 0; i < 3 * m; ++i)
    csv += std::to_string(2 * i) + (i % 3 == 2 ? ",nan,nan\n" : ",1.5,2.5\n");
  uploaded("many", csv);
  Response r = get("/api/v1/gaze/many/events");
  expect_error(r, 413, "payload_too_large", "events");
  EXPECT_EQ(body(r).at("detail"),
            "the selection holds " + std::to_string(events) + " events, more than the limit of " +
                std::to_string(limits::kMaxGazeEvents) +
                "; narrow it with participant, stimulus, recording, t0_ms/t1_ms or type");
  // A window that holds fewer is answered: [0, 20) ms is samples 0..9, whose events start at 0, 2 (blink),
  // 3, 5 (blink), 6, 8 (blink) and 9.
  r = get("/api/v1/gaze/many/events", {{"t1_ms", "20"}});
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(body(r).at("events").size(), 7u);
  EXPECT_EQ(body(r).at("counts").at("blink"), 3);
  EXPECT_EQ(body(r).at("counts").at("fixation"), 4);
}

TEST_F(GazeStoreTest, StimulusImages) {
  const std::string png = slurp(shared_data("gaze/andersson2017_lund/stimuli/Europe1024x768.png"));
  uploaded("lund", slurp(shared_data("gaze/andersson2017_lund/tsv/TH34_img_Europe.tsv")),
           {{"stimulus", "Europe"}});
  expect_error(get("/api/v1/gaze/lund/stimulus"), 404, "not_found", "stimulus");
  // The size as the PNG's IHDR chunk says (big-endian width and height at bytes 16 and 20).
  const auto be32 = [&](std::size_t at) {
    return (std::uint32_t(std::uint8_t(png[at])) << 24) | (std::uint32_t(std::uint8_t(png[at + 1])) << 16) |
           (std::uint32_t(std::uint8_t(png[at + 2])) << 8) | std::uint32_t(std::uint8_t(png[at + 3]));
  };
  Response r = send("PUT", "/api/v1/gaze/lund/stimulus", png);
  ASSERT_EQ(r.status, 200) << r.body;
  EXPECT_EQ(body(r).at("width_px"), be32(16));
  EXPECT_EQ(body(r).at("height_px"), be32(20));
  EXPECT_EQ(body(r).at("content_type"), "image/png");
  r = get("/api/v1/gaze/lund/stimulus", {{"stimulus", "Europe"}});
  EXPECT_EQ(r.status, 200);
  EXPECT_EQ(r.content_type, "image/png");
  EXPECT_TRUE(r.body == png);
  EXPECT_EQ(body(get("/api/v1/gaze/lund")).at("stimulus_images").size(), 1u);
  // Refusals: not an image, a cut PNG, a stimulus the dataset does not have.
  r = send("PUT", "/api/v1/gaze/lund/stimulus", "GIF89a\x01\x00\x01\x00");
  expect_error(r, 415, "unsupported_format", "image");
  EXPECT_EQ(body(r).at("detail"),
            "not a PNG or JPEG image (the first bytes are neither the PNG signature nor a JPEG SOI marker)");
  expect_error(send("PUT", "/api/v1/gaze/lund/stimulus", png.substr(0, png.size() / 2)), 422, "unprocessable",
               "image");
  r = send("PUT", "/api/v1/gaze/lund/stimulus", png, {{"stimulus", "Asia"}});
  expect_error(r, 400, "invalid_argument", "stimulus");
  EXPECT_EQ(body(r).at("detail"), "stimulus 'Asia' is not in gaze dataset 'lund' (its stimuli: 'Europe')");
  expect_error(send("PUT", "/api/v1/gaze/lund/stimulus", ""), 400, "invalid_argument", "body");
  // The body limits the network layer applies before a byte is read.
  EXPECT_EQ(router.body_rule("PUT", "/api/v1/gaze/lund/stimulus").limit, limits::kMaxGazeStimulusBytes);
  EXPECT_EQ(router.body_rule("POST", "/api/v1/gaze").limit, limits::kMaxGazeUploadBytes);
  EXPECT_TRUE(router.body_rule("POST", "/api/v1/gaze").to_file);
  // Still the first image; and after a restart.
  open_app();
  EXPECT_TRUE(get("/api/v1/gaze/lund/stimulus").body == png);
}

}  // namespace
}  // namespace trailscope::server::test_routes

namespace trailscope::server::test_routes {
namespace {

// The selection every gaze view shares (gaze/query.hpp), on a hand-made dataset: two participants, two
// stimuli, recordings at 2 ms steps whose clocks start at different times.
TEST(GazeSelection, RecordingsAndWindowsAsDefined) {
  gaze::GazeDataset ds;
  const auto rec = [&](const std::string& p, const std::string& s, double t0) {
    gaze::Recording r;
    r.participant = p, r.stimulus = s;
    for (int i = 0; i < 10; ++i)
      r.t_ms.push_back(t0 + 2 * i), r.x.push_back(i), r.y.push_back(0), r.valid.push_back(1);
    ds.recordings.push_back(r);
  };
  rec("ann", "a.png", 1000), rec("ann", "b.png", 5000), rec("bob", "a.png", 0);
  gaze::GazeFilter f;
  EXPECT_EQ(gaze::select_recordings(ds, f), (std::vector<std::size_t>{0, 1, 2}));
  f.participant = "ann";
  EXPECT_EQ(gaze::select_recordings(ds, f), (std::vector<std::size_t>{0, 1}));
  f.stimulus = "a.png";
  EXPECT_EQ(gaze::select_recordings(ds, f), (std::vector<std::size_t>{0}));
  f.participant = "bob", f.stimulus = "b.png";  // both exist, never together
  EXPECT_TRUE(gaze::select_recordings(ds, f).empty());
  f = {};
  f.recording = 2;
  EXPECT_EQ(gaze::select_recordings(ds, f), (std::vector<std::size_t>{2}));
  // Windows count from each recording's first sample: [4, 10) ms is samples 2..4 whatever the clock.
  f = {};
  f.t0_ms = 4, f.t1_ms = 10;
  for (const auto& r : ds.recordings)
    EXPECT_EQ(gaze::window_samples(r, f), (std::pair<std::size_t, std::size_t>{2, 5}));
  f.t0_ms = 100, f.t1_ms = 200;
  EXPECT_EQ(gaze::window_samples(ds.recordings[0], f), (std::pair<std::size_t, std::size_t>{10, 10}));
  f.t0_ms = 0, f.t1_ms = INFINITY;
  EXPECT_EQ(gaze::window_samples(ds.recordings[0], f), (std::pair<std::size_t, std::size_t>{0, 10}));
  f.t0_ms = -1;
  EXPECT_THROW(gaze::select_recordings(ds, f), Error);
}

}  // namespace
}  // namespace trailscope::server::test_routes
