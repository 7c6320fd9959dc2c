// The live frame loop's timing report (pipeline/frame_report.hpp): the medians of a run's frame
// reports, the Table 3 style text table `holopyramid run` and `bench frame` print, and its JSON
// form (`--json`, timing.json).
//
// Units: milliseconds, frames per second.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "holo/pipeline/frame_report.hpp"

namespace holo::eval {

// Median of each stage over the reports (0 for none).
pipeline::StageTimes medianTimes(const std::vector<pipeline::FrameReport>& reports);
// Median milliseconds per reflect::Pass over the reports, by pass name in the enum's order, then
// "CameraImages".
std::vector<std::pair<std::string, double>> medianPasses(const std::vector<pipeline::FrameReport>& reports);

// The text table of the medians (with the run's non-finite pixels and camera frames). With
// simulated cameras, their rendering (the acquisition wait) is shown apart from the appliance's
// own stages, whose sum gives the pipeline's own frame rate without overlap (a lower bound: the
// stages still share the cores with the simulation); `holopyramid bench frame` measures it with
// the cameras simulated before timing.
std::string formatTimingTable(const pipeline::StageTimes& median,
                              const std::vector<pipeline::FrameReport>& reports,
                              const pipeline::CameraFrameCounts& cameras);
// The same as a JSON document (2-space indent): the medians, frame rates, camera frames and every
// frame's stages, counters and pass times.
std::string timingJson(const pipeline::StageTimes& median, const std::vector<pipeline::FrameReport>& reports,
                       const pipeline::CameraFrameCounts& cameras);

}  // namespace holo::eval
