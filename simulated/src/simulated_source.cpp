#include "holo/simulated/simulated_source.hpp"

#include <cmath>
#include <map>
#include <string>
#include <thread>

#include "holo/capture/camera_power.hpp"
#include "holo/core/error.hpp"
#include "holo/sim/museum.hpp"

namespace holo::simulated {

using capture::cameraPowered;
using capture::GrabResult;
using capture::GrabStatus;

namespace {

// The power switches are the rig's; the check camera has none.
bool powered(int camera) {
  return camera == sim::Museum::kCheckCamera || cameraPowered(camera);
}

}  // namespace

SimulatedSource::SimulatedSource(std::shared_ptr<const sim::Museum> museum, int camera,
                                 SimulationOptions options)
    : museum_(std::move(museum)), camera_(camera), options_(options), next_frame_(options.first_frame) {
  if (!museum_) throw InputError("", "museum", "a simulated museum");
  if (camera_ < 0 || (camera_ >= museum_->cameraCount() && camera_ != sim::Museum::kCheckCamera))
    throw InputError(museum_->description().source, "camera",
                     "0.." + std::to_string(museum_->cameraCount() - 1) + " or the check camera " +
                         std::to_string(sim::Museum::kCheckCamera),
                     std::to_string(camera_));
  if (options_.first_frame < 0) throw InputError(museum_->description().source, "first_frame", ">= 0");
}

std::string SimulatedSource::name() const {
  if (camera_ == sim::Museum::kCheckCamera) return "sim:" + museum_->description().name + "/check";
  return "sim:" + museum_->description().name + "/cam" + std::to_string(camera_);
}

std::string SimulatedSource::serial() const {
  return "SIM-" + museum_->description().name + "-" + std::to_string(camera_);
}

void SimulatedSource::open() {
  if (!powered(camera_)) throw Error(name() + ": switched off (injected fault)");
}

void SimulatedSource::start() {
  next_frame_ = options_.first_frame;
  start_ = Clock::now();
}

GrabResult SimulatedSource::grab(Nanoseconds timeout) {
  if (!powered(camera_)) {
    std::this_thread::sleep_for(timeout);
    return {GrabStatus::Timeout, {}, "switched off (injected fault)"};
  }
  const int index = next_frame_ - options_.first_frame;
  if (options_.frame_count >= 0 && index >= options_.frame_count)
    return {GrabStatus::EndOfStream, {}, "end of simulation"};
  if (options_.paced) {
    const double fps = museum_->description().camera.fps;
    const auto due =
        start_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(index / fps));
    const auto now = Clock::now();
    if (due - now > timeout) {
      std::this_thread::sleep_for(timeout);
      return {GrabStatus::Timeout, {}, "next frame not due yet"};
    }
    std::this_thread::sleep_until(due);
  }
  sim::SimulatedFrame simulated = museum_->renderCamera(camera_, next_frame_, options_.with_visitors);
  GrabResult result;
  result.status = GrabStatus::Ok;
  result.frame = std::move(simulated.frame);
  result.frame.camera_id = camera_;
  result.frame.sequence = static_cast<std::uint64_t>(index);
  // Exact in double (frameTime() is a float, off by nanoseconds).
  result.frame.device_time =
      Nanoseconds(std::llround(next_frame_ * 1e9 / static_cast<double>(museum_->description().camera.fps)));
  result.frame.host_time = Clock::now();
  ++next_frame_;
  return result;
}

std::optional<CameraModel> SimulatedSource::cameraModel() const {
  return museum_->camera(camera_);
}

capture::SourceFactory configuredSources() {
  return [museums = std::map<std::string, std::shared_ptr<const sim::Museum>>()](
             const capture::CameraEntry& entry) mutable -> std::unique_ptr<capture::CameraSource> {
    auto& museum = museums[entry.scene];
    if (!museum) museum = std::make_shared<const sim::Museum>(sim::loadScene(entry.scene));
    return std::make_unique<SimulatedSource>(museum, entry.sim_camera,
                                             SimulationOptions{.paced = entry.paced});
  };
}

}  // namespace holo::simulated
