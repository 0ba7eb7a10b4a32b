#pragma once
// Umbrella header of the density area, in pipeline order (after Datashader: Canvas → aggregate → shade).
#include "trailscope/density/canvas.hpp"
#include "trailscope/density/density_lines.hpp"
#include "trailscope/density/raster.hpp"
#include "trailscope/density/kde.hpp"
#include "trailscope/density/aggregate.hpp"
#include "trailscope/density/span.hpp"
#include "trailscope/density/colormap.hpp"
#include "trailscope/density/shade.hpp"
#include "trailscope/density/png.hpp"
#include "trailscope/density/renderer.hpp"
