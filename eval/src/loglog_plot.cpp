#include "holo/eval/loglog_plot.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace holo::eval {
namespace {

bool drawable(const PlotMarker& m) {
  return std::isfinite(m.x) && std::isfinite(m.y) && m.x > 0 && m.y > 0;
}

// Markup characters in tooltips and labels (method knobs hold '<' or '&' at times).
std::string escaped(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else if (c == '\'')
      out += "&apos;";
    else
      out += c;
  }
  return out;
}

}  // namespace

std::string svgOf(const LogLogPlot& plot) {
  const double W = plot.width, H = plot.height, L = 70, R = 190, T = 40, B = 50;
  double x_lo = HUGE_VAL, x_hi = 0, y_lo = HUGE_VAL, y_hi = 0;
  for (const PlotSeries& series : plot.series)
    for (const PlotMarker& m : series.markers)
      if (drawable(m))
        x_lo = std::min(x_lo, m.x), x_hi = std::max(x_hi, m.x), y_lo = std::min(y_lo, m.y),
        y_hi = std::max(y_hi, m.y);
  if (!(x_hi > 0)) x_lo = 1, x_hi = 10, y_lo = 1e-4, y_hi = 1e-2;
  const double dx0 = std::floor(std::log10(x_lo)), dx1 = std::ceil(std::log10(x_hi) + 1e-9);
  const double dy0 = std::floor(std::log10(y_lo)), dy1 = std::ceil(std::log10(y_hi) + 1e-9);
  const auto px = [&](double x) {
    return L + (std::log10(x) - dx0) / std::max(dx1 - dx0, 1.0) * (W - L - R);
  };
  const auto py = [&](double y) {
    return H - B - (std::log10(y) - dy0) / std::max(dy1 - dy0, 1.0) * (H - T - B);
  };

  std::ostringstream s;
  s << "<svg xmlns='http://www.w3.org/2000/svg' width='" << W << "' height='" << H
    << "' font-family='sans-serif' font-size='12'>\n<rect width='100%' height='100%' fill='white'/>\n"
    << "<text x='" << L << "' y='22' font-size='14'>" << escaped(plot.title) << "</text>\n";
  for (double d = dx0; d <= dx1; ++d)
    s << "<line x1='" << px(std::pow(10, d)) << "' y1='" << T << "' x2='" << px(std::pow(10, d)) << "' y2='"
      << H - B << "' stroke='#ddd'/><text x='" << px(std::pow(10, d)) - 12 << "' y='" << H - B + 16 << "'>1e"
      << d << "</text>\n";
  for (double d = dy0; d <= dy1; ++d)
    s << "<line x1='" << L << "' y1='" << py(std::pow(10, d)) << "' x2='" << W - R << "' y2='"
      << py(std::pow(10, d)) << "' stroke='#ddd'/><text x='20' y='" << py(std::pow(10, d)) + 4 << "'>1e" << d
      << "</text>\n";
  s << "<text x='" << (L + W - R) / 2 - 60 << "' y='" << H - 12 << "'>" << escaped(plot.x_label)
    << "</text>\n"
    << "<text x='14' y='" << T - 8 << "'>" << escaped(plot.y_label) << "</text>\n";

  int legend = 0;
  for (const PlotSeries& series : plot.series) {
    if (series.joined) {
      s << "<polyline fill='none' stroke='" << series.colour << "'"
        << (series.dashed ? " stroke-dasharray='4 3'" : "") << " points='";
      for (const PlotMarker& m : series.markers)
        if (drawable(m)) s << px(m.x) << "," << py(m.y) << " ";
      s << "'/>\n";
    }
    if (series.marker_radius > 0)
      for (const PlotMarker& m : series.markers)
        if (drawable(m))
          s << "<circle cx='" << px(m.x) << "' cy='" << py(m.y) << "' r='" << series.marker_radius
            << "' fill='" << (m.filled ? series.colour : "white") << "' stroke='" << series.colour
            << "'><title>" << escaped(m.tooltip) << "</title></circle>\n";
    if (!series.in_legend) continue;
    const double ly = T + 18 * legend++;
    if (series.marker_radius > 0)
      s << "<circle cx='" << W - R + 18 << "' cy='" << ly << "' r='4' fill='" << series.colour << "'/>";
    else
      s << "<line x1='" << W - R + 8 << "' y1='" << ly << "' x2='" << W - R + 28 << "' y2='" << ly
        << "' stroke='" << series.colour << "'" << (series.dashed ? " stroke-dasharray='4 3'" : "") << "/>";
    s << "<text x='" << W - R + 35 << "' y='" << ly + 4 << "'>" << escaped(series.name) << "</text>\n";
  }
  if (!plot.legend_note.empty())
    s << "<text x='" << W - R + 10 << "' y='" << T + 18 * legend + 4 << "'>" << escaped(plot.legend_note)
      << "</text>\n";
  s << "</svg>\n";
  return s.str();
}

}  // namespace holo::eval
