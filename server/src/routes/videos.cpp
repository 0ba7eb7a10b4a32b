#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <random>

#include "routes/handlers.hpp"
#include "routes/params.hpp"
#include "routes/tracker_body.hpp"
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

VideoStore& video_store(App& app) {
  if (!app.videos) throw Error(Error::Kind::internal, "", "this server was started without a video store");
  return *app.videos;
}

std::string video_name(const std::string& name) {
  if (name.size() > kMaxVideoNameLength)
    throw invalid_argument("name", "name: at most " + std::to_string(kMaxVideoNameLength) + " characters");
  return name;
}

/// A finite number query parameter, or `fallback` when absent. Throws invalid_argument(name).
double number_param(const Request& req, const std::string& name, double fallback) {
  auto it = req.query.find(name);
  if (it == req.query.end()) return fallback;
  const std::string& text = it->second;
  double v = 0;
  auto [p, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || p != text.data() + text.size() || text.empty() || !std::isfinite(v))
    throw invalid_argument(name, name + ": '" + text + "' is not a number");
  return v;
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
fs::path upload_file(App& app, const Request& req) {
  if (!req.body_file.empty()) {
    std::error_code ec;
    const auto size = fs::file_size(req.body_file, ec);
    if (ec) throw Error(Error::Kind::internal, "", "cannot read upload " + req.body_file.string());
    if (size > limits::kMaxVideoUploadBytes) throw Error(Error::Kind::payload_too_large, "body", kTooLarge);
    if (size == 0) throw invalid_argument("body", "body: the upload is empty");
    return req.body_file;
  }
  if (req.body.empty()) throw invalid_argument("body", "body: the upload is empty");
  std::random_device rd;
  const fs::path file = app.upload_dir / ("inline-" + std::to_string(rd()) + std::to_string(rd()));
  std::ofstream out(file, std::ios::binary);
  out.write(req.body.data(), static_cast<std::streamsize>(req.body.size()));
  out.close();
  if (!out) throw Error(Error::Kind::internal, "", "cannot write upload to " + file.string());
  return file;
}

/// Gives a reserved video id back unless the job committed it (a job cancelled while queued never runs).
struct Reservation {
  std::shared_ptr<VideoStore> store;
  std::string id;
  ~Reservation() { store->release(id); }
};
}  // namespace

Response list_videos(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  return Response::json(200, {{"videos", video_store(app).list()}});
}

Response get_video(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  return Response::json(200, video_store(app).meta(p.at("video")));
}

Response delete_video(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  video_store(app).remove(p.at("video"));
  return Response::no_content();
}

Response create_video(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {"name"});
  VideoStore& videos = video_store(app);
  auto n = req.query.find("name");
  const std::string name = video_name(n == req.query.end() ? "" : n->second);
  const fs::path file = upload_file(app, req);
  std::string id;
  try {
    id = videos.reserve();
  } catch (...) {
    std::error_code ec;
    fs::remove(file, ec);
    throw;
  }
  const nlohmann::json meta = videos.commit_pack(id, file, name);
  Response res = Response::json(201, meta);
  res.headers.emplace_back("Location", "/api/v1/videos/" + id);
  return res;
}

Response synth_video(App& app, const Request& req, const PathParams&) {
  reject_unknown_params(req, {});
  const nlohmann::json j = parse_body_object(
      req.body, {"scenario", "frames", "seed", "width", "height", "fps", "noise_free", "name"});
  tof::SynthOptions o;
  o.scenario = tof::parse_scenario(string_field(j, "scenario"));
  const auto integer = [&](const char* k, auto& out) {
    auto it = j.find(k);
    if (it == j.end()) return;
    if (!it->is_number_integer() || (it->is_number_integer() && it->template get<std::int64_t>() < 0))
      throw invalid_argument(k, std::string(k) + ": must be a non-negative integer");
    using T = std::remove_reference_t<decltype(out)>;
    const auto v = it->template get<std::uint64_t>();
    if (v > static_cast<std::uint64_t>(std::numeric_limits<T>::max()))
      throw invalid_argument(k, std::string(k) + ": " + std::to_string(v) + " is too large");
    out = static_cast<T>(v);
  };
  integer("frames", o.frames);
  integer("seed", o.seed);
  integer("width", o.width);
  integer("height", o.height);
  if (auto it = j.find("fps"); it != j.end()) {
    if (!it->is_number()) throw invalid_argument("fps", "fps: must be a number");
    o.fps = it->get<double>();
  }
  if (auto it = j.find("noise_free"); it != j.end()) {
    if (!it->is_boolean()) throw invalid_argument("noise_free", "noise_free: must be true or false");
    o.noise_free = it->get<bool>();
  }
  std::string name;
  if (j.contains("name")) name = video_name(string_field(j, "name"));
  if (name.empty()) name = std::string(tof::to_string(o.scenario)) + " seed " + std::to_string(o.seed);
  tof::ToFSynth check(o);  // every option's range, now rather than in the job
  VideoStore& videos = video_store(app);
  // Built in place: a copy's destructor would give the id back at once.
  const std::shared_ptr<Reservation> reservation(new Reservation{app.videos, videos.reserve()});
  const std::string id = reservation->id;
  const JobState job = app.jobs.submit(
      "synth", id, [reservation, o, name](const ProgressFn& progress, const CancelToken& cancel) {
        const ProgressFn report = [&](double f, std::string_view stage) {
          cancel.throw_if_cancelled();  // the writer removes its temporary file on the way out
          progress(f, stage);
        };
        return reservation->store->commit_synthetic(reservation->id, o, name, report);
      });
  Response res = Response::json(202, {{"job", job.to_json()}, {"video", id}});
  res.headers.emplace_back("Location", "/api/v1/jobs/" + job.id);
  return res;
}

Response video_frame(App& app, const Request& req, const PathParams& p) {
  reject_unknown_params(req, {});
  const std::string id = p.at("video");
  const tof::DepthVideoReader reader(video_store(app).pack_path(id));
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
  const double min = number_param(req, "min", NAN), max = number_param(req, "max", NAN);
  const tof::DepthVideoReader reader(video_store(app).pack_path(id));
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
  const tof::DepthVideoReader reader(video_store(app).pack_path(id));
  const tof::DepthFrame f = reader.read_frame(frame_index(p, reader, id));
  const auto& k = reader.info().intrinsics;
  return png(density::encode_png(tof::render_amplitude(f.amplitude, k.width, k.height)));
}

}  // namespace trailscope::server::handlers
