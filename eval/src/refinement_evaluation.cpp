#include "holo/eval/refinement_evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <opencv2/core.hpp>

#include "holo/core/hdr_io.hpp"
#include "holo/core/image.hpp"
#include "holo/core/stopwatch.hpp"
#include "holo/eval/loglog_plot.hpp"
#include "holo/pipeline/frame_loop.hpp"
#include "holo/reflect/frame_renderer.hpp"
#include "holo/reflect/view.hpp"
#include "holo/relics/relics.hpp"

namespace holo::eval {
namespace {

// A sky over a darker ground with a bright warm window low on one side.
cv::Mat syntheticSky() {
  cv::Mat pano(128, 256, CV_32FC3);
  for (int y = 0; y < pano.rows; ++y)
    for (int x = 0; x < pano.cols; ++x) {
      const float v = (float(y) + 0.5f) / float(pano.rows);
      vec3 rgb = v < 0.5f ? vec3(0.6f, 0.8f, 1.2f) * (1.2f - v) : vec3(0.25f, 0.2f, 0.15f);
      if (v > 0.3f && v < 0.5f && x < pano.cols / 8) rgb = vec3(6.0f, 4.0f, 2.5f);
      pano.at<cv::Vec3f>(y, x) = cv::Vec3f(rgb.z, rgb.y, rgb.x);
    }
  return pano;
}

std::vector<CameraModel> faceViews(const Bounds3& relic, int size, float turn) {
  std::vector<CameraModel> views;
  for (int face = 0; face < 4; ++face) {
    vec3 eye = reflect::defaultFaceEye(face, relic, -1.0f);
    // A moved eye: turned about the relic's axis by `turn` radians.
    const float c = std::cos(turn), s = std::sin(turn);
    eye = vec3(c * eye.x + s * eye.z, eye.y, -s * eye.x + c * eye.z);
    views.push_back(
        reflect::lookAtCamera(eye, relic.center(), reflect::framingFovDeg(eye, relic), size, size));
  }
  return views;
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::nth_element(v.begin(), v.begin() + std::ptrdiff_t(v.size() / 2), v.end());
  return v[v.size() / 2];
}

std::vector<cv::Mat> renderFrame(reflect::FrameRenderer& renderer, const std::vector<CameraModel>& views,
                                 double* ms = nullptr) {
  const Stopwatch clock;
  const reflect::FrameResult r = renderer.render({}, {}, views);
  if (ms) *ms = clock.ms();
  std::vector<cv::Mat> hdr;
  for (const reflect::ViewImages& v : r.views) hdr.push_back(v.hdr);
  return hdr;
}

}  // namespace

int RefinementEvaluation::framesWithin(double seconds) const {
  return refining_ms > 0 ? int(std::floor(seconds * 1000.0 / refining_ms)) : 0;
}

int RefinementEvaluation::firstFrameBelow(double bar) const {
  for (std::size_t n = 0; n < error.size(); ++n)
    if (error[n] <= bar) return int(n) + 1;
  return 0;
}

bool RefinementEvaluation::monotonicUpTo(int last) const {
  for (int n = 1; n < std::min(last, int(error.size())); ++n)
    if (error[std::size_t(n)] > error[std::size_t(n) - 1]) return false;
  return true;
}

RefinementEvaluation evaluateRefinement(const RefinementEvaluationOptions& o) {
  const reflect::RenderScene scene(relics::makeRelic(o.relic), {});
  const reflect::Environment environment(o.panorama.empty() ? syntheticSky() : loadHdr(o.panorama).pixels);
  const reflect::PrefilteredIbl ibl(environment);
  const std::vector<CameraModel> views = faceViews(scene.relicBounds(), o.view_size, 0.0f);
  RefinementEvaluation e;
  reflect::TracerSettings base;
  if (o.live_loop) {
    base = pipeline::liveTracerSettings();
    base.relic_interreflection = true;
  }
  base.evaluation.axis_aligned_filter = o.axis_aligned_filter;

  reflect::TracerSettings converging = base;
  converging.refinement_sets = o.converged_sets;
  std::vector<cv::Mat> converged;
  {
    reflect::FrameRenderer renderer(scene, ibl, converging);
    for (int f = 0; f < o.converged_sets; ++f) converged = renderFrame(renderer, views);
  }
  reflect::TracerSettings flat = base;
  flat.relic_interreflection = false;
  reflect::FrameRenderer flat_renderer(scene, ibl, flat);
  const std::vector<cv::Mat> without = renderFrame(flat_renderer, views);
  // The region: pixels where the interreflection changes the converged luminance.
  std::vector<cv::Mat> region;
  double light_sq = 0;
  for (std::size_t v = 0; v < views.size(); ++v) {
    cv::Mat mask(o.view_size, o.view_size, CV_8UC1, cv::Scalar(0));
    for (int y = 0; y < mask.rows; ++y)
      for (int x = 0; x < mask.cols; ++x) {
        const double d = luminance(rgbAt(converged[v], x, y)) - luminance(rgbAt(without[v], x, y));
        if (std::abs(d) > 1e-3) {
          mask.at<std::uint8_t>(y, x) = 1;
          light_sq += d * d;
          ++e.region_pixels;
        }
      }
    region.push_back(mask);
  }
  e.interreflected_rms = e.region_pixels ? std::sqrt(light_sq / double(e.region_pixels)) : 0.0;

  reflect::FrameRenderer renderer(scene, ibl, base);
  e.plan = renderer.plan({}, {}).describe();
  for (int f = 0; f < o.frames; ++f) {
    double ms = 0;
    const std::vector<cv::Mat> hdr = renderFrame(renderer, views, &ms);
    double sq = 0;
    for (std::size_t v = 0; v < views.size(); ++v)
      for (int y = 0; y < o.view_size; ++y)
        for (int x = 0; x < o.view_size; ++x)
          if (region[v].at<std::uint8_t>(y, x)) {
            const double d = luminance(rgbAt(hdr[v], x, y)) - luminance(rgbAt(converged[v], x, y));
            sq += d * d;
          }
    e.error.push_back(e.region_pixels && e.interreflected_rms > 0
                          ? std::sqrt(sq / double(e.region_pixels)) / e.interreflected_rms
                          : 0.0);
    e.frame_ms.push_back(ms);
  }

  // The budget, the three frames in turn (the same minutes): a refining still frame (a renderer
  // that refines without end), every eye moved (two poses 1 cm apart in turn) and the still frame
  // without refinement.
  std::vector<double> refining, moved, reused;
  const std::vector<CameraModel> other = faceViews(scene.relicBounds(), o.view_size, 0.01f);
  reflect::TracerSettings endless = base, off = base;
  endless.refinement_sets = 4096;
  off.refinement_sets = 1;
  reflect::FrameRenderer refiner(scene, ibl, endless), still(scene, ibl, off);
  renderFrame(refiner, views);
  renderFrame(still, views);
  for (int f = 0; f < o.timing_frames; ++f) {
    double ms = 0;
    renderFrame(refiner, views, &ms);
    refining.push_back(ms);
    renderFrame(renderer, f % 2 ? views : other, &ms);
    moved.push_back(ms);
    renderFrame(still, views, &ms);
    reused.push_back(ms);
  }
  e.refining_ms = median(refining);
  e.moved_ms = median(moved);
  e.reused_ms = median(reused);
  return e;
}

std::string refinementPlotSvg(const RefinementEvaluation& e, const std::string& title) {
  LogLogPlot plot;
  plot.title = title;
  plot.x_label = "frames still (1: sample set 0 alone)";
  plot.y_label = "error against the converged image / interreflected light";
  PlotSeries curve{"progressive refinement", "#1f77b4", {}, true};
  for (std::size_t n = 0; n < e.error.size(); ++n) {
    char tip[96];
    std::snprintf(tip, sizeof tip, "frame %zu: %.4f, %.1f ms", n + 1, e.error[n], e.frame_ms[n]);
    curve.markers.push_back({double(n + 1), e.error[n], tip});
  }
  curve.marker_radius = 2.0;
  PlotSeries bar{"10% bar", "#d62728", {}, true, true, 0.0};
  bar.markers = {{1.0, 0.1, ""}, {double(std::max<std::size_t>(e.error.size(), 2)), 0.1, ""}};
  plot.series = {curve, bar};
  const int two_seconds = e.framesWithin(2.0);
  if (two_seconds >= 1 && two_seconds <= int(e.error.size())) {
    PlotSeries mark{"2 s of frames", "#2ca02c", {}, false};
    char tip[96];
    std::snprintf(tip, sizeof tip, "frame %d (%.1f ms a frame): %.4f", two_seconds, e.refining_ms,
                  e.error[std::size_t(two_seconds) - 1]);
    mark.markers = {{double(two_seconds), e.error[std::size_t(two_seconds) - 1], tip}};
    mark.marker_radius = 6.0;
    plot.series.push_back(mark);
  }
  return svgOf(plot);
}

}  // namespace holo::eval
