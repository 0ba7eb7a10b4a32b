#pragma once
// Colormaps for shading density images: 256-entry RGB tables computed at start-up by linear interpolation
// between published colour stops (a subset of each published 256-entry table, chosen so that the
// interpolation stays within 0.5/255 of every published entry):
//  - fire: colorcet "fire" = CET linear_kryw_0-100_c71 (Kovesi, "Good Colour Maps: How to Design Them",
//    arXiv:1509.03700, 2015), Datashader's customary map for density;
//  - viridis, inferno, magma: van der Walt & Smith's matplotlib maps (matplotlib 2.0, 2015);
//  - gray: black to white.
// Index 0 is the colour of the lowest value, 255 of the highest.
#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace trailscope::density {

struct Colormap {
  std::string name;
  std::array<std::array<std::uint8_t, 3>, 256> rgb;  ///< sRGB, 8 bits per channel
};

/// The colormap called `name` (exact, lower case). Throws invalid_argument(param) listing the valid names
/// otherwise. The returned reference lives for the whole process; thread-safe.
const Colormap& colormap(std::string_view name, const std::string& param = "cmap");
/// The valid names, sorted: fire, gray, inferno, magma, viridis.
std::vector<std::string> colormap_names();

}  // namespace trailscope::density
