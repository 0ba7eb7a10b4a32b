// MOTChallenge files and metrics over the API, in process: MOT17-09-FRCNN ground truth and a real
// tracker's output uploaded and evaluated reproduce every column of TrackEval's pedestrian_detailed.csv;
// malformed files are refused with the reader's message; list, get, delete and persistence; the metrics
// body's errors.
#include <cmath>

#include <gtest/gtest.h>

#include "test_support.hpp"
#include "tracker_fixture.hpp"
#include "trailscope/metrics/evaluate.hpp"
#include "trailscope/metrics/mot_text.hpp"

namespace trailscope::server {
namespace {

const std::filesystem::path& gt_file() {
  static const auto p = test::shared_data("tracker/mot/gt/MOT17-09-FRCNN/gt/gt.txt");
  return p;
}
const std::filesystem::path& run_file() {
  static const auto p = test::shared_data("tracker/mot/tracker_MoTT/MOT17-09-FRCNN.txt");
  return p;
}

class MotTest : public test_routes::TrackerFixture {
 protected:
  std::string post_mot(const std::string& kind, const std::string& text, const std::string& name = "") {
    const Response r = send("POST", "/api/v1/mot", text, {{"kind", kind}, {"name", name}});
    EXPECT_EQ(r.status, 201) << r.body;
    return r.status == 201 ? body(r).at("id").get<std::string>() : "";
  }
  Response metrics(const nlohmann::json& j) { return send("POST", "/api/v1/metrics", j.dump()); }
};

TEST_F(MotTest, Mot17UploadedAndEvaluatedReproducesTrackEval) {
  const Response g = upload("/api/v1/mot", gt_file(), {{"kind", "gt"}, {"name", "MOT17-09 gt"}});
  ASSERT_EQ(g.status, 201) << g.body;
  const auto gt = body(g);
  EXPECT_EQ(gt["id"], "m1");
  EXPECT_EQ(header(g, "Location"), "/api/v1/mot/m1");
  EXPECT_EQ(gt["kind"], "gt");
  EXPECT_EQ(gt["name"], "MOT17-09 gt");
  EXPECT_EQ(gt["rows"], 10411);
  EXPECT_EQ(gt["frames"], 525);
  EXPECT_EQ(gt["bytes"], std::filesystem::file_size(gt_file()));
  const Response u = upload("/api/v1/mot", run_file(), {{"kind", "result"}});
  ASSERT_EQ(u.status, 201) << u.body;
  EXPECT_EQ(body(u)["id"], "m2");
  EXPECT_EQ(body(u)["rows"], 5174);

  const Response r = metrics({{"gt", "m1"}, {"run", "m2"}, {"frames", 525}});
  ASSERT_EQ(r.status, 200) << r.body.substr(0, 500);
  const auto j = body(r);
  const auto& m = j["metrics"];
  EXPECT_NEAR(m["HOTA___AUC"].get<double>(), 0.65188, 1e-4);
  EXPECT_NEAR(m["MOTA"].get<double>(), 0.88038, 1e-4);
  EXPECT_NEAR(m["IDF1"].get<double>(), 0.73969, 1e-4);
  EXPECT_EQ(m["IDSW"], 32);
  // Every column TrackEval wrote for the sequence.
  const auto reference =
      test::csv_row(test::shared_data("tracker/mot/tracker_MoTT/pedestrian_detailed.csv"), "MOT17-09-FRCNN");
  ASSERT_FALSE(reference.empty());
  for (const auto& [name, value] : reference) {
    ASSERT_TRUE(m.contains(name)) << name;
    const double tol = std::max(1e-4, 1e-9 * std::fabs(value));
    EXPECT_NEAR(m[name].get<double>(), value, tol) << name;
  }
  EXPECT_EQ(m.size(), reference.size());
  EXPECT_FALSE(j.contains("per_frame"));

  // The same JSON as `trailscope metrics --json` (metrics::to_json of the files), but for the time.
  metrics::MetricsOptions options;
  options.frames = 525;
  auto expected =
      metrics::to_json(metrics::evaluate_text(metrics::read_text_file(gt_file(), "gt"),
                                              metrics::read_text_file(run_file(), "run"), options),
                       true);
  const Response detailed = metrics({{"gt", "m1"}, {"run", "m2"}, {"frames", 525}, {"per_frame", true}});
  ASSERT_EQ(detailed.status, 200);
  auto got = body(detailed);
  EXPECT_GE(got["ms"].get<double>(), 0.0);
  got.erase("ms"), expected.erase("ms");
  EXPECT_EQ(got, expected);
  EXPECT_EQ(got["per_frame"].size(), 525u);
}

TEST_F(MotTest, MalformedLinesAreReportedWithTheReadersMessage) {
  const std::string text = "1,1,10,10,5,5,1,1,1\nnot a line\n2,1,10,10,5,5,1,1,1\n3,x,10,10,5,5,1,1,1\n";
  std::string message;
  try {
    metrics::parse_mot_gt(text, "body");
  } catch (const Error& e) {
    message = e.what();
  }
  ASSERT_NE(message.find("line 2"), std::string::npos) << message;
  ASSERT_NE(message.find("line 4"), std::string::npos) << message;
  const Response r = send("POST", "/api/v1/mot", text, {{"kind", "gt"}});
  expect_detail(r, 422, "unprocessable", "body", message);
  // A ground-truth file is not a result file's format and the other way round only where columns lack.
  expect_error(send("POST", "/api/v1/mot", "1,1,10,10,5,5\n", {{"kind", "gt"}}), 422, "unprocessable",
               "body");
  EXPECT_EQ(send("POST", "/api/v1/mot", "1,1,10,10,5,5\n", {{"kind", "result"}}).status, 201);
  expect_detail(send("POST", "/api/v1/mot", "", {{"kind", "gt"}}), 400, "invalid_argument", "body",
                "body: the upload is empty");
  expect_detail(send("POST", "/api/v1/mot", text), 400, "invalid_argument", "kind",
                "kind: required (gt, result or points)");
  expect_detail(send("POST", "/api/v1/mot", text, {{"kind", "boxes"}}), 400, "invalid_argument", "kind",
                "kind must be gt, result or points, got 'boxes'");
  expect_error(send("POST", "/api/v1/mot", text, {{"kind", "gt"}, {"colour", "red"}}), 400,
               "invalid_argument", "colour");
  EXPECT_EQ(body(get("/api/v1/mot"))["files"].size(), 1u);  // only the good one was stored
}

TEST_F(MotTest, UploadBeyondTheLimitIs413) {
  Request r;
  r.method = "POST", r.path = "/api/v1/mot", r.query = {{"kind", "gt"}};
  r.body_file = store->upload_dir() / "too-large";
  std::ofstream(r.body_file).put('1');
  std::filesystem::resize_file(r.body_file, limits::kMaxRunBytes + 1);  // sparse: no disk used
  expect_detail(router.handle(r), 413, "payload_too_large", "body",
                "MOT file upload exceeds the limit of 256 MiB");
  EXPECT_FALSE(std::filesystem::exists(r.body_file));  // the streamed body is removed
  EXPECT_EQ(body(get("/api/v1/mot"))["files"].size(), 0u);
}

TEST_F(MotTest, ListGetDeleteAndPersistence) {
  const std::string a = post_mot("gt", "1,1,10,10,5,5,1,1,1\n2,1,11,10,5,5,1,1,1\n", "a");
  const std::string b = post_mot("points", "1,0,1,2,3\n1,1,4,5,6\n", "b");
  EXPECT_EQ(a, "m1");
  EXPECT_EQ(b, "m2");
  const auto one = body(get("/api/v1/mot/m2"));
  EXPECT_EQ(one["kind"], "points");
  EXPECT_EQ(one["rows"], 2);
  EXPECT_EQ(one["ids"], 2);
  EXPECT_EQ(one["frames"], 1);
  open_empty();  // a restart
  const auto files = body(get("/api/v1/mot"))["files"];
  ASSERT_EQ(files.size(), 2u);
  EXPECT_EQ(files[0]["id"], "m1");
  EXPECT_EQ(files[0]["name"], "a");
  EXPECT_EQ(send("DELETE", "/api/v1/mot/m1").status, 204);
  expect_detail(get("/api/v1/mot/m1"), 404, "not_found", "mot", "MOT file 'm1' does not exist");
  expect_error(send("DELETE", "/api/v1/mot/m1"), 404, "not_found", "mot");
  open_empty();
  ASSERT_EQ(body(get("/api/v1/mot"))["files"].size(), 1u);
  EXPECT_EQ(post_mot("result", "1,1,1,1,1,1\n"), "m3");  // ids are not reused
}

TEST_F(MotTest, MetricsBodyErrorsNameTheField) {
  const std::string gt = post_mot("gt", "1,1,10,10,5,5,1,1,1\n2,1,11,10,5,5,1,1,1\n");
  const std::string run = post_mot("result", "1,7,10,10,5,5,1\n2,7,11,10,5,5,1\n");
  const std::string pts = post_mot("points", "1,0,1,2,3\n2,0,1,2,3\n");
  const Response ok = metrics({{"gt", gt}, {"run", run}});
  ASSERT_EQ(ok.status, 200) << ok.body;
  EXPECT_DOUBLE_EQ(body(ok)["metrics"]["MOTA"].get<double>(), 1.0);
  EXPECT_DOUBLE_EQ(body(ok)["metrics"]["IDF1"].get<double>(), 1.0);
  const Response dist = metrics({{"gt", pts}, {"run", pts}, {"similarity", "distance"}, {"d_max", 50}});
  ASSERT_EQ(dist.status, 200) << dist.body;
  EXPECT_EQ(body(dist)["similarity"], "distance");
  EXPECT_DOUBLE_EQ(body(dist)["metrics"]["MOTA"].get<double>(), 1.0);

  expect_detail(metrics({{"gt", "m9"}, {"run", run}}), 404, "not_found", "gt",
                "MOT file 'm9' does not exist");
  expect_detail(metrics({{"gt", gt}, {"run", "m9"}}), 404, "not_found", "run",
                "MOT file 'm9' does not exist");
  expect_detail(metrics({{"gt", gt}, {"run", gt}}), 400, "invalid_argument", "run",
                "run: MOT file 'm1' is of kind gt, similarity iou needs kind result");
  expect_detail(metrics({{"gt", gt}, {"run", pts}, {"similarity", "distance"}}), 400, "invalid_argument",
                "gt", "gt: MOT file 'm1' is of kind gt, similarity distance needs kind points");
  expect_detail(metrics({{"gt", gt}, {"run", run}, {"similarity", "giou"}}), 400, "invalid_argument",
                "similarity", "similarity must be iou or distance, got 'giou'");
  expect_detail(metrics({{"run", run}}), 400, "invalid_argument", "gt", "gt: required");
  expect_detail(metrics({{"gt", gt}, {"run", run}, {"per_frame", 1}}), 400, "invalid_argument", "per_frame",
                "per_frame: must be true or false");
  expect_detail(metrics({{"gt", gt}, {"run", run}, {"frames", 1.5}}), 400, "invalid_argument", "frames",
                "frames: must be an integer");
  expect_error(metrics({{"gt", gt}, {"run", run}, {"frames", -1}}), 400, "invalid_argument", "frames");
  expect_error(metrics({{"gt", pts}, {"run", pts}, {"similarity", "distance"}, {"d_max", -5}}), 400,
               "invalid_argument", "d_max");
  expect_detail(metrics({{"gt", gt}, {"run", run}, {"colour", 1}}), 400, "invalid_argument", "colour",
                "unknown field 'colour'");
  expect_error(send("POST", "/api/v1/metrics", "[1]"), 400, "invalid_argument", "body");
}

}  // namespace
}  // namespace trailscope::server
