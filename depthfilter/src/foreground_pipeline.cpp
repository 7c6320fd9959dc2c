#include "holo/depthfilter/foreground_pipeline.hpp"

#include <tbb/parallel_for.h>
#include <array>
#include <chrono>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "holo/core/error.hpp"
#include "holo/core/image.hpp"
#include "holo/core/stats.hpp"
#include "holo/depthfilter/full_size_outline.hpp"
#include "holo/depthfilter/reused_zero_image.hpp"

namespace holo::depthfilter {

struct ForegroundPipeline::CameraStage {
  ForegroundMasker masker;
  PrecursorFlow flow;
  MaskPersistence persistence;
  TemporalDepthFilter filter;
  ReusedZeroImage border_weight, border_depth;  // the border layer's images
  // With full_size_outline: the mask, depth and border layer at the camera's resolution.
  ReusedZeroImage camera_mask, camera_depth, camera_border_weight, camera_border_depth;
  std::vector<vec3> plane_directions;         // z = 1 ray per pixel, row-major
  std::vector<vec3> camera_plane_directions;  // the same at the camera's resolution (full_size_outline)
  CameraForeground result;
  std::vector<ForegroundPoint> points;
};

namespace {

std::array<float, 256> srgbTable() {
  std::array<float, 256> table{};
  for (int i = 0; i < 256; ++i) table[std::size_t(i)] = srgbToLinear(float(i) / 255.0f);
  return table;
}

// Back-projects the filtered depth and the border layer. Both are 0 outside `box` (the filter
// outputs only on the mask; see borderBox), so only the box is read.
void appendPoints(const CameraModel& camera, std::uint16_t camera_index, const std::vector<vec3>& directions,
                  const cv::Mat& colour, const CameraForeground& result, const cv::Rect& box,
                  vec3 gains_over_exposure, int scale, std::vector<ForegroundPoint>& out) {
  static const std::array<float, 256> kLinear = srgbTable();
  const mat4& T = camera.T_world_camera();
  for (int y = box.y; y < box.y + box.height; ++y) {
    const float* depth = result.depth.ptr<float>(y);
    const float* border_weight = result.border.weight.ptr<float>(y);
    const float* border_depth = result.border.depth.ptr<float>(y);
    const cv::Vec3b* bgr = colour.ptr<cv::Vec3b>(y);
    for (int x = box.x; x < box.x + box.width; ++x) {
      float d = depth[x], w = 1.0f;
      if (!(d > 0.0f)) {
        d = border_depth[x];
        w = border_weight[x];
        if (!(d > 0.0f) || !(w > 0.0f)) continue;
      }
      ForegroundPoint p;
      p.position =
          transformPoint(T, directions[std::size_t(y) * std::size_t(result.depth.cols) + std::size_t(x)] * d);
      p.radiance = vec3(kLinear[bgr[x][2]], kLinear[bgr[x][1]], kLinear[bgr[x][0]]) * gains_over_exposure;
      p.weight = std::min(w, 1.0f);
      p.camera = camera_index;
      p.x = static_cast<std::uint16_t>(x * scale);
      p.y = static_cast<std::uint16_t>(y * scale);
      if (!isFinite(p.position) || !isFinite(p.radiance)) continue;
      out.push_back(p);
    }
  }
}

// Camera i's colour gains (1 when not given) over the exposure: one multiply per point.
vec3 gainsOverExposure(const ForegroundPipelineConfig& config, std::size_t camera) {
  const vec3 gains = camera < config.colour_gains.size() ? config.colour_gains[camera] : vec3(1.0f);
  return gains / config.exposure;
}

// `camera` is the reduced one: the frame must have its size times the scale.
void checkFrame(const RgbdFrame& frame, const CameraModel& camera, int scale, std::size_t index) {
  const std::string which = "ForegroundPipeline: camera " + std::to_string(index);
  if (frame.colour.type() != CV_8UC3 || frame.depth.type() != CV_32FC1)
    throw Error(which + ": expected CV_8UC3 colour and CV_32FC1 depth");
  const int width = camera.width() * scale, height = camera.height() * scale;
  if (frame.colour.cols != width || frame.colour.rows != height || frame.depth.size() != frame.colour.size())
    throw Error(which + ": expected " + std::to_string(width) + "x" + std::to_string(height) +
                " frames, got colour " + std::to_string(frame.colour.cols) + "x" +
                std::to_string(frame.colour.rows) + " and depth " + std::to_string(frame.depth.cols) + "x" +
                std::to_string(frame.depth.rows));
}

// `reduced` at `scale` times its size, each pixel of `box` repeated over its block, 0 elsewhere
// (the border layer is 0 outside borderBox).
cv::Mat expandedOnBox(const cv::Mat& reduced, const cv::Rect& box, int scale, ReusedZeroImage& image) {
  cv::Mat out = image.next(reduced.size() * scale, reduced.type());
  if (box.empty()) return out;
  const cv::Rect full_box(box.x * scale, box.y * scale, box.width * scale, box.height * scale);
  image.written(full_box);
  cv::Mat out_box = out(full_box);
  cv::resize(reduced(box), out_box, full_box.size(), 0.0, 0.0, cv::INTER_NEAREST);
  return out;
}

std::vector<CameraModel> reducedCameras(std::vector<CameraModel> cameras, int scale) {
  if (cameras.empty()) throw Error("ForegroundPipeline: expected at least one camera");
  for (CameraModel& camera : cameras) {
    checkForegroundScale(scale, camera.width(), camera.height());
    camera = reducedCamera(camera, scale);
  }
  return cameras;
}

}  // namespace

ForegroundPipeline::ForegroundPipeline(std::vector<CameraModel> cameras, ForegroundPipelineConfig config)
    : config_(std::move(config)),
      cameras_(reducedCameras(cameras, config_.scale)),
      camera_resolution_cameras_(std::move(cameras)),
      cross_camera_(cameras_, config_.cross_camera),
      witnesses_(cameras_, config_.cross_camera.tolerance_m, config_.cross_camera.tolerance_z2) {
  if (!(config_.exposure > 0.0f) || !std::isfinite(config_.exposure))
    throw Error("ForegroundPipeline: exposure must be positive and finite");
  for (const vec3& gains : config_.colour_gains)
    if (!(gains.r > 0.0f && gains.g > 0.0f && gains.b > 0.0f) || !isFinite(gains))
      throw Error("ForegroundPipeline: colour gains must be positive and finite");
  const bool outline_at_camera_resolution = config_.full_size_outline && config_.scale > 1;
  stages_.reserve(cameras_.size());
  for (std::size_t i = 0; i < cameras_.size(); ++i) {
    ForegroundMaskConfig mask_config = config_.mask;
    if (i < config_.static_foreground.size() && !config_.static_foreground[i].empty()) {
      // A reduced pixel is the pyramid's when any pixel of its block is.
      const cv::Mat& full = config_.static_foreground[i];
      if (config_.scale == 1) {
        mask_config.static_foreground = full;
      } else {
        cv::Mat block_share;
        cv::resize(full, block_share, cv::Size(cameras_[i].width(), cameras_[i].height()), 0.0, 0.0,
                   cv::INTER_AREA);
        mask_config.static_foreground = block_share > 0;
      }
    }
    stages_.push_back(CameraStage{ForegroundMasker(mask_config),
                                  PrecursorFlow(config_.flow),
                                  MaskPersistence(config_.persistence),
                                  TemporalDepthFilter(config_.filter),
                                  {},
                                  {},
                                  {},
                                  {},
                                  {},
                                  {},
                                  cameras_[i].planeDirectionTable(),
                                  outline_at_camera_resolution
                                      ? camera_resolution_cameras_[i].planeDirectionTable()
                                      : std::vector<vec3>{},
                                  {},
                                  {}});
  }
}

ForegroundPipeline::~ForegroundPipeline() = default;
ForegroundPipeline::ForegroundPipeline(ForegroundPipeline&&) noexcept = default;
ForegroundPipeline& ForegroundPipeline::operator=(ForegroundPipeline&&) noexcept = default;

std::size_t ForegroundPipeline::cameraCount() const {
  return cameras_.size();
}
const CameraForeground& ForegroundPipeline::lastResult(std::size_t camera) const {
  return stages_.at(camera).result;
}
const TemporalDepthFilter& ForegroundPipeline::filter(std::size_t camera) const {
  return stages_.at(camera).filter;
}

void ForegroundPipeline::learnBackground(std::span<const RgbdFrame> frames) {
  if (frames.size() != cameras_.size())
    throw Error("ForegroundPipeline::learnBackground: expected " + std::to_string(cameras_.size()) +
                " frames, got " + std::to_string(frames.size()));
  for (std::size_t i = 0; i < frames.size(); ++i) {
    if (frames[i].empty()) continue;
    checkFrame(frames[i], cameras_[i], config_.scale, i);
    stages_[i].masker.learnBackground(reducedFrame(frames[i], config_.scale));
  }
}

void ForegroundPipeline::forgetBackground() {
  for (CameraStage& stage : stages_) {
    stage.masker = ForegroundMasker(stage.masker.config());
    stage.filter.resetHistory();
    stage.persistence.reset();
    stage.flow.reset();
    stage.result = {};
  }
}

ForegroundCloud ForegroundPipeline::process(std::span<const RgbdFrame> camera_frames) {
  if (camera_frames.size() != cameras_.size())
    throw Error("ForegroundPipeline::process: expected " + std::to_string(cameras_.size()) + " frames, got " +
                std::to_string(camera_frames.size()));
  for (std::size_t i = 0; i < camera_frames.size(); ++i)
    if (!camera_frames[i].empty()) checkFrame(camera_frames[i], cameras_[i], config_.scale, i);
  // The frames at the foreground's resolution (the camera's own at scale 1, not copied).
  std::vector<RgbdFrame> reduced;
  if (config_.scale > 1) {
    reduced.resize(camera_frames.size());
    const auto reduce = [&](std::size_t i) { reduced[i] = reducedFrame(camera_frames[i], config_.scale); };
    if (config_.parallel)
      tbb::parallel_for(std::size_t(0), reduced.size(), reduce);
    else
      for (std::size_t i = 0; i < reduced.size(); ++i) reduce(i);
  }
  const std::span<const RgbdFrame> frames =
      config_.scale > 1 ? std::span<const RgbdFrame>(reduced) : camera_frames;

  // Per camera: the mask and the flow.
  auto mask_camera = [&](std::size_t i) {
    CameraStage& stage = stages_[i];
    const RgbdFrame& frame = frames[i];
    stage.points.clear();
    if (frame.empty()) {
      stage.result = {};
      stage.flow.reset();
      stage.persistence.reset();
      stage.filter.resetHistory();
      stats::add("Depthfilter/Missing camera frames");
      return;
    }
    CameraForeground& result = stage.result;
    result.present = true;
    result.mask = stage.masker.apply(frame);
    // From the frame before, kept by the flow; needed only where the persistence may add to the
    // mask and on the mask's box, the only pixels where the persistence and the filter read it.
    const cv::Rect flow_needed =
        cv::boundingRect(result.mask) | stage.persistence.searchBox(frame.colour.size());
    result.flow.release();  // unshared, the flow's buffer is reused instead of cleared whole
    result.flow = stage.flow.next(frame.colour, flow_needed);
    stage.persistence.extend(result.mask, frame, result.flow);
  };
  // Per camera: the filter on the depth the other cameras completed, the border, the points.
  std::vector<cv::Mat> depth;
  std::vector<CrossCameraView> views(stages_.size());
  auto filter_camera = [&](std::size_t i) {
    CameraStage& stage = stages_[i];
    const RgbdFrame& frame = frames[i];
    if (frame.empty()) return;
    CameraForeground& result = stage.result;
    result.depth.release();  // likewise the filter's output
    const OtherCameraWitness witness = witnesses_.witnessFor(views, i);
    result.depth = stage.filter.apply({frame.colour, depth[i], result.mask, result.flow, &witness});
    result.border = {};  // unshared, its images are reused too
    result.border =
        expandBorder(result.mask, result.depth, config_.border, stage.border_weight, stage.border_depth);
    const cv::Rect box = borderBox(result.mask, config_.border);
    if (stage.camera_plane_directions.empty()) {
      appendPoints(cameras_[i], static_cast<std::uint16_t>(i), stage.plane_directions, frame.colour, result,
                   box, gainsOverExposure(config_, i), config_.scale, stage.points);
      return;
    }
    const RgbdFrame& camera_frame = camera_frames[i];
    const int s = config_.scale;
    const CameraForeground reduced_result = result;
    FullSizeForeground full =
        fullSizeOutline(result.mask, result.depth, stage.masker.backgroundDepth(), camera_frame.depth, s,
                        {stage.masker.config().depth_margin_m, stage.masker.config().depth_margin_z2},
                        stage.camera_mask, stage.camera_depth);
    result.mask = std::move(full.mask);
    result.depth = std::move(full.depth);
    result.border = {expandedOnBox(result.border.weight, box, s, stage.camera_border_weight),
                     expandedOnBox(result.border.depth, box, s, stage.camera_border_depth)};
    // Points at the resolution each block needs: a repeated block's pixels all carry its one
    // depth, so its reduced point stands for them; a redrawn block's pixels each their own.
    const vec3 gains = gainsOverExposure(config_, i);
    for (int by = box.y; by < box.y + box.height; ++by) {
      const std::uint8_t* redrawn = full.redrawn.ptr<std::uint8_t>(by);
      for (int bx = box.x; bx < box.x + box.width;) {
        int end = bx;
        while (end < box.x + box.width && (redrawn[end] != 0) == (redrawn[bx] != 0)) ++end;
        if (redrawn[bx] == 0)
          appendPoints(cameras_[i], static_cast<std::uint16_t>(i), stage.plane_directions, frame.colour,
                       reduced_result, cv::Rect(bx, by, end - bx, 1), gains, s, stage.points);
        else
          appendPoints(camera_resolution_cameras_[i], static_cast<std::uint16_t>(i),
                       stage.camera_plane_directions, camera_frame.colour, result,
                       cv::Rect(bx * s, by * s, (end - bx) * s, s), gains, 1, stage.points);
        bx = end;
      }
    }
  };
  const auto for_each_camera = [&](const auto& step) {
    if (config_.parallel)
      tbb::parallel_for(std::size_t(0), stages_.size(), step);
    else
      for (std::size_t i = 0; i < stages_.size(); ++i) step(i);
  };
  for_each_camera(mask_camera);
  for (std::size_t i = 0; i < stages_.size(); ++i)
    views[i] = frames[i].empty() ? CrossCameraView{}
                                 : CrossCameraView{frames[i].depth, stages_[i].result.mask,
                                                   stages_[i].masker.backgroundDepth()};
  std::vector<CrossCameraCounts> counts;
  depth = cross_camera_.apply(views, &counts);
  for (const CrossCameraCounts& c : counts) {
    if (c.filled > 0) stats::add("Depthfilter/Cross-camera filled pixels", std::int64_t(c.filled));
    if (c.confirmed > 0) stats::add("Depthfilter/Cross-camera confirmed pixels", std::int64_t(c.confirmed));
  }
  for_each_camera(filter_camera);

  ForegroundCloud cloud;
  std::size_t total = 0;
  for (const CameraStage& stage : stages_) total += stage.points.size();
  cloud.points.reserve(total);
  for (const CameraStage& stage : stages_)
    cloud.points.insert(cloud.points.end(), stage.points.begin(), stage.points.end());
  for (const RgbdFrame& frame : frames) {
    if (frame.empty()) continue;
    cloud.sequence = static_cast<std::int64_t>(frame.sequence);
    cloud.time_s = std::chrono::duration<double>(frame.host_time.time_since_epoch()).count();
    break;
  }
  return cloud;
}

}  // namespace holo::depthfilter
