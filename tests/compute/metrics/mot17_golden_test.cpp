// MOT17-09-FRCNN with a real tracker's output must reproduce every column TrackEval wrote to
// pedestrian_detailed.csv for that sequence (the data set's manifest,
// $TRAILSCOPE_SHARED/data/tracker/SOURCES.md).
#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>

#include "test_support.hpp"
#include "trailscope/metrics/evaluate.hpp"
#include "trailscope/metrics/mot_text.hpp"

namespace trailscope::metrics {
namespace {

class Mot17Golden : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    const auto gt = read_text_file(test::shared_data("tracker/mot/gt/MOT17-09-FRCNN/gt/gt.txt"), "gt");
    const auto run = read_text_file(test::shared_data("tracker/mot/tracker_MoTT/MOT17-09-FRCNN.txt"), "run");
    MetricsOptions options;
    options.frames = 525;  // seqLength in seqinfo.ini
    report_ = new MetricsReport(evaluate_text(gt, run, options));
    reference_ = new std::map<std::string, double>(test::csv_row(
        test::shared_data("tracker/mot/tracker_MoTT/pedestrian_detailed.csv"), "MOT17-09-FRCNN"));
  }
  static void TearDownTestSuite() {
    delete report_;
    delete reference_;
  }
  static MetricsReport* report_;
  static std::map<std::string, double>* reference_;
};
MetricsReport* Mot17Golden::report_ = nullptr;
std::map<std::string, double>* Mot17Golden::reference_ = nullptr;

TEST_F(Mot17Golden, HeadlineNumbers) {
  const MetricsReport& r = *report_;
  EXPECT_NEAR(HotaResult::mean(r.hota.hota), 0.65188, 1e-4);
  EXPECT_NEAR(HotaResult::mean(r.hota.det_a), 0.77567, 1e-4);
  EXPECT_NEAR(HotaResult::mean(r.hota.ass_a), 0.54889, 1e-4);
  EXPECT_NEAR(r.clear.mota, 0.88038, 1e-4);
  EXPECT_NEAR(r.clear.motp, 0.87489, 1e-4);
  EXPECT_NEAR(r.identity.idf1, 0.73969, 1e-4);
  EXPECT_EQ(r.clear.idsw, 32);
  EXPECT_EQ(r.clear.clr_fp, 227);
  EXPECT_EQ(r.clear.clr_fn, 378);
  EXPECT_EQ(r.clear.clr_tp, 4947);
  EXPECT_EQ(r.gt_ids, 26);
  EXPECT_EQ(r.ids, 40);
}

TEST_F(Mot17Golden, EveryTrackEvalColumn) {
  ASSERT_FALSE(reference_->empty()) << "MOT17-09-FRCNN row missing from pedestrian_detailed.csv";
  const auto columns = trackeval_columns(*report_);
  std::size_t compared = 0;
  for (const auto& [name, value] : columns) {
    const auto it = reference_->find(name);
    ASSERT_NE(it, reference_->end()) << name << " is not a TrackEval column";
    // Counts and sums are large numbers: compare them relatively; ratios absolutely.
    const double tol = std::max(1e-4, 1e-9 * std::fabs(it->second));
    EXPECT_NEAR(value, it->second, tol) << name;
    ++compared;
  }
  EXPECT_EQ(compared, reference_->size()) << "a TrackEval column is not computed";
}

TEST_F(Mot17Golden, ExtrasAgreeWithTheSummary) {
  const ClearResult& c = report_->clear;
  long tp = 0, fn = 0, fp = 0, idsw = 0, frag = 0;
  for (const auto& f : c.frames) tp += f.tp, fn += f.fn, fp += f.fp, idsw += f.idsw;
  for (const auto& t : c.targets) frag += t.frag;
  EXPECT_EQ(c.frames.size(), 525u);
  EXPECT_EQ(c.targets.size(), 26u);
  EXPECT_EQ(tp, c.clr_tp);
  EXPECT_EQ(fn, c.clr_fn);
  EXPECT_EQ(fp, c.clr_fp);
  EXPECT_EQ(idsw, c.idsw);
  EXPECT_EQ(frag, c.frag);
  // MOTP is the mean IoU of matches and the IoU error is 1 - IoU.
  EXPECT_NEAR(c.mean_error, 1.0 - c.motp, 1e-12);
  EXPECT_GE(c.lost_episodes, c.frag);  // every resumption ends a lost episode
  EXPECT_TRUE(std::isfinite(c.jitter));
}

}  // namespace
}  // namespace trailscope::metrics
