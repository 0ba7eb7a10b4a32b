// Runs the three metric families on one sequence and flattens them into TrackEval's column layout.
#include "trailscope/metrics/evaluate.hpp"

#include <chrono>

namespace trailscope::metrics {
namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

MetricsReport evaluate(const EvalSequence& seq) {
  const auto t0 = std::chrono::steady_clock::now();
  MetricsReport r;
  r.kind = seq.kind;
  r.d_max = seq.d_max;
  r.hota = hota_metrics(seq);
  r.clear = clear_metrics(seq);
  r.identity = identity_metrics(seq);
  r.dets = static_cast<long>(seq.num_trk_dets);
  r.gt_dets = static_cast<long>(seq.num_gt_dets);
  r.ids = seq.num_trk_ids();
  r.gt_ids = seq.num_gt_ids();
  r.ms = ms_since(t0);
  return r;
}

MetricsReport evaluate_text(std::string_view gt_text, std::string_view run_text,
                            const MetricsOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  EvalSequence seq;
  if (options.kind == SimilarityKind::iou)
    seq = mot_challenge_sequence(parse_mot_gt(gt_text), parse_mot_run(run_text), options.frames);
  else
    seq = point_sequence(parse_points(gt_text, "gt"), parse_points(run_text, "run"), options.d_max,
                         options.frames);
  MetricsReport r = evaluate(seq);
  r.ms = ms_since(t0);
  return r;
}

std::vector<std::pair<std::string, double>> trackeval_columns(const MetricsReport& r) {
  std::vector<std::pair<std::string, double>> c;
  const HotaResult& h = r.hota;
  c.emplace_back("HOTA(0)", h.hota0);
  c.emplace_back("LocA(0)", h.loc_a0);
  c.emplace_back("HOTALocA(0)", h.hota_loc_a0);
  const std::pair<const char*, const HotaCurve*> curves[] = {
      {"HOTA", &h.hota},    {"DetA", &h.det_a},   {"AssA", &h.ass_a},   {"DetRe", &h.det_re},
      {"DetPr", &h.det_pr}, {"AssRe", &h.ass_re}, {"AssPr", &h.ass_pr}, {"LocA", &h.loc_a},
      {"RHOTA", &h.rhota},  {"HOTA_TP", &h.tp},   {"HOTA_FN", &h.fn},   {"HOTA_FP", &h.fp}};
  for (const auto& [name, curve] : curves) {
    for (int a = 0; a < kHotaAlphas; ++a)
      c.emplace_back(std::string(name) + "___" + std::to_string(5 * (a + 1)), (*curve)[a]);
    c.emplace_back(std::string(name) + "___AUC", HotaResult::mean(*curve));
  }
  const ClearResult& k = r.clear;
  const std::pair<const char*, double> clear[] = {{"MOTA", k.mota},
                                                  {"MOTP", k.motp},
                                                  {"MODA", k.moda},
                                                  {"CLR_Re", k.clr_re},
                                                  {"CLR_Pr", k.clr_pr},
                                                  {"MTR", k.mtr},
                                                  {"PTR", k.ptr},
                                                  {"MLR", k.mlr},
                                                  {"sMOTA", k.smota},
                                                  {"CLR_F1", k.clr_f1},
                                                  {"FP_per_frame", k.fp_per_frame},
                                                  {"MOTAL", k.motal},
                                                  {"MOTP_sum", k.motp_sum},
                                                  {"CLR_TP", double(k.clr_tp)},
                                                  {"CLR_FN", double(k.clr_fn)},
                                                  {"CLR_FP", double(k.clr_fp)},
                                                  {"IDSW", double(k.idsw)},
                                                  {"MT", double(k.mt)},
                                                  {"PT", double(k.pt)},
                                                  {"ML", double(k.ml)},
                                                  {"Frag", double(k.frag)},
                                                  {"CLR_Frames", double(k.clr_frames)}};
  for (const auto& [name, v] : clear) c.emplace_back(name, v);
  const IdentityResult& i = r.identity;
  const std::pair<const char*, double> id[] = {{"IDF1", i.idf1},         {"IDR", i.idr},
                                               {"IDP", i.idp},           {"IDTP", double(i.idtp)},
                                               {"IDFN", double(i.idfn)}, {"IDFP", double(i.idfp)}};
  for (const auto& [name, v] : id) c.emplace_back(name, v);
  c.emplace_back("Dets", double(r.dets));
  c.emplace_back("GT_Dets", double(r.gt_dets));
  c.emplace_back("IDs", double(r.ids));
  c.emplace_back("GT_IDs", double(r.gt_ids));
  return c;
}

}  // namespace trailscope::metrics
