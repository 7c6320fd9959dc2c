// The SVG of the (time, error) plots: what can sit on a log axis is drawn, in the right place,
// the rest is left out; text cannot break the markup.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <regex>
#include <string>

#include "holo/eval/loglog_plot.hpp"

namespace {

using holo::eval::LogLogPlot;
using holo::eval::PlotSeries;

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

double attribute(const std::string& element, const std::string& name) {
  std::smatch m;
  EXPECT_TRUE(std::regex_search(element, m, std::regex(name + "='([-0-9.e]+)'"))) << element;
  return std::stod(m[1]);
}

TEST(LogLogPlot, DrawsOnlyPositiveFinitePointsWithinTheDecades) {
  LogLogPlot plot{"error <vs> time", "ms", "MSE", "hollow: not reached", 680, 440, {}};
  PlotSeries series{"ours & co", "#000000", {}, false, false, 4, true};
  series.markers = {{2.0, 0.05, "fast", true},
                    {300.0, 0.0004, "slow", false},
                    {0.0, 0.01, "zero time", true},
                    {5.0, -1.0, "negative error", true},
                    {std::numeric_limits<double>::quiet_NaN(), 0.01, "nan", true},
                    {std::numeric_limits<double>::infinity(), 0.01, "inf", true}};
  plot.series.push_back(series);
  const std::string svg = holo::eval::svgOf(plot);

  EXPECT_EQ(count(svg, "<title>"), 2) << svg;
  EXPECT_NE(svg.find("<title>fast</title>"), std::string::npos);
  EXPECT_EQ(svg.find("nan"), std::string::npos) << svg;
  EXPECT_EQ(svg.find("inf"), std::string::npos) << svg;
  // Decades 1e0..1e3 in time and 1e-4..1e-1 in error hold both points.
  for (const std::string label : {">1e0<", ">1e3<", ">1e-4<", ">1e-1<"})
    EXPECT_NE(svg.find(label), std::string::npos) << label << "\n" << svg;
  EXPECT_EQ(svg.find(">1e4<"), std::string::npos);
  // The slower point is to the right and lower; the not-reached one is hollow.
  std::smatch fast, slow;
  ASSERT_TRUE(std::regex_search(svg, fast, std::regex("<circle[^>]*><title>fast")));
  ASSERT_TRUE(std::regex_search(svg, slow, std::regex("<circle[^>]*><title>slow")));
  EXPECT_GT(attribute(slow.str(), "cx"), attribute(fast.str(), "cx"));
  EXPECT_GT(attribute(slow.str(), "cy"), attribute(fast.str(), "cy"));  // SVG y grows downwards
  EXPECT_NE(slow.str().find("fill='white'"), std::string::npos);
  EXPECT_NE(fast.str().find("fill='#000000'"), std::string::npos);
  // Markup in text is escaped.
  EXPECT_NE(svg.find("error &lt;vs&gt; time"), std::string::npos);
  EXPECT_NE(svg.find("ours &amp; co"), std::string::npos);
}

TEST(LogLogPlot, JoinsSeriesAndKeepsTheLegendToTheSeriesThatAskForIt) {
  LogLogPlot plot{"t", "ms", "MSE", "", 640, 420, {}};
  plot.series.push_back({"front", "#888", {{1, 0.1, "", true}, {10, 0.01, "", true}}, true, true, 0, false});
  plot.series.push_back({"ibl", "#d62728", {{3, 0.02, "ibl", true}}, false, false, 3, true});
  const std::string svg = holo::eval::svgOf(plot);
  EXPECT_EQ(count(svg, "<polyline"), 1);
  EXPECT_NE(svg.find("stroke-dasharray"), std::string::npos);
  EXPECT_EQ(count(svg, "<title>"), 1);  // the front has no markers
  EXPECT_NE(svg.find(">ibl</text>"), std::string::npos);
  EXPECT_EQ(svg.find(">front</text>"), std::string::npos);
}

TEST(LogLogPlot, AnEmptyPlotIsStillAPicture) {
  const std::string svg = holo::eval::svgOf(LogLogPlot{"nothing yet", "ms", "MSE", "", 640, 420, {}});
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_EQ(svg.find("nan"), std::string::npos);
}

}  // namespace
