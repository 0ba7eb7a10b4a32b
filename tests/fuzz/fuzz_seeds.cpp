// Writes the seeds that need TrailScope's own writers (tests/fuzz/seeds.sh runs it):
//   fuzz_seeds DEPTH_PNG_DIR OUT
// OUT/depth_pack/video.tsdv and OUT/depth_manifest/manifest.json: the 16-bit depth PNGs of DEPTH_PNG_DIR
// (real frames, cut small by seeds.sh) read as a video and written as a pack and as a folder by
// DepthVideoWriter; OUT/tracker_log_binary/log.pb and OUT/tracker_log_json/log.json: the hand-built log
// of the format tests (tests/compute/tracker_log/log_fixture.hpp: every field set) through encode_log;
// OUT/gaze_store_file/*.tsgz: the gaze_ingest seeds seeds.sh wrote before (OUT/gaze_ingest, real files cut
// small) read as gaze_ingest_fuzz reads them with the format detected, and written as the gaze store
// writes its files (encode_gaze_file): one per seed that reads, at most 12.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "../compute/tracker_log/log_fixture.hpp"
#include "store/gaze_file.hpp"
#include "trailscope/gaze/ingest.hpp"
#include "trailscope/tof/depth_video_io.hpp"
#include "trailscope/tracker/tracker_log.hpp"

namespace fs = std::filesystem;
using namespace trailscope;

namespace {
void write_file(const fs::path& p, const std::string& bytes) {
  fs::create_directories(p.parent_path());
  std::ofstream(p, std::ios::binary) << bytes;
}
}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: fuzz_seeds DEPTH_PNG_DIR OUT\n");
    return 2;
  }
  const fs::path out = argv[2];
  try {
    const tracker::TrackerLog log = tracker::test::sample_log(true);
    write_file(out / "tracker_log_binary" / "log.pb", tracker::encode_log(log, tracker::LogEncoding::binary));
    write_file(out / "tracker_log_json" / "log.json", tracker::encode_log(log, tracker::LogEncoding::json));

    const tof::DepthVideo video = tof::read_depth_video(argv[1]);
    const fs::path tmp = out / "tmp-video";
    fs::remove_all(tmp);
    fs::create_directories(tmp);
    tof::write_depth_video(video, tmp / "video.tsdv", {.layout = tof::VideoLayout::pack});
    tof::write_depth_video(video, tmp / "folder", {.layout = tof::VideoLayout::folder});
    fs::create_directories(out / "depth_pack");
    fs::create_directories(out / "depth_manifest");
    fs::copy_file(tmp / "video.tsdv", out / "depth_pack" / "video.tsdv",
                  fs::copy_options::overwrite_existing);
    fs::copy_file(tmp / "folder" / "manifest.json", out / "depth_manifest" / "manifest.json",
                  fs::copy_options::overwrite_existing);
    fs::remove_all(tmp);

    int gaze_seeds = 0;
    if (fs::is_directory(out / "gaze_ingest"))
      for (const auto& e : fs::directory_iterator(out / "gaze_ingest")) {
        if (gaze_seeds == 12) break;
        std::ifstream in(e.path(), std::ios::binary);
        const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        if (bytes.size() < 2) continue;
        try {
          const gaze::GazeDataset ds = gaze::read_gaze(std::string_view(bytes).substr(1), {});
          write_file(out / "gaze_store_file" / (e.path().filename().string() + ".tsgz"),
                     server::encode_gaze_file(ds));
          ++gaze_seeds;
        } catch (const Error&) {
          // a cut the readers refuse: not a seed for the stored format
        }
      }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fuzz_seeds: %s\n", e.what());
    return 1;
  }
  return 0;
}
