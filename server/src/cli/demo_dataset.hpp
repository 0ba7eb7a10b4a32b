#pragma once
// The generated demo dataset (a day of US airline traffic), shared by `serve --demo` and `demo`.
#include <cstdint>
#include <string>

#include "store/dataset_store.hpp"
#include "store/video_store.hpp"

namespace trailscope::cli {

/// Folder of vega-datasets' data files: `source` if given, else web/node_modules/vega-datasets/data.
/// Throws not_found("demo-source") naming the missing file.
std::string demo_source_dir(const std::string& source);

/// Generates `flights` flights with `seed` and stores them as dataset `id`, with a progress bar.
void create_demo_dataset(server::DatasetStore& store, const std::string& id, std::size_t flights,
                         std::uint64_t seed, const std::string& source);

/// The demo's depth videos for the tracker dashboard (cli/demo_videos.cpp): synthetic "standard" (500
/// frames, seed 1) and "cups-attached" (500 frames, seed 2), each generated (about a second) when no video
/// of its name is stored.
void create_demo_videos(server::VideoStore& videos);

}  // namespace trailscope::cli
