// Ownership, ids that are never reused, and the admission of jobs and heavy requests, in process: every kind
// of resource records its creator's owner name and shows it; only the owner or an admin deletes it (403 with
// the exact body otherwise, after the 404); ids continue after a restart for every store, the jobs and the
// replays; one owner's job quota (429 with Retry-After); the disk budget (507 up front with the numbers, and
// a write stopped midway that leaves nothing); and the up-front refusal of projections and images beyond
// their work. Handlers are called as the access check leaves them, with Request::principal set (the access
// check itself is tested with the tokens).
#include <atomic>
#include <condition_variable>
#include <functional>
#include <future>
#include <mutex>

#include <gtest/gtest.h>

#include "errors/error_table.hpp"
#include "jobs/disk_budget.hpp"
#include "jobs/synth_job.hpp"
#include "routes/ownership.hpp"
#include "store/column_io.hpp"
#include "store/id_counter.hpp"
#include "tracker_fixture.hpp"
#include "trailscope/tracker/params.hpp"
#include "trailscope/trails/trail_set_builder.hpp"

namespace trailscope::server {
namespace {
namespace fs = std::filesystem;

const Principal kAlice{"t-alice", "alice", Role::writer};
const Principal kBob{"t-bob", "bob", Role::writer};
const Principal kAdmin{"t-root", "root", Role::admin};

const char* kCsv =
    "time,icao24,lat,lon,velocity,heading,vertrate,callsign,onground,alert,spi,squawk,baroaltitude,"
    "geoaltitude,"
    "lastposupdate,lastcontact\n"
    "1514764800,4ca1d0,52.3,4.76,100,90,0,KLM1,false,false,false,1000,1000,1010,1514764800,1514764800\n"
    "1514764810,4ca1d0,52.3,4.78,100,90,0,KLM1,false,false,false,1000,1000,1010,1514764810,1514764810\n";

const char* kSectors = R"({"type": "FeatureCollection", "features": [
  {"type": "Feature", "properties": {"name": "S1", "lower_fl": 300, "upper_fl": 400},
   "geometry": {"type": "Polygon", "coordinates": [[[0.95, 44.9], [1.05, 44.9], [1.05, 45.1], [0.95, 45.1], [0.95, 44.9]]]}}]})";

/// A tracker log of `frames` frames in SEARCH, with the default parameters.
std::string small_log(std::size_t frames) {
  tracker::TrackerLog log;
  const auto values = tracker::to_vector(tracker::TrackerParams{});
  for (std::size_t i = 0; i < values.size(); ++i)
    log.header.params.push_back({tracker::parameter_infos()[i].name, values[i]});
  log.header.fps = 25;
  log.header.frame_count = frames;
  log.frames.resize(frames);
  for (std::size_t i = 0; i < frames; ++i) {
    log.frames[i].index = i;
    log.frames[i].timestamp_s = static_cast<double>(i) / 25.0;
    log.frames[i].state = tracker::State::search;
  }
  return tracker::encode_log(log, tracker::LogEncoding::binary);
}

/// A gate a test's jobs wait at until the test opens it.
struct Gate {
  std::mutex mu;
  std::condition_variable cv;
  bool open = false;
  void wait() {
    std::unique_lock lock(mu);
    cv.wait(lock, [&] { return open; });
  }
  void release() {
    {
      std::lock_guard lock(mu);
      open = true;
    }
    cv.notify_all();
  }
};

class OwnershipTest : public test_routes::TrackerFixture {
 protected:
  /// The handler of `method` `path` with `who` as the caller, as the access check leaves the request;
  /// errors become the error table's response.
  Response call(const Principal& who, const std::string& method, const std::string& path,
                std::string body = {}, std::map<std::string, std::string> query = {},
                fs::path body_file = {}) {
    Request r;
    r.method = method, r.path = path, r.body = std::move(body), r.query = std::move(query);
    r.body_file = std::move(body_file);
    r.principal = who;
    PathParams params;
    const Router::Route* route = router.find(method, path, params);
    if (!route) {
      ADD_FAILURE() << "no route for " << method << " " << path;
      return {};
    }
    try {
      return route->handler(r, params);
    } catch (const std::exception& e) {
      return error_response(e);
    }
  }
  /// The id a create answered (201 or 202), from `key` of its body.
  static std::string created(const Response& r, const std::string& key) {
    EXPECT_TRUE(r.status == 201 || r.status == 202) << r.body;
    const auto j = body(r);
    return j.contains(key) ? j.at(key).get<std::string>() : "";
  }
  std::string wait_job(const Response& r) {
    EXPECT_EQ(r.status, 202) << r.body;
    if (r.status != 202) return "";
    const JobState done = app->jobs.wait(body(r).at("job").at("id").get<std::string>());
    EXPECT_EQ(done.state, "done") << done.to_json().dump();
    return done.id;
  }
  std::string upload_pack(const Principal& who, std::size_t frames) {
    static int n = 0;
    const fs::path pack = make_pack("own" + std::to_string(n), frames);
    const fs::path upload = store->upload_dir() / ("own-upload-" + std::to_string(n++));
    fs::copy_file(pack, upload);
    return created(call(who, "POST", "/api/v1/videos", "", {}, upload), "id");
  }
  void expect_body(const Response& r, int status, const std::string& error, const std::string& param,
                   const std::string& detail) {
    EXPECT_EQ(r.status, status) << r.body;
    EXPECT_EQ(body(r), (nlohmann::json{{"error", error}, {"detail", detail}, {"param", param}})) << r.body;
  }
};

/// One kind of resource: how alice creates one, where it lives, and how its refusal reads.
struct Kind {
  std::string noun, param;
  std::function<std::string(const Principal&)> create;
  std::function<std::string(const std::string&)> path;
  std::string verb = "delete";
  int deleted = 204;
};

TEST_F(OwnershipTest, EveryKindRecordsItsOwnerAndOnlyTheOwnerOrAnAdminDeletesIt) {
  int dataset_n = 0;
  const std::string video = upload_pack(kAdmin, 12);
  const std::vector<Kind> kinds = {
      {"dataset", "dataset",
       [&](const Principal& who) {
         const std::string name = "d" + std::to_string(dataset_n++);
         wait_job(call(who, "POST", "/api/v1/datasets", kCsv, {{"name", name}}));
         return name;
       },
       [](const std::string& id) { return "/api/v1/datasets/" + id; }},
      {"graph", "graph",
       [&](const Principal& who) {
         return created(call(who, "POST", "/api/v1/graphs", test_routes::two_clusters()), "id");
       },
       [](const std::string& id) { return "/api/v1/graphs/" + id; }},
      {"bundle", "bundle",
       [&](const Principal& who) {
         const std::string g =
             created(call(kAdmin, "POST", "/api/v1/graphs", test_routes::two_clusters()), "id");
         const Response r = call(
             who, "POST", "/api/v1/bundles",
             R"({"source": {"graph": ")" + g +
                 R"("}, "params": {"size": 128, "iterations": 4, "h": 16, "spl": 4}, "backend": "cpu"})");
         wait_job(r);
         return created(r, "bundle");
       },
       [](const std::string& id) { return "/api/v1/bundles/" + id; }},
      {"video", "video", [&](const Principal& who) { return upload_pack(who, 3); },
       [](const std::string& id) { return "/api/v1/videos/" + id; }},
      {"run", "run",
       [&](const Principal& who) { return created(call(who, "POST", "/api/v1/runs", small_log(5)), "id"); },
       [](const std::string& id) { return "/api/v1/runs/" + id; }},
      {"MOT file", "mot",
       [&](const Principal& who) {
         return created(call(who, "POST", "/api/v1/mot", "1,1,10,10,5,5\n", {{"kind", "result"}}), "id");
       },
       [](const std::string& id) { return "/api/v1/mot/" + id; }},
      {"sector set", "sectors",
       [&](const Principal& who) { return created(call(who, "POST", "/api/v1/sectors", kSectors), "id"); },
       [](const std::string& id) { return "/api/v1/sectors/" + id; }},
      {"replay", "replay",
       [&](const Principal& who) {
         return created(call(who, "POST", "/api/v1/replays", R"({"video": ")" + video + R"("})"), "id");
       },
       [](const std::string& id) { return "/api/v1/replays/" + id; }},
      {"job", "job",
       [&](const Principal& who) {
         const Response r =
             call(who, "POST", "/api/v1/videos/synth", R"({"scenario": "standard", "frames": 3000})");
         return r.status == 202 ? body(r)["job"]["id"].get<std::string>() : "";
       },
       [](const std::string& id) { return "/api/v1/jobs/" + id; }, "cancel", 200},
  };
  for (const Kind& k : kinds) {
    SCOPED_TRACE(k.noun);
    const std::string a = k.create(kAlice), b = k.create(kAlice);
    ASSERT_FALSE(a.empty());
    ASSERT_FALSE(b.empty());
    // The owner is recorded and shown, in the item and in its collection (sector sets: in the list; their
    // GET is the GeoJSON itself).
    if (k.param == "sectors") {
      const auto sets = body(call(kBob, "GET", "/api/v1/sectors"));  // named: outlives the loop
      for (const auto& m : sets["sectors"]) EXPECT_EQ(m["owner"], "alice");
    } else {
      EXPECT_EQ(body(call(kBob, "GET", k.path(a)))["owner"], "alice");
    }
    // An unknown one is a 404 for anyone; someone else's is a 403 with the exact body; the owner and an
    // admin may.
    EXPECT_EQ(call(kBob, "DELETE", k.path(k.param == "dataset" ? "nope" : "x999999")).status, 404);
    expect_body(call(kBob, "DELETE", k.path(a)), 403, "forbidden", k.param,
                k.noun + " '" + a + "' belongs to 'alice'; only its owner or an admin may " + k.verb + " it");
    EXPECT_EQ(call(kAlice, "DELETE", k.path(a)).status, k.deleted);
    EXPECT_EQ(call(kAdmin, "DELETE", k.path(b)).status, k.deleted);
    if (k.param == "job") {
      EXPECT_EQ(app->jobs.wait(a).state, "cancelled");
      EXPECT_EQ(app->jobs.wait(b).state, "cancelled");
      EXPECT_EQ(app->jobs.get(a).owner, "alice");
    } else {
      EXPECT_EQ(call(kAdmin, "GET", k.path(a)).status, 404);
      EXPECT_EQ(call(kAdmin, "GET", k.path(b)).status, 404);
    }
  }
}

TEST_F(OwnershipTest, WhatHasNoOwnerBelongsToTheAdmins) {
  // A dataset of the CLI (or of a store written before owners were recorded) has owner "".
  TrailSetBuilder tb;
  Sample s;
  s.t = 1514764800, s.lat = 52, s.lon = 4, s.alt = 1000, s.speed = 100;
  tb.add("4ca1d0", "KLM1", s);
  s.t += 10, s.lon += 0.01f;
  tb.add("4ca1d0", "KLM1", s);
  auto ds = std::make_shared<Dataset>();
  ds->id = ds->name = "cli", ds->format = "test", ds->created = "2026-01-01T00:00:00Z";
  ds->trails = std::make_shared<const TrailSet>(tb.build());
  store->put(ds);
  open_empty();  // read back from disk: the manifest has no owner
  EXPECT_EQ(body(call(kBob, "GET", "/api/v1/datasets/cli"))["owner"], "");
  expect_body(
      call(kBob, "DELETE", "/api/v1/datasets/cli"), 403, "forbidden", "dataset",
      "dataset 'cli' has no owner (it was made before owners were recorded, or by the command line); only "
      "an admin may delete it");
  // An anonymous caller never owns anything, not even what has no owner.
  EXPECT_EQ(call(Principal{}, "DELETE", "/api/v1/datasets/cli").status, 403);
  EXPECT_EQ(call(kAdmin, "DELETE", "/api/v1/datasets/cli").status, 204);
  EXPECT_FALSE(may_modify(Principal{}, ""));
  EXPECT_FALSE(may_modify(Principal{"t", "", Role::writer}, ""));
  EXPECT_TRUE(may_modify(kAdmin, ""));
  EXPECT_TRUE(may_modify(kAlice, "alice"));
  EXPECT_FALSE(may_modify(kAlice, "bob"));
}

TEST_F(OwnershipTest, SweepsAndTheirRunsRecordTheirOwner) {
  const std::string video = upload_pack(kAdmin, 6);
  const Response r = call(
      kAlice, "POST", "/api/v1/sweeps",
      R"({"videos": [")" + video +
          R"("], "sweep": {"mode": "grid", "axes": [{"param": "ncc_min", "min": 0.5, "max": 0.6, "steps": 2}]}})");
  ASSERT_EQ(r.status, 202) << r.body;
  EXPECT_EQ(body(r)["sweep"]["owner"], "alice");
  EXPECT_EQ(body(r)["job"]["owner"], "alice");
  app->jobs.wait(body(r)["job"]["id"]);
  const auto sweep = body(call(kAlice, "GET", "/api/v1/sweeps/" + body(r)["sweep"]["id"].get<std::string>()));
  ASSERT_EQ(sweep["runs"].size(), 2u) << sweep.dump();
  for (const auto& run : sweep["runs"])
    EXPECT_EQ(body(call(kBob, "GET", "/api/v1/runs/" + run.get<std::string>()))["owner"], "alice");
}

// --- ids ------------------------------------------------------------------------------------------------

TEST_F(OwnershipTest, IdsOfEveryStoreContinueAfterTheNewestIsDeletedAndTheServerRestarts) {
  struct Store {
    std::string name;
    std::function<std::string()> create;
    std::function<std::string(const std::string&)> path;
  };
  const std::vector<Store> stores = {
      {"graphs",
       [&] { return created(call(kAlice, "POST", "/api/v1/graphs", test_routes::two_clusters()), "id"); },
       [](const std::string& id) { return "/api/v1/graphs/" + id; }},
      {"videos", [&] { return upload_pack(kAlice, 2); },
       [](const std::string& id) { return "/api/v1/videos/" + id; }},
      {"runs", [&] { return created(call(kAlice, "POST", "/api/v1/runs", small_log(3)), "id"); },
       [](const std::string& id) { return "/api/v1/runs/" + id; }},
      {"mot",
       [&] {
         return created(call(kAlice, "POST", "/api/v1/mot", "1,1,10,10,5,5\n", {{"kind", "result"}}), "id");
       },
       [](const std::string& id) { return "/api/v1/mot/" + id; }},
      {"sectors", [&] { return created(call(kAlice, "POST", "/api/v1/sectors", kSectors), "id"); },
       [](const std::string& id) { return "/api/v1/sectors/" + id; }},
      {"bundles",
       [&] {
         const std::string g =
             created(call(kAlice, "POST", "/api/v1/graphs", test_routes::two_clusters()), "id");
         const Response r = call(
             kAlice, "POST", "/api/v1/bundles",
             R"({"source": {"graph": ")" + g +
                 R"("}, "params": {"size": 128, "iterations": 4, "h": 16, "spl": 4}, "backend": "cpu"})");
         wait_job(r);
         return created(r, "bundle");
       },
       [](const std::string& id) { return "/api/v1/bundles/" + id; }},
  };
  for (const Store& s : stores) {
    SCOPED_TRACE(s.name);
    const std::string first = s.create(), newest = s.create();
    ASSERT_EQ(call(kAlice, "DELETE", s.path(newest)).status, 204);
    open_empty();  // a restart
    const std::string next = s.create();
    const auto number = [](const std::string& id) { return std::stoull(id.substr(1)); };
    EXPECT_GT(number(next), number(newest)) << first << " " << newest << " " << next;
    EXPECT_EQ(call(kAlice, "GET", s.path(newest)).status, 404);  // the deleted id names nothing
  }
}

TEST_F(OwnershipTest, JobAndReplayIdsContinueAfterARestart) {
  const std::string video = upload_pack(kAdmin, 8);
  const Response j1 =
      call(kAlice, "POST", "/api/v1/videos/synth", R"({"scenario": "standard", "frames": 2})");
  const std::string job = body(j1)["job"]["id"];
  app->jobs.wait(job);
  const std::string replay =
      created(call(kAlice, "POST", "/api/v1/replays", R"({"video": ")" + video + R"("})"), "id");
  open_empty();
  // The old job is forgotten (404), and no new job or replay is ever given its id.
  EXPECT_EQ(call(kAlice, "GET", "/api/v1/jobs/" + job).status, 404);
  const Response j2 =
      call(kAlice, "POST", "/api/v1/videos/synth", R"({"scenario": "standard", "frames": 2})");
  const std::string next = body(j2)["job"]["id"];
  EXPECT_GT(std::stoull(next.substr(1)), std::stoull(job.substr(1)));
  app->jobs.wait(next);
  const std::string next_replay =
      created(call(kAlice, "POST", "/api/v1/replays", R"({"video": ")" + video + R"("})"), "id");
  EXPECT_GT(std::stoull(next_replay.substr(2)), std::stoull(replay.substr(2)));

  // A JobManager on its own: ids continue across instances on the same file.
  const fs::path file = tmp.path() / "jm" / ".last_job_id";
  std::string last;
  {
    JobManager jobs(1, file);
    for (int i = 0; i < 3; ++i)
      last =
          jobs.submit("test", "", [](const ProgressFn&, const CancelToken&) { return nlohmann::json(); }).id;
  }
  EXPECT_EQ(last, "j3");
  JobManager again(1, file);
  EXPECT_EQ(
      again.submit("test", "", [](const ProgressFn&, const CancelToken&) { return nlohmann::json(); }).id,
      "j4");
}

TEST_F(OwnershipTest, AnIdIsPersistedBeforeItIsHandedOut) {
  const fs::path file = tmp.path() / "counter" / ".last_id";
  {
    IdCounter c(file);
    EXPECT_EQ(c.next(), 1u);
    c.observe(41);  // an id found on disk, from before the counter
    EXPECT_EQ(c.next(), 42u);
    // On disk already, as a crash right after the return would find it.
    std::ifstream in(file);
    std::string text;
    std::getline(in, text);
    EXPECT_EQ(text, "42");
  }
  // A temporary file that a crash left beside the counter is removed; the mark is read back.
  std::ofstream(file.parent_path() / ".last_id.tmp.deadbeef") << "7";
  IdCounter reopened(file);
  EXPECT_FALSE(fs::exists(file.parent_path() / ".last_id.tmp.deadbeef"));
  EXPECT_EQ(reopened.next(), 43u);
  // A counter that does not hold a number is never guessed past.
  std::ofstream(file, std::ios::trunc) << "forty";
  try {
    IdCounter broken(file);
    ADD_FAILURE() << "a damaged counter was accepted";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::internal);
    EXPECT_EQ(std::string(e.what()),
              "store: cannot read the id counter " + file.string() + " (it must hold one number)");
  }
}

TEST_F(OwnershipTest, SweepIdsContinueWhenTheNewestRecordIsGone) {
  std::string first;
  {
    SweepStore sweeps(tmp.path() / "sw");
    sweeps.create({}, nlohmann::json::array(), {}, 0, "alice");
    first = sweeps.create({}, nlohmann::json::array(), {}, 0, "alice");
    EXPECT_EQ(sweeps.get(first)["owner"], "alice");
  }
  fs::remove(tmp.path() / "sw" / "sweeps" / (first + ".json"));
  SweepStore reopened(tmp.path() / "sw");
  EXPECT_EQ(reopened.create({}, nlohmann::json::array(), {}, 0), "s3");
}

// --- job admission --------------------------------------------------------------------------------------

TEST_F(OwnershipTest, OneOwnersJobsAreCappedWithA429AndRetryAfter) {
  Gate gate;
  const auto blocked = [&gate](const ProgressFn&, const CancelToken&) {
    gate.wait();
    return nlohmann::json();
  };
  std::vector<std::string> ids;
  for (std::size_t i = 0; i < limits::kMaxQueuedJobsPerOwner; ++i)
    ids.push_back(app->jobs.submit("test", "", blocked, "alice").id);
  const std::string detail =
      "owner 'alice' has 8 jobs queued or running, the most one owner may have "
      "(kMaxQueuedJobsPerOwner = 8); retry when one has ended, or cancel one";
  // Through the API: refused before a video id or a disk grant is taken.
  const Response r = call(kAlice, "POST", "/api/v1/videos/synth", R"({"scenario": "standard", "frames": 2})");
  expect_body(r, 429, "too_many_requests", "job", detail);
  std::string retry_after;
  for (const auto& [k, v] : r.headers)
    if (k == "Retry-After") retry_after = v;
  EXPECT_EQ(retry_after, std::to_string(limits::kJobRetryAfterSeconds));
  EXPECT_EQ(app->disk->granted(), 0u);
  EXPECT_EQ(app->videos->size(), 0u);
  expect_body(call(kAlice, "POST", "/api/v1/datasets", kCsv, {{"name", "late"}}), 429, "too_many_requests",
              "job", detail);
  // Another owner is not held back, and alice may submit again once one of hers has ended.
  const Response bob = call(kBob, "POST", "/api/v1/videos/synth", R"({"scenario": "standard", "frames": 2})");
  ASSERT_EQ(bob.status, 202) << bob.body;
  app->jobs.cancel(ids.front());
  gate.release();
  for (const auto& id : ids) app->jobs.wait(id);
  app->jobs.wait(body(bob)["job"]["id"]);
  const Response again =
      call(kAlice, "POST", "/api/v1/videos/synth", R"({"scenario": "standard", "frames": 2})");
  EXPECT_EQ(again.status, 202) << again.body;
  app->jobs.wait(body(again)["job"]["id"]);
}

TEST_F(OwnershipTest, AShortJobDoesNotWaitBehindALongOne) {
  ASSERT_GE(limits::kJobWorkers, 2u);
  Gate gate;
  const std::string slow = app->jobs
                               .submit("test", "",
                                       [&gate](const ProgressFn&, const CancelToken&) {
                                         gate.wait();
                                         return nlohmann::json();
                                       })
                               .id;
  const std::string quick = app->jobs
                                .submit("test", "",
                                        [](const ProgressFn&, const CancelToken&) {
                                          return nlohmann::json{{"quick", true}};
                                        })
                                .id;
  // With one worker the quick job would wait for the gate, which opens only after it ended.
  auto done = std::async(std::launch::async, [&] { return app->jobs.wait(quick); });
  const bool ended = done.wait_for(std::chrono::seconds(120)) == std::future_status::ready;
  EXPECT_TRUE(ended) << "the quick job waited behind the slow one";
  if (ended) EXPECT_EQ(done.get().state, "done");
  EXPECT_EQ(app->jobs.get(slow).state, "running");
  gate.release();
  app->jobs.wait(slow);
}

// --- the disk budget -------------------------------------------------------------------------------------

TEST_F(OwnershipTest, ASynthThatCannotFitIsRefusedUpFrontWithTheNumbers) {
  const Response r = call(kAlice, "POST", "/api/v1/videos/synth",
                          R"({"scenario":"noisy","frames":100000,"width":1024,"height":1024})");
  const std::uint64_t bytes = 100000ull * 1024 * 1024 * 4;
  expect_body(r, 507, "insufficient_storage", "frames",
              "the video needs up to " + std::to_string(bytes) +
                  " bytes (100000 frames × 1024 × 1024 px × 4 bytes), more than one job may write: " +
                  std::to_string(limits::kMaxJobWriteBytes) + " bytes (kMaxJobWriteBytes)");
  // Within the cap but beyond what the disk has free less the reserve and the other grants.
  app->disk =
      DiskBudget::open(tmp.path(), 1000, limits::kMaxJobWriteBytes, [] { return std::uint64_t{150000}; });
  const auto held = app->disk->admit(20000, "frames", "another video", "a test");
  const std::uint64_t small = 4ull * 176 * 144 * 4;
  expect_body(
      call(kAlice, "POST", "/api/v1/videos/synth", R"({"scenario": "standard", "frames": 4})"), 507,
      "insufficient_storage", "frames",
      "the video needs up to " + std::to_string(small) +
          " bytes (4 frames × 176 × 144 px × 4 bytes), more than the disk can take: 150000 bytes free, "
          "less 1000 bytes kept free (kDiskReserveBytes) and 20000 bytes granted to jobs still writing");
  EXPECT_EQ(app->videos->size(), 0u);
  EXPECT_EQ(app->disk->granted(), 20000u);  // the refused request holds nothing
}

TEST_F(OwnershipTest, ASynthStopsCleanlyWhenTheDiskRunsShortWhileItWrites) {
  // Plenty of room when the job is admitted; then something else fills the disk below the reserve.
  auto calls = std::make_shared<std::atomic<int>>(0);
  app->disk = DiskBudget::open(tmp.path(), 1 << 20, limits::kMaxJobWriteBytes, [calls] {
    return ++*calls == 1 ? std::uint64_t{1} << 40 : std::uint64_t{4096};
  });
  const Response r =
      call(kAlice, "POST", "/api/v1/videos/synth", R"({"scenario": "standard", "frames": 200})");
  ASSERT_EQ(r.status, 202) << r.body;
  EXPECT_EQ(app->disk->granted(), 200ull * 176 * 144 * 4);
  const JobState done = app->jobs.wait(body(r)["job"]["id"]);
  ASSERT_EQ(done.state, "failed") << done.to_json().dump();
  EXPECT_EQ(done.error["error"], "insufficient_storage");
  EXPECT_EQ(done.error["param"], "frames");
  const std::string detail = done.error["detail"];
  EXPECT_EQ(detail.rfind("the job stopped after writing ", 0), 0u) << detail;
  const std::string tail =
      " bytes: the disk has 4096 bytes free, less than the 1048576 bytes the server keeps free "
      "(kDiskReserveBytes); nothing of it was kept";
  EXPECT_EQ(detail.substr(detail.size() - tail.size()), tail) << detail;
  // Nothing partial: no video, an empty staging folder, the id given back, the grant returned.
  EXPECT_EQ(body(call(kAlice, "GET", "/api/v1/videos"))["videos"].size(), 0u);
  EXPECT_TRUE(fs::is_empty(tmp.path() / "store" / "tmp"));
  for (const auto& e : fs::directory_iterator(tmp.path() / "store" / "videos"))
    EXPECT_EQ(e.path().filename(), kIdCounterFile);  // only the id counter
  EXPECT_EQ(app->disk->granted(), 0u);
  app->disk = DiskBudget::open(tmp.path());
  const Response next =
      call(kAlice, "POST", "/api/v1/videos/synth", R"({"scenario": "standard", "frames": 2})");
  EXPECT_EQ(body(next)["video"], "v2");  // v1 is never handed out again
  app->jobs.wait(body(next)["job"]["id"]);
}

TEST_F(OwnershipTest, AGrantStopsAJobThatWritesMoreThanItWasGranted) {
  auto budget = DiskBudget::open(tmp.path(), 0, 1000, [] { return std::uint64_t{1} << 40; });
  const auto grant = budget->admit(600, "bundle", "the bundle", "a test");
  grant->check(600);
  try {
    grant->check(601);
    ADD_FAILURE() << "601 bytes passed a grant of 600";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::insufficient_storage);
    EXPECT_EQ(e.param(), "bundle");
    EXPECT_EQ(std::string(e.what()),
              "the job stopped: it wrote 601 bytes, more than the 600 bytes it was granted; nothing of it "
              "was kept");
  }
}

TEST_F(OwnershipTest, AnIngestBeyondTheBudgetFailsBeforeItWrites) {
  app->disk = DiskBudget::open(tmp.path(), 0, 1000, [] { return std::uint64_t{1} << 40; });
  const Response r = call(kAlice, "POST", "/api/v1/datasets", kCsv, {{"name", "big"}});
  ASSERT_EQ(r.status, 202) << r.body;
  const JobState done = app->jobs.wait(body(r)["job"]["id"]);
  ASSERT_EQ(done.state, "failed");
  const std::uint64_t bytes = 2 * EmbeddedStore::kBytesPerPoint + 1 * EmbeddedStore::kBytesPerFlight + 65536;
  EXPECT_EQ(done.error,
            (nlohmann::json{{"error", "insufficient_storage"},
                            {"param", "upload"},
                            {"detail", "the dataset needs up to " + std::to_string(bytes) +
                                           " bytes (2 points × 33 bytes and 1 flights × 72 bytes), more "
                                           "than one job may write: 1000 bytes (kMaxJobWriteBytes)"}}));
  EXPECT_EQ(call(kAlice, "GET", "/api/v1/datasets/big").status, 404);
  EXPECT_TRUE(fs::is_empty(tmp.path() / "store" / "tmp"));
}

// --- synchronous heavy requests ---------------------------------------------------------------------------

nlohmann::json table(std::size_t rows) {
  nlohmann::json t = {{"rows", nlohmann::json::array()}};
  for (std::size_t r = 0; r < rows; ++r)
    t["rows"].push_back({static_cast<double>(r % 97) * 0.5, static_cast<double>((r * 31) % 89)});
  return t;
}

TEST_F(OwnershipTest, ProjectionsBeyondTheirWorkAreRefusedBeforeTheyStart) {
  nlohmann::json force = {
      {"table", table(5000)}, {"method", "force"}, {"iterations", 10000}, {"backend", "cpu"}};
  expect_body(
      call(kAlice, "POST", "/api/v1/projections", force.dump()), 413, "payload_too_large", "iterations",
      "method force on 5000 rows × 10000 iterations is 250000000000 units of work (rows² × iterations), "
      "more than one request may do: 500000000 (kMaxForceSchemeRequestWork); use fewer rows or iterations, "
      "or `trailscope project` (no limit on work, with progress)");
  force.erase("iterations");  // the default 100: 5000² × 100 is still too much
  EXPECT_EQ(body(call(kAlice, "POST", "/api/v1/projections", force.dump()))["param"], "table");
  const nlohmann::json tsne = {{"table", table(20000)}, {"method", "tsne"}};
  expect_body(
      call(kAlice, "POST", "/api/v1/projections", tsne.dump()), 413, "payload_too_large", "table",
      "method tsne on 20000 rows × 750 iterations (early exaggeration included) is 15000000 units of work "
      "(rows × iterations), more than one request may do: 3750000 (kMaxTsneRequestWork); use fewer rows or "
      "iterations, or `trailscope project` (no limit on work, with progress)");
  // Within the budget it runs; a client that has gone away stops it (the compute pool's CancelToken).
  const nlohmann::json ok = {{"table", table(300)}, {"method", "tsne"}, {"backend", "cpu"}};
  EXPECT_EQ(call(kAlice, "POST", "/api/v1/projections", ok.dump()).status, 200);
  Request gone;
  gone.method = "POST", gone.path = "/api/v1/projections", gone.body = ok.dump(), gone.principal = kAlice;
  auto token = std::make_shared<CancelToken>();
  token->cancel();
  gone.cancel = token;
  PathParams params;
  const Router::Route* route = router.find("POST", "/api/v1/projections", params);
  ASSERT_NE(route, nullptr);
  try {
    route->handler(gone, params);
    ADD_FAILURE() << "a cancelled projection ran to the end";
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::cancelled);
  }
}

TEST_F(OwnershipTest, ABundleImageBeyondTheLimitIsRefusedBeforeDrawing) {
  const std::string g = created(call(kAlice, "POST", "/api/v1/graphs", test_routes::two_clusters()), "id");
  const Response b =
      call(kAlice, "POST", "/api/v1/bundles",
           R"({"source": {"graph": ")" + g +
               R"("}, "params": {"size": 128, "iterations": 4, "h": 16, "spl": 4}, "backend": "cpu"})");
  wait_job(b);
  const std::string path = "/api/v1/bundles/" + created(b, "bundle") + "/image.png";
  expect_body(
      call(kAlice, "GET", path, "", {{"width", "8192"}, {"height", "8192"}}), 413, "payload_too_large",
      "height",
      "an image of 8192 × 8192 = 67108864 pixels is larger than one request may render: 16777216 pixels "
      "(kMaxImagePixels); ask for a smaller width or height, or use the map tiles");
  // A fitted graph is square: width alone gives the same area.
  EXPECT_EQ(body(call(kAlice, "GET", path, "", {{"width", "8192"}}))["param"], "width");
  EXPECT_EQ(call(kAlice, "GET", path, "", {{"width", "4096"}, {"height", "16"}}).status, 200);
}

}  // namespace
}  // namespace trailscope::server
