#pragma once
// A small line plot rendered to an RGBA image (no font library: digits from a 3x5 bitmap),
// for `orbis bench --sweep`: error against run time, one labelled point per setting.

#include "base/Png.h"

#include <string>
#include <vector>

namespace orbis::cli {

struct PlotPoint {
    double x = 0.0, y = 0.0;
    std::string label;   ///< digits, '.', '-', '=' and spaces are drawn
};

/// Plots y against x (both from 0 to their maximum), joined in the given order.
ImageRgba8 plotPoints(const std::vector<PlotPoint>& points, uint32_t width = 640, uint32_t height = 400);

}  // namespace orbis::cli
