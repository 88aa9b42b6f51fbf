#pragma once
// Small line plots rendered to RGBA images (no font library: text from a 3x5 bitmap): error
// against run time for `orbis bench --sweep`, one labelled point per setting; and timelines
// stacked in panels for `orbis bench --soak`.

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

/// One panel of a timeline: a title and (x, y) points in x order.
struct PlotSeries {
    std::string title;   ///< letters, digits and a little punctuation are drawn
    std::vector<std::pair<double, double>> points;
};

/// Panels stacked top to bottom over a shared x axis from 0 to the largest x; each panel's y
/// axis runs from 0 to its largest y, both ends labelled. `xTitle` goes under the last panel.
ImageRgba8 plotPanels(const std::vector<PlotSeries>& panels, const std::string& xTitle, uint32_t width = 800,
                      uint32_t panelHeight = 150);

}  // namespace orbis::cli
