// The (time, error) pictures of the evaluations: a log-log scatter plot written as SVG, one
// colour per series, tooltips on the markers, a legend on the right. Both axes are decades
// chosen to hold every drawable point; a point with a coordinate <= 0 or not finite has no place
// on a log axis and is left out (the CSV beside the plot still has it).
#pragma once

#include <string>
#include <vector>

namespace holo::eval {

struct PlotMarker {
  double x = 0;         // e.g. milliseconds per view
  double y = 0;         // e.g. MSE
  std::string tooltip;  // shown on hover
  bool filled = true;   // hollow markers flag a special state (not reached, off the front)
};

struct PlotSeries {
  std::string name;    // legend text
  std::string colour;  // SVG colour, e.g. "#1f77b4"
  std::vector<PlotMarker> markers;
  bool joined = false;         // a polyline through the markers in their given order
  bool dashed = false;         // for the polyline
  double marker_radius = 3.5;  // 0: no markers, only the polyline
  bool in_legend = true;
};

struct LogLogPlot {
  std::string title, x_label, y_label;
  std::string legend_note;  // one line under the legend, e.g. what hollow markers mean
  int width = 680, height = 440;
  std::vector<PlotSeries> series;
};

std::string svgOf(const LogLogPlot& plot);

}  // namespace holo::eval
