#include "holo/ar/live_composite.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <limits>
#include <opencv2/imgproc.hpp>

#include "holo/ar/albedo_estimate.hpp"
#include "holo/core/error.hpp"
#include "holo/core/image.hpp"

namespace holo::ar {

cv::Mat blurredLuma(const cv::Mat& colour, const StillnessSettings& settings) {
  cv::Mat grey, luma;
  cv::cvtColor(colour, grey, cv::COLOR_BGR2GRAY);
  grey.convertTo(luma, CV_32F);
  if (settings.blur_radius > 0) {
    const int side = 2 * settings.blur_radius + 1;
    cv::blur(luma, luma, cv::Size(side, side), cv::Point(-1, -1), cv::BORDER_REPLICATE);
  }
  return luma;
}

double changedShare(const cv::Mat& reference_luma, const cv::Mat& reference_depth, const cv::Mat& luma,
                    const cv::Mat& depth, const StillnessSettings& settings) {
  if (reference_luma.size() != luma.size() || reference_depth.size() != depth.size()) return 1.0;
  std::int64_t changed = 0;
  for (int y = 0; y < luma.rows; ++y) {
    const float* a = reference_luma.ptr<float>(y);
    const float* b = luma.ptr<float>(y);
    const float* da = reference_depth.ptr<float>(y);
    const float* db = depth.ptr<float>(y);
    for (int x = 0; x < luma.cols; ++x) {
      const bool colour = std::abs(a[x] - b[x]) > settings.colour_codes;
      const bool shape =
          da[x] > 0.0f && db[x] > 0.0f && std::abs(da[x] - db[x]) > settings.depth_ratio * da[x];
      changed += (colour || shape) ? 1 : 0;
    }
  }
  return static_cast<double>(changed) / static_cast<double>(luma.total());
}

LiveComposite::LiveComposite(int index, CameraModel camera, const cv::Mat& panorama, const Model& relic,
                             LiveCompositeSettings settings)
    : index_(index),
      camera_(std::move(camera)),
      settings_(std::move(settings)),
      relic_(relic),
      environment_(std::make_unique<reflect::Environment>(panorama, settings_.view.panorama_yaw_rad)),
      irradiance_(std::make_unique<reflect::IrradianceSH>(*environment_)) {
  const StillnessSettings& s = settings_.still;
  if (s.blur_radius < 0) throw InputError("AR live view", "blur_radius", "a radius >= 0 pixels");
  if (!(s.colour_codes > 0.0f)) throw InputError("AR live view", "colour_codes", "a threshold > 0 codes");
  if (!(s.depth_ratio > 0.0f)) throw InputError("AR live view", "depth_ratio", "a ratio > 0");
  if (!(s.changed_fraction >= 0.0 && s.changed_fraction < 1.0))
    throw InputError("AR live view", "changed_fraction", "a share in [0, 1)");
  if (settings_.view.composite.spp < 1)
    throw InputError("AR live view", "spp", "at least 1 sample per frame");
  if (settings_.max_samples < settings_.view.composite.spp)
    throw InputError("AR live view", "max_samples", "at least the samples of one frame");
}

LiveComposite::~LiveComposite() = default;

void LiveComposite::setRelic(const Model& relic) {
  relic_ = relic;
  relic_changed_ = true;
}

void LiveComposite::restart(const RgbdFrame& frame) {
  const float exposure = settings_.view.exposure > 0.0f ? settings_.view.exposure : 1.0f;
  scene_.reset();
  background_ = srgb8ToLinear(frame.colour) * (1.0f / exposure);
  DepthSurface surface =
      depthSurface(frame.depth, camera_, settings_.view.surface, "camera " + std::to_string(index_));
  RealSurface real;
  real.albedo = estimateAlbedo(surface, background_, *irradiance_);
  real.mesh = std::move(surface.mesh);
  surface_pixels_ = std::move(surface.pixels);
  if (relic_changed_ || !relic_geometry_) {
    relic_geometry_ = std::make_shared<const RelicGeometry>(relic_);
    caustic_ = traceRelicCaustic(relic_, *environment_, settings_.view.caustic);
  }
  scene_ = std::make_unique<LocalScene>(std::move(real), relic_geometry_, *environment_);
  ++surfaces_built_;
  region_ = compositeRegion(*scene_, camera_, background_, settings_.view, caustic_ ? &*caustic_ : nullptr);
  reference_depth_ = frame.depth.clone();
  reference_colour_ = frame.colour.clone();
  sum_ = cv::Mat(background_.size(), CV_32FC3, cv::Scalar::all(0));
  coverage_sum_ = cv::Mat(background_.size(), CV_32FC1, cv::Scalar(0));
  samples_ = 0;
  relic_changed_ = false;
}

cv::Rect LiveComposite::changeBox() const {
  const cv::Rect image(0, 0, background_.cols, background_.rows);
  if (region_.empty()) return image;
  const cv::Rect bounds = cv::boundingRect(region_);
  if (bounds.empty()) return bounds;
  const int margin = 2 * std::max(settings_.view.filter.radius, 0);
  return cv::Rect(bounds.x - margin, bounds.y - margin, bounds.width + 2 * margin,
                  bounds.height + 2 * margin) &
         image;
}

void LiveComposite::recolour(const RgbdFrame& frame) {
  const float exposure = settings_.view.exposure > 0.0f ? settings_.view.exposure : 1.0f;
  background_ = srgb8ToLinear(frame.colour) * (1.0f / exposure);
  const DepthSurface surface{scene_->real().mesh, surface_pixels_};
  scene_->setRealAlbedo(estimateAlbedo(surface, background_, *irradiance_));
  region_ = compositeRegion(*scene_, camera_, background_, settings_.view, caustic_ ? &*caustic_ : nullptr);
  reference_colour_ = frame.colour.clone();
  sum_.setTo(cv::Scalar::all(0));
  coverage_sum_.setTo(cv::Scalar(0));
  samples_ = 0;
}

LiveCompositeFrame LiveComposite::add(const RgbdFrame& frame) {
  const auto start = std::chrono::steady_clock::now();
  const std::clock_t cpu_start = std::clock();
  requireArCameraInputs(index_, camera_, frame);
  LiveCompositeFrame out;
  const cv::Mat luma = blurredLuma(frame.colour, settings_.still);
  out.changed =
      scene_ ? changedShare(reference_luma_, reference_depth_, luma, frame.depth, settings_.still) : 1.0;
  if (!scene_ || relic_changed_ || out.changed > settings_.still.changed_fraction) {
    // Only the colour changed (the depth still): the depth surface and its ray scene are kept.
    StillnessSettings depth_only = settings_.still;
    depth_only.colour_codes = std::numeric_limits<float>::infinity();
    if (scene_ && !relic_changed_ &&
        changedShare(reference_luma_, reference_depth_, luma, frame.depth, depth_only) <=
            settings_.still.changed_fraction)
      recolour(frame);
    else
      restart(frame);
    reference_luma_ = luma;
    out.reset = true;
  }
  const int spp = settings_.view.composite.spp;
  if (samples_ + spp <= settings_.max_samples) {
    CompositeSettings pass = settings_.view.composite;
    pass.first_sample = samples_;
    const CompositeImage image = renderComposite(*scene_, camera_, background_, pass, region_,
                                                 reference_depth_, caustic_ ? &*caustic_ : nullptr);
    cv::scaleAdd(image.radiance, static_cast<double>(spp), sum_, sum_);
    cv::scaleAdd(image.relic_coverage, static_cast<double>(spp), coverage_sum_, coverage_sum_);
    samples_ += spp;
    out.rays = image.rays;
  }
  // Outside the change region's box, widened by two filter radii (a filtered pixel's whole window
  // inside), the composite is the background and the image the camera's colour: only the box is
  // averaged, filtered and encoded.
  const cv::Rect box = changeBox();
  const double scale = 1.0 / static_cast<double>(samples_);
  out.unfiltered = background_.clone();
  out.radiance = background_.clone();
  out.image = reference_colour_.clone();
  const float exposure = settings_.view.exposure > 0.0f ? settings_.view.exposure : 1.0f;
  if (!box.empty()) {
    cv::Mat unfiltered = sum_(box) * scale;
    // The untraced pixels are the background exactly (a sum's round-off is no change to filter).
    if (!region_.empty()) background_(box).copyTo(unfiltered, region_(box) == 0);
    unfiltered.copyTo(out.unfiltered(box));
    const cv::Mat coverage = coverage_sum_(box) * scale;
    const cv::Mat radiance =
        filterChange(unfiltered, background_(box), coverage, reference_depth_(box), settings_.view.filter);
    radiance.copyTo(out.radiance(box));
    linearToSrgb8(radiance, exposure).copyTo(out.image(box));
    out.relic_pixels = cv::countNonZero(coverage > 0.0f);
  }
  out.samples = samples_;
  out.traced_pixels = region_.empty() ? static_cast<int>(sum_.total()) : cv::countNonZero(region_);
  out.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  out.cpu_ms = 1000.0 * static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  return out;
}

}  // namespace holo::ar
