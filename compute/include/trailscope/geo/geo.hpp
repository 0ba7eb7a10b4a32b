#pragma once
// Umbrella header of the geo area: Web Mercator and XYZ tile maths.
#include "trailscope/geo/tile_id.hpp"
#include "trailscope/geo/web_mercator.hpp"
