#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <random>

#include "jobs/synth_job.hpp"
#include "routes/handlers.hpp"
#include "params/query_params.hpp"
#include "params/upload_body.hpp"
#include "params/json_fields.hpp"
#include "trailscope/core/error.hpp"
#include "trailscope/core/limits.hpp"
#include "trailscope/density/png.hpp"
#include "trailscope/tof/depth_render.hpp"
#include "trailscope/tof/depth_video_io.hpp"

namespace trailscope::server::handlers {
namespace fs = std::filesystem;

namespace {
/// Longest display name of a video (characters).
constexpr std::size_t kMaxVideoNameLength = 128;
/// The colormap of depth pictures unless ?colormap= says otherwise.
constexpr char kDefaultColormap[] = "viridis";

const std::string kTooLarge =
    "video upload exceeds the limit of " + std::to_string(limits::kMaxVideoUploadBytes >> 30) + " GiB";

std::string video_name(const std::string& name) {
  if (name.size() > kMaxVideoNameLength)
    throw invalid_argument("name", "name: at most " + std::to_string(kMaxVideoNameLength) + " characters");
  return name;
}

/// The frame `{i}` of a video: 400 when not an index, 404 beyond the video's frames.
std::size_t frame_index(const PathParams& p, const tof::DepthVideoReader& reader, const std::string& video) {
  const auto i = static_cast<std::size_t>(params::path_integer(p, "i", 0, 1'000'000'000));
  if (i >= reader.size())
    throw not_found("i", "video '" + video + "' has " + std::to_string(reader.size()) + " frames (0.." +
                             std::to_string(reader.size() - 1) + "); there is no frame " + std::to_string(i));
  return i;
}

Response png(std::string bytes) {
  Response res;
  res.content_type = "image/png";
  res.body = std::move(bytes);
  // A stored video never changes (an id is not reused while the server runs).
  res.headers.emplace_back("Cache-Control", "private, max-age=3600");
  return res;
}

/// The upload as a file: the streamed body, or a small in-memory body spilled to the upload folder.
fs::path video_upload_file(App& app, const Request& req) {
  if (!req.body_file.empty()) {
    std::error_code ec;
    const auto size = fs::file_size(req.body_file, ec);
    if (ec) throw Error(Error::Kind::internal, "", "cannot read upload " + req.body_file.string());
    if (size > limits::kMaxVideoUploadBytes) throw Error(Error::Kind::payload_too_large, "body", kTooLarge);
    if (size == 0) throw invalid_argument("body", "body: the upload is empty");
    return req.body_file;
  }
  return server::upload_file(req, app.upload_dir);
}

}  // namespace

namespace {
// The name of a video upload, checked: what the precheck runs on the header and the handler again.
std::string video_upload(App& app, const Request& req) {
  reject_unknown_params(req, {"name"});
  need(app.videos, "a video store");
  auto n = req.query.find("name");
  return video_name(n == req.query.end() ? "" : n->second);
}
}  // namespace

void create_video_check(App& app, const Request& req, const PathParams&) {
  video_upload(app, req);
}

Response create_video(App& app, const Request& req, const PathParams&) {
  const std::string name = video_upload(app, req);
  VideoStore& videos = *app.videos;
  const fs::path file = video_upload_file(app, req);
  std::string id;
  try {
    id = videos.reserve();
  } catch (...) {
    std::error_code ec;
    fs::remove(file, ec);
    throw;
  }
  const nlohmann::json meta = videos.commit_pack(id, file, name, req.principal.owner);
  return Response::json_at(201, meta, "/api/v1/videos/" + id);
}

Response synth_video(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  const nlohmann::json j = parse_body_object(
      req.body, {"scenario", "frames", "seed", "width", "height", "fps", "noise_free", "name"});
  tof::SynthOptions o;
  o.scenario = tof::parse_scenario(string_field(j, "scenario"));
  unsigned_field(j, "frames", o.frames);
  unsigned_field(j, "seed", o.seed);
  unsigned_field(j, "width", o.width);
  unsigned_field(j, "height", o.height);
  o.fps = number_field(j, "fps", o.fps);
  o.noise_free = bool_field(j, "noise_free", o.noise_free);
  std::string name;
  if (j.contains("name")) name = video_name(string_field(j, "name"));
  if (name.empty()) name = std::string(tof::to_string(o.scenario)) + " seed " + std::to_string(o.seed);
  tof::ToFSynth check(o);             // every option's range, now rather than in the job
  need(app.videos, "a video store");  // the server has a video store
  const auto [job, id] = submit_synth(app.jobs, app.videos, o, name, *app.disk, req.principal.owner);
  return Response::json_at(202, {{"job", job.to_json()}, {"video", id}}, "/api/v1/jobs/" + job.id);
}

Response video_frame(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  const std::string id = p.at("video");
  const tof::DepthVideoReader reader(need(app.videos, "a video store").pack_path(id));
  const std::size_t i = frame_index(p, reader, id);
  const tof::DepthFrame f = reader.read_frame(i);
  return Response::json(200, {{"video", id},
                              {"index", i},
                              {"timestamp_s", f.timestamp_s},
                              {"truth", f.truth ? tof::truth_to_json(*f.truth) : nlohmann::json(nullptr)}});
}

Response video_depth_png(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {"min", "max", "colormap"});
  const std::string id = p.at("video");
  auto c = req.query.find("colormap");
  const density::Colormap& cmap =
      density::colormap(c == req.query.end() ? kDefaultColormap : c->second, "colormap");
  // Parameters before the frame is read: a malformed query is a 400 whatever the frame.
  const double min = params::number(req, "min", NAN), max = params::number(req, "max", NAN);
  const tof::DepthVideoReader reader(need(app.videos, "a video store").pack_path(id));
  const tof::DepthFrame f = reader.read_frame(frame_index(p, reader, id));
  tof::DepthRange range{min, max};
  if (std::isnan(min) || std::isnan(max)) {
    const tof::DepthRange q = tof::depth_quantile_range(f.depth_mm);
    if (std::isnan(min)) range.min_mm = q.min_mm;
    if (std::isnan(max)) range.max_mm = q.max_mm;
  }
  if (!(range.min_mm < range.max_mm))
    throw invalid_argument(req.query.count("max") ? "max" : "min",
                           "the depth range must have min < max (mm), got min " +
                               std::to_string(range.min_mm) + ", max " + std::to_string(range.max_mm));
  const auto& k = reader.info().intrinsics;
  return png(density::encode_png(tof::render_depth(f.depth_mm, k.width, k.height, range, cmap)));
}

Response video_amplitude_png(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  const std::string id = p.at("video");
  const tof::DepthVideoReader reader(need(app.videos, "a video store").pack_path(id));
  const tof::DepthFrame f = reader.read_frame(frame_index(p, reader, id));
  const auto& k = reader.info().intrinsics;
  return png(density::encode_png(tof::render_amplitude(f.amplitude, k.width, k.height)));
}

}  // namespace trailscope::server::handlers
