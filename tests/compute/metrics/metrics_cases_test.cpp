// Small hand-made sequences whose metrics can be worked out on paper.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/metrics/evaluate.hpp"

namespace trailscope::metrics {
namespace {

std::string gt_row(int frame, int id, double x, double y, double w = 10, double h = 10, int consider = 1,
                   int cls = 1) {
  return std::to_string(frame) + "," + std::to_string(id) + "," + std::to_string(x) + "," +
         std::to_string(y) + "," + std::to_string(w) + "," + std::to_string(h) + "," +
         std::to_string(consider) + "," + std::to_string(cls) + ",1\n";
}
std::string run_row(int frame, int id, double x, double y, double w = 10, double h = 10) {
  return std::to_string(frame) + "," + std::to_string(id) + "," + std::to_string(x) + "," +
         std::to_string(y) + "," + std::to_string(w) + "," + std::to_string(h) + ",1,-1,-1,-1\n";
}

MetricsReport eval(const std::string& gt, const std::string& run, std::int64_t frames = 0) {
  MetricsOptions o;
  o.frames = frames;
  return evaluate_text(gt, run, o);
}

TEST(MetricsCases, PerfectTrackerScoresOneEverywhere) {
  std::string gt, run;
  for (int f = 1; f <= 10; ++f) {
    gt += gt_row(f, 1, 10 * f, 0) + gt_row(f, 2, 200, 5 * f);
    run += run_row(f, 0, 10 * f, 0) + run_row(f, 7, 200, 5 * f);  // other ids, same boxes
  }
  const MetricsReport r = eval(gt, run);
  for (int a = 0; a < kHotaAlphas; ++a) {
    EXPECT_DOUBLE_EQ(r.hota.hota[a], 1.0);
    EXPECT_DOUBLE_EQ(r.hota.det_a[a], 1.0);
    EXPECT_DOUBLE_EQ(r.hota.ass_a[a], 1.0);
    EXPECT_DOUBLE_EQ(r.hota.loc_a[a], 1.0);
  }
  EXPECT_DOUBLE_EQ(r.clear.mota, 1.0);
  EXPECT_DOUBLE_EQ(r.clear.motp, 1.0);
  EXPECT_DOUBLE_EQ(r.identity.idf1, 1.0);
  EXPECT_EQ(r.clear.clr_tp, 20);
  EXPECT_EQ(r.clear.idsw + r.clear.clr_fp + r.clear.clr_fn + r.clear.frag, 0);
  EXPECT_EQ(r.clear.mt, 2);
  EXPECT_DOUBLE_EQ(r.clear.mean_error, 0.0);
  EXPECT_DOUBLE_EQ(r.clear.jitter, 0.0);
  EXPECT_EQ(r.clear.lost_episodes, 0);
  EXPECT_EQ(r.gt_ids, 2);
  EXPECT_EQ(r.ids, 2);
}

TEST(MetricsCases, IdSwitchIsCountedOnce) {
  std::string gt, run;
  for (int f = 1; f <= 10; ++f) gt += gt_row(f, 1, 0, 0), run += run_row(f, f <= 5 ? 5 : 6, 0, 0);
  const MetricsReport r = eval(gt, run);
  EXPECT_EQ(r.clear.idsw, 1);
  EXPECT_EQ(r.clear.frames[5].idsw, 1);  // frame 6
  EXPECT_EQ(r.clear.targets.at(0).idsw, 1);
  EXPECT_DOUBLE_EQ(r.clear.mota, 0.9);
  EXPECT_EQ(r.clear.frag, 0);
  EXPECT_EQ(r.identity.idtp, 5);
  EXPECT_EQ(r.identity.idfn, 5);
  EXPECT_EQ(r.identity.idfp, 5);
  EXPECT_DOUBLE_EQ(r.identity.idf1, 0.5);
  // Every TP pairs a 10-frame target with a 5-frame track sharing 5 frames: Jaccard 5 / 10.
  EXPECT_DOUBLE_EQ(HotaResult::mean(r.hota.det_a), 1.0);
  EXPECT_DOUBLE_EQ(HotaResult::mean(r.hota.ass_a), 0.5);
  EXPECT_DOUBLE_EQ(HotaResult::mean(r.hota.hota), std::sqrt(0.5));
}

TEST(MetricsCases, PreviousMatchIsKeptOverABetterOverlap) {
  // Frame 2: T1 overlaps G2 perfectly and G1 with IoU 90/110, T2 the reverse. CLEAR keeps G1-T1.
  const std::string gt = gt_row(1, 1, 0, 0) + gt_row(2, 1, 0, 0) + gt_row(2, 2, 1, 0);
  const std::string run = run_row(1, 1, 0, 0) + run_row(2, 1, 1, 0) + run_row(2, 2, 0, 0);
  const MetricsReport r = eval(gt, run);
  EXPECT_EQ(r.clear.idsw, 0);
  EXPECT_EQ(r.clear.clr_tp, 3);
  EXPECT_NEAR(r.clear.motp, (1.0 + 2 * 90.0 / 110.0) / 3, 1e-12);
}

TEST(MetricsCases, FragmentationAndLostEpisodes) {
  std::string gt, run;
  for (int f = 1; f <= 10; ++f) {
    gt += gt_row(f, 3, 0, 0);
    if (f <= 3 || f >= 6) run += run_row(f, 1, 0, 0);
  }
  // TrackEval skips frames without any tracker object when it follows matches, so a gap made only of
  // such frames is no fragmentation; lost episodes (ours) count it all the same.
  const MetricsReport quiet = eval(gt, run);
  EXPECT_EQ(quiet.clear.frag, 0);
  EXPECT_EQ(quiet.clear.lost_episodes, 1);
  run += run_row(4, 8, 500, 500) + run_row(5, 8, 500, 500);  // a false positive elsewhere in the gap
  const MetricsReport r = eval(gt, run);
  EXPECT_EQ(r.clear.clr_tp, 8);
  EXPECT_EQ(r.clear.clr_fn, 2);
  EXPECT_EQ(r.clear.frag, 1);
  EXPECT_EQ(r.clear.idsw, 0);
  EXPECT_EQ(r.clear.pt, 1);  // 0.8 covered is not "mostly tracked" (> 0.8)
  const ClearTarget& t = r.clear.targets.at(0);
  EXPECT_EQ(t.id, 3);
  EXPECT_EQ(t.lost_episodes, 1);
  EXPECT_EQ(t.frag, 1);
  EXPECT_EQ(t.coverage, "PT");
  EXPECT_EQ(t.jitter_pairs, 6);  // 1-2, 2-3, 6-7, 7-8, 8-9, 9-10
}

TEST(MetricsCases, EmptyRun) {
  std::string gt;
  for (int f = 1; f <= 5; ++f) gt += gt_row(f, 1, 0, 0) + gt_row(f, 2, 50, 0);
  const MetricsReport r = eval(gt, "");
  EXPECT_EQ(r.clear.clr_fn, 10);
  EXPECT_EQ(r.clear.clr_tp + r.clear.clr_fp + r.clear.idsw, 0);
  EXPECT_EQ(r.clear.ml, 2);
  EXPECT_DOUBLE_EQ(r.clear.mlr, 1.0);
  EXPECT_DOUBLE_EQ(r.clear.mota, 0.0);
  EXPECT_EQ(r.identity.idfn, 10);
  EXPECT_DOUBLE_EQ(r.identity.idf1, 0.0);
  EXPECT_DOUBLE_EQ(HotaResult::mean(r.hota.hota), 0.0);
  EXPECT_DOUBLE_EQ(r.hota.fn[0], 10.0);
  EXPECT_DOUBLE_EQ(r.hota.loc_a0, 1.0);  // TrackEval's convention
  EXPECT_EQ(r.clear.frames.size(), 5u);
  EXPECT_EQ(r.clear.frames[0].fn, 2);
  EXPECT_TRUE(std::isnan(r.clear.mean_error));
  EXPECT_EQ(r.dets, 0);
}

TEST(MetricsCases, EmptyGroundTruth) {
  const MetricsReport r = eval("", run_row(1, 1, 0, 0) + run_row(2, 1, 0, 0));
  EXPECT_EQ(r.clear.clr_fp, 2);
  EXPECT_DOUBLE_EQ(r.clear.mota, 0.0);  // TrackEval returns before computing MOTA
  EXPECT_EQ(r.identity.idfp, 2);
  EXPECT_DOUBLE_EQ(r.hota.fp[18], 2.0);
}

TEST(MetricsCases, HotaCountsATruePositiveUpToItsSimilarity) {
  // IoU exactly 0.5: a TP for alpha 0.05 .. 0.50 (10 thresholds), a FN and a FP above.
  const MetricsReport r = eval(gt_row(1, 1, 0, 0), run_row(1, 1, 0, 0, 10, 5));
  for (int a = 0; a < kHotaAlphas; ++a) {
    EXPECT_DOUBLE_EQ(r.hota.tp[a], a < 10 ? 1.0 : 0.0) << a;
    EXPECT_DOUBLE_EQ(r.hota.det_a[a], a < 10 ? 1.0 : 0.0) << a;
  }
  EXPECT_NEAR(HotaResult::mean(r.hota.det_a), 10.0 / 19.0, 1e-12);
  EXPECT_EQ(r.clear.clr_tp, 1);  // CLEAR's threshold 0.5 is inclusive
  EXPECT_DOUBLE_EQ(r.clear.motp, 0.5);
}

TEST(MetricsCases, MotChallengePreprocessing) {
  std::string gt, run;
  gt += gt_row(1, 1, 0, 0);                  // pedestrian, tracked: TP
  gt += gt_row(1, 2, 100, 0, 10, 10, 0, 7);  // static person (distractor): its run box is removed
  gt += gt_row(1, 3, 200, 0, 10, 10, 0, 3);  // car, not a distractor: its run box stays, a FP
  gt += gt_row(1, 4, 300, 0, 10, 10, 0, 1);  // zero-marked pedestrian: ignored, its run box is a FP
  run += run_row(1, 1, 0, 0) + run_row(1, 2, 100, 0) + run_row(1, 3, 200, 0) + run_row(1, 4, 300, 0);
  run += run_row(1, 5, 101, 0, 10, 3);  // low overlap with the distractor (0.27): stays, a FP
  const MetricsReport r = eval(gt, run);
  EXPECT_EQ(r.gt_dets, 1);
  EXPECT_EQ(r.dets, 4);
  EXPECT_EQ(r.clear.clr_tp, 1);
  EXPECT_EQ(r.clear.clr_fp, 3);
  EXPECT_EQ(r.gt_ids, 1);
}

TEST(MetricsCases, Mot15GroundTruthWithoutClasses) {
  // Class -1 everywhere: no distractor step, consider = 0 rows are still dropped.
  const std::string gt = gt_row(1, 1, 0, 0, 10, 10, 1, -1) + gt_row(1, 2, 100, 0, 10, 10, 0, -1);
  const MetricsReport r = eval(gt, run_row(1, 1, 0, 0));
  EXPECT_EQ(r.gt_dets, 1);
  EXPECT_EQ(r.clear.clr_tp, 1);
}

TEST(MetricsCases, DistanceSimilarityForPoints) {
  // A teat at the origin; the tracker is 2, 4, 2, 4, 2 mm off along x, then 12 mm off (no CLEAR match).
  std::string gt, run;
  const double dx[] = {2, 4, 2, 4, 2, 12};
  for (int f = 1; f <= 6; ++f) {
    gt += std::to_string(f) + ",1,0,0,500\n";
    run += std::to_string(f) + ",9," + std::to_string(dx[f - 1]) + ",0,500\n";
  }
  MetricsOptions o;
  o.kind = SimilarityKind::distance;
  o.d_max = 20;
  const MetricsReport r = evaluate_text(gt, run, o);
  EXPECT_EQ(r.clear.clr_tp, 5);
  EXPECT_EQ(r.clear.clr_fn, 1);
  EXPECT_NEAR(r.clear.mean_error, 2.8, 1e-12);  // mm
  EXPECT_NEAR(r.clear.jitter, 2.0, 1e-12);      // |4-2| four times
  EXPECT_NEAR(r.clear.motp, 1 - 2.8 / 20, 1e-12);
  EXPECT_EQ(r.clear.lost_episodes, 1);
  // sim 0.4 at 12 mm still counts for HOTA at alpha <= 0.4.
  EXPECT_DOUBLE_EQ(r.hota.tp[7], 6.0);  // alpha 0.40
  EXPECT_DOUBLE_EQ(r.hota.tp[8], 5.0);  // alpha 0.45
  o.d_max = 0;
  EXPECT_THROW(evaluate_text(gt, run, o), Error);
}

TEST(MetricsCases, StructuralErrorsNameTheFileAndLine) {
  try {
    eval(gt_row(1, 1, 0, 0) + gt_row(1, 1, 50, 0), "");
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::unprocessable);
    EXPECT_EQ(e.param(), "gt");
    EXPECT_NE(std::string(e.what()).find("line 2: id 1 appears twice in frame 1"), std::string::npos)
        << e.what();
  }
  try {
    eval(gt_row(1, 1, 0, 0), run_row(1, 1, 0, 0) + run_row(9, 1, 0, 0), 5);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.param(), "run");
    EXPECT_NE(std::string(e.what()).find("line 2: frame 9"), std::string::npos) << e.what();
  }
}

TEST(MetricsCases, CrowdedFrameIsRefused) {
  std::string run;
  for (std::size_t k = 0; k <= limits::kMaxObjectsPerFrame; ++k)
    run += run_row(1, static_cast<int>(k), 20.0 * k, 0);
  try {
    eval(gt_row(1, 1, 0, 0), run);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.kind(), Error::Kind::payload_too_large);
    EXPECT_EQ(e.param(), "run");
  }
}

TEST(MetricsCases, JsonAndTable) {
  const MetricsReport r = eval(gt_row(1, 1, 0, 0), "");
  const auto j = to_json(r, true);
  EXPECT_EQ(j["similarity"], "iou");
  EXPECT_EQ(j["metrics"]["CLR_FN"], 1.0);
  EXPECT_TRUE(j["extras"]["mean_error"].is_null());
  EXPECT_EQ(j["per_target"].size(), 1u);
  EXPECT_EQ(j["per_frame"].size(), 1u);
  EXPECT_FALSE(to_json(r, false).contains("per_frame"));
  const std::string table = to_table(r, "seq");
  EXPECT_NE(table.find("CLEAR: seq"), std::string::npos);
  EXPECT_NE(table.find("IDF1"), std::string::npos);
}

}  // namespace
}  // namespace trailscope::metrics
