#include "holo/calib/calibration_session.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "holo/calib/background.hpp"
#include "holo/calib/colour_gains.hpp"
#include "holo/calib/depth_registration.hpp"
#include "holo/calib/display_alignment.hpp"
#include "holo/calib/edge_alignment.hpp"
#include "holo/calib/extrinsics.hpp"
#include "holo/calib/intrinsics.hpp"
#include "holo/calib/panorama_alignment.hpp"
#include "holo/calib/pose.hpp"
#include "holo/calib/verification_target.hpp"
#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/core/median.hpp"
#include "holo/core/progress.hpp"

namespace holo::calib {

namespace fs = std::filesystem;

namespace {

void addVerdict(StepOutcome& out, std::ostream& log, StepVerdict verdict) {
  log << formatVerdict(verdict) << "\n";
  out.verdicts.push_back(std::move(verdict));
}

void preview(StepOutcome& out, const CalibrationSession::PreviewCallback& on_preview, std::string label,
             cv::Mat picture) {
  if (on_preview) on_preview(static_cast<int>(out.previews.size()), label, picture);
  out.previews.emplace_back(std::move(label), std::move(picture));
}

// The linear HDR panorama as an 8-bit picture (Reinhard, then sRGB-like gamma) for the preview.
cv::Mat panoramaPicture(const cv::Mat& panorama) {
  cv::Mat mapped = panorama / (panorama + cv::Scalar::all(1.0));
  cv::pow(mapped, 1.0 / 2.2, mapped);
  cv::Mat out;
  mapped.convertTo(out, CV_8UC3, 255.0);
  return out;
}

std::string cameraLabel(const CalibrationRig& rig, int c) {
  return "camera " + std::to_string(c) + " (" + rig.serial(c) + ")";
}

}  // namespace

const char* stepTitle(CalibrationStep step) {
  switch (step) {
    case CalibrationStep::Intrinsics:
      return "intrinsics";
    case CalibrationStep::Poses:
      return "camera poses";
    case CalibrationStep::Background:
      return "background";
    case CalibrationStep::Panorama:
      return "panorama yaw";
    case CalibrationStep::Display:
      return "display alignment";
    case CalibrationStep::Verification:
      return "verification";
    case CalibrationStep::Save:
      return "save";
  }
  return "?";
}

const char* stepInstructions(CalibrationStep step) {
  switch (step) {
    case CalibrationStep::Intrinsics:
      return "Camera by camera: hold the small ChArUco board 30-45 cm in front of it, tilt it and move it "
             "into every part of the picture, holding it still for a moment at each place (a view is kept "
             "when the board is steady and unlike the views kept so far; the grid shows the parts of the "
             "picture and the tilts covered). Every camera needs at least 8 views. Take the board away to "
             "go on to the next camera.";
    case CalibrationStep::Poses:
      return "Stand the large ChArUco board on the easel at the marked spot in front of camera 0, then "
             "carry it to the spots of cameras 1, 2 and 3 in turn. Nothing may cover it; leave it standing "
             "still until the camera has taken it (a second or so).";
    case CalibrationStep::Background:
      return "Clear the hall: take the boards away and make sure nobody stands in front of the cameras. "
             "Each camera records several frames of the empty hall; keep the lights as they are during "
             "opening hours.";
    case CalibrationStep::Panorama:
      return "Nothing to do: the hall panorama is turned until it matches what the calibrated cameras see. "
             "If this fails, the panorama was taken in another hall or the furniture has moved.";
    case CalibrationStep::Display:
      return "Each face shows the test pattern. Its 25 dots are found on the monitor and the face's "
             "offset, scale, rotation and mirror are fitted. The arrow must point up and the number read "
             "normally on the pyramid.";
    case CalibrationStep::Verification:
      return "Slot the verification jig onto each side of the base (its arm on the two dowel pins beside the "
             "camera) and keep everyone out of the cameras' view. Each picture shows the jig's printed "
             "squares where the calibration puts them (green) over the edges the camera sees (blue); the "
             "pose error they show must stay under 5 mm and 0.5 degree. Take the jigs off before opening.";
    case CalibrationStep::Save:
      return "Every step passed. Save writes the calibration into the output folder; the previous "
             "calibration is kept as .bak beside each file.";
  }
  return "";
}

bool StepOutcome::passed() const {
  return error.empty() && !verdicts.empty() &&
         std::all_of(verdicts.begin(), verdicts.end(), [](const StepVerdict& v) { return v.pass; });
}

CalibrationSession::CalibrationSession(CalibrationRig& rig, AutoCalibrationConfig config)
    : rig_(rig), config_(std::move(config)) {
  const int cameras = rig_.cameraCount();
  if (static_cast<int>(config_.placements.size()) != cameras)
    throw InputError("calibration configuration", "placements", std::to_string(cameras) + " board placements",
                     std::to_string(config_.placements.size()));
  if (config_.background_frames < 1)
    throw InputError("calibration configuration", "background_frames", "at least 1",
                     std::to_string(config_.background_frames));
  cameras_.resize(static_cast<std::size_t>(cameras));
  for (int c = 0; c < cameras; ++c) cameras_[static_cast<std::size_t>(c)].serial = rig_.serial(c);
}

const std::optional<StepOutcome>& CalibrationSession::outcome(CalibrationStep step) const {
  return outcomes_[static_cast<std::size_t>(step)];
}

const StepOutcome& CalibrationSession::measure(CalibrationStep step, std::ostream& log, bool quiet,
                                               const PreviewCallback& on_preview) {
  const auto index = static_cast<std::size_t>(step);
  HOLO_ASSERT(step != CalibrationStep::Save);
  for (std::size_t earlier = 0; earlier < index; ++earlier) HOLO_ASSERT(outcomes_[earlier].has_value());
  for (std::size_t later = index; later < outcomes_.size(); ++later) outcomes_[later].reset();
  log << "step " << index + 1 << ": " << stepTitle(step) << "\n";
  StepOutcome out;
  try {
    switch (step) {
      case CalibrationStep::Intrinsics:
        out = measureIntrinsics(log, quiet, on_preview);
        break;
      case CalibrationStep::Poses:
        out = measurePoses(log, on_preview);
        break;
      case CalibrationStep::Background:
        out = measureBackground(log, quiet, on_preview);
        break;
      case CalibrationStep::Panorama:
        out = measurePanorama(log, on_preview);
        break;
      case CalibrationStep::Display:
        out = measureDisplay(log, on_preview);
        break;
      case CalibrationStep::Verification:
        out = measureVerification(log, on_preview);
        break;
      case CalibrationStep::Save:
        break;
    }
  } catch (const InputError& e) {
    out.error = e.what();
    out.exception = std::current_exception();
    log << "  could not measure: " << out.error << "\n";
  }
  outcomes_[index] = std::move(out);
  return *outcomes_[index];
}

StepOutcome CalibrationSession::measureIntrinsics(std::ostream& log, bool quiet,
                                                  const PreviewCallback& on_preview) {
  StepOutcome out;
  log << "  board " << config_.intrinsics_board.describe() << " (" << rig_.describe() << ")\n";
  rig_.begin(RigActivity::HandHeldBoard);
  intrinsics_observations_.assign(static_cast<std::size_t>(rig_.cameraCount()), {});
  intrinsics_views_.assign(static_cast<std::size_t>(rig_.cameraCount()), {});
  for (int c = 0; c < rig_.cameraCount(); ++c) {
    IntrinsicsViewSelector selector(config_.intrinsics_board, c, rig_.imageSize(c), rig_.stills());
    int frames = 0, gone = 0;
    bool seen = false;
    {
      ProgressReporter progress(config_.max_frames_per_step, "camera " + std::to_string(c) + " board frames",
                                quiet);
      while (frames < config_.max_frames_per_step) {
        std::optional<RgbdFrame> frame = rig_.nextFrame(c);
        if (!frame) break;
        if (frame->colour.size() != rig_.imageSize(c))
          throw InputError(
              cameraLabel(rig_, c), "frame size",
              std::to_string(rig_.imageSize(c).width) + "x" + std::to_string(rig_.imageSize(c).height),
              std::to_string(frame->colour.cols) + "x" + std::to_string(frame->colour.rows));
        const BoardFrameObservation& obs = selector.add(*frame, "frame " + std::to_string(frames));
        if (obs.kept) intrinsics_views_[static_cast<std::size_t>(c)].push_back({*frame, obs.detection});
        ++frames;
        progress.update();
        if (obs.detection.usable()) {
          seen = true;
          gone = 0;
        } else if (seen && ++gone >= kBoardGoneFrames &&
                   static_cast<int>(selector.keptViews().size()) >= kIntrinsicsMinViews) {
          break;  // the technician took the board away: this camera is done
        }
        if (on_preview && (obs.kept || frames % 10 == 1)) {
          cv::Mat picture = drawDetection(config_.intrinsics_board, frame->colour, obs.detection);
          selector.coverage().draw(picture);
          on_preview(c,
                     cameraLabel(rig_, c) + ", frame " + std::to_string(frames) + ", " +
                         std::to_string(selector.keptViews().size()) + " views kept",
                     picture);
        }
      }
    }
    const CoverageGrid& coverage = selector.coverage();
    log << "  camera " << c << ": " << frames << " frames, board in " << selector.framesWithBoard()
        << ", moving " << selector.framesMoving() << ", repeated views " << selector.framesRepeated()
        << ", kept " << selector.keptViews().size() << "; coverage " << coverage.describe() << "\n";
    std::vector<cv::Mat> drawn = selector.keptPictures();
    std::vector<double> fractions;
    for (const BoardView& view : selector.keptViews())
      fractions.push_back(view.detection.widthFraction(rig_.imageSize(c).width));
    if (!drawn.empty()) {
      cv::Mat coverage_picture = drawn.back().clone();
      coverage.draw(coverage_picture);
      drawn.insert(drawn.begin(), coverage_picture);
    }
    // Roughly square sheets: a sheet more than 3 times wider than high would be shown as a panorama.
    const int n = static_cast<int>(drawn.size());
    const int columns =
        n <= 2 ? 1 : std::min(4, static_cast<int>(std::ceil(std::sqrt(static_cast<double>(n)))));
    const cv::Mat sheet = drawn.empty() ? cv::Mat(rig_.imageSize(c), CV_8UC3, cv::Scalar::all(0))
                                        : detectionContactSheet(drawn, columns);
    out.files.emplace_back("intrinsics_camera" + std::to_string(c) + ".png", sheet);
    out.previews.emplace_back(cameraLabel(rig_, c), sheet);
    intrinsics_observations_[static_cast<std::size_t>(c)] = selector.observations();
    if (static_cast<int>(selector.keptViews().size()) < kMinIntrinsicsViews) {
      // Too few views to compute anything: this camera fails with its hint, the others go on.
      addVerdict(
          out, log,
          judgeIntrinsics("intrinsics camera " + std::to_string(c), std::numeric_limits<double>::quiet_NaN(),
                          static_cast<int>(selector.keptViews().size()), frames, median(fractions)));
      continue;
    }
    CameraCalibration& cal = cameras_[static_cast<std::size_t>(c)];
    const IntrinsicsResult result = calibrateIntrinsics(config_.intrinsics_board, selector.keptViews(),
                                                        rig_.imageSize(c), "camera " + std::to_string(c));
    cal.intrinsics = result.intrinsics;
    cal.rms = result.rms;
    for (BoardFrameObservation& obs : intrinsics_observations_[static_cast<std::size_t>(c)])
      obs.T_camera_board = boardPose(obs.detection, cal.intrinsics);
    log << "  camera " << c << " (" << cal.serial << "): fx " << result.intrinsics.fx << " fy "
        << result.intrinsics.fy << " cx " << result.intrinsics.cx << " cy " << result.intrinsics.cy << "\n";
    log << "    per view RMS (px):";
    for (std::size_t i = 0; i < result.used_views.size(); ++i)
      log << (i % 6 == 0 ? "\n     " : "") << " " << result.used_views[i] << " " << std::setprecision(3)
          << result.view_rms[i];
    log << "\n";
    for (std::size_t i = 0; i < result.outlier_views.size(); ++i)
      log << "    dropped as an outlier: " << result.outlier_views[i] << " (" << result.outlier_rms[i]
          << " px)\n";
    log << std::setprecision(6);
    addVerdict(out, log,
               judgeIntrinsics("intrinsics camera " + std::to_string(c), result.rms,
                               static_cast<int>(result.used_views.size()), frames, median(fractions)));
  }
  measureDepthAndColour(out, log);
  return out;
}

void CalibrationSession::measureDepthAndColour(StepOutcome& out, std::ostream& log) {
  const BoardSpec& board = config_.intrinsics_board;
  std::vector<BoardSquareLevels> levels;
  std::vector<std::size_t> levelled;  // the cameras `levels` belong to
  for (int c = 0; c < rig_.cameraCount(); ++c) {
    const auto i = static_cast<std::size_t>(c);
    CameraCalibration& cal = cameras_[i];
    const std::vector<KeptView>& views = intrinsics_views_[i];
    cal.colour_gains = vec3(1.0f);  // a measurement again starts from none
    cal.depth_scale_fitted = false;
    cal.depth_intrinsics.reset();
    cal.T_colour_depth = mat4(1.0f);
    // Both build on the camera's intrinsics: a camera whose intrinsics failed gets neither.
    const std::string intrinsics_step = "intrinsics camera " + std::to_string(c);
    const bool intrinsics_passed =
        std::any_of(out.verdicts.begin(), out.verdicts.end(),
                    [&](const StepVerdict& v) { return v.step == intrinsics_step && v.pass; });
    if (!intrinsics_passed || views.empty()) continue;
    const std::string label = cameraLabel(rig_, c);

    // Depth: the board's plane from its corners against the plane fitted to its depth pixels.
    std::vector<PlanePair> pairs;
    bool has_depth = false, other_size = false;
    for (const KeptView& view : views) {
      if (view.frame.depth.empty()) continue;
      has_depth = true;
      // A depth image of another size needs the depth device's own intrinsics, which this step
      // does not measure.
      if (view.frame.depth.size() != view.frame.colour.size()) {
        other_size = true;
        continue;
      }
      const std::optional<Plane> colour_plane = boardPlaneInCamera(view.detection, cal.intrinsics);
      const std::optional<cv::Matx44d> pose = boardPoseInCamera(view.detection, cal.intrinsics);
      if (!colour_plane || !pose) continue;
      const std::optional<DepthPlaneFit> fit =
          fitBoardPlaneInDepth(view.frame.depth, cal.intrinsics, board, *pose, cv::Matx44d::eye());
      if (fit) pairs.push_back({*colour_plane, fit->plane});
    }
    if (other_size)
      log << "  camera " << c << ": depth of another size than colour; its registration needs the depth "
          << "device's intrinsics and is left out\n";
    if (has_depth && !other_size) {
      const std::string step = "depth registration camera " + std::to_string(c);
      if (static_cast<int>(pairs.size()) < kDepthRegistrationMinViews) {
        addVerdict(out, log,
                   judgeDepthRegistration(step, std::numeric_limits<double>::quiet_NaN(),
                                          static_cast<int>(pairs.size())));
      } else {
        try {
          const DepthRegistration reg = fitDepthRegistration(pairs, label);
          const double t_mm = 1000.0 * cv::norm(cv::Vec3d(reg.T_colour_depth(0, 3), reg.T_colour_depth(1, 3),
                                                          reg.T_colour_depth(2, 3)));
          const double r_deg = rotationErrorDeg(reg.T_colour_depth, cv::Matx44d::eye());
          const StepVerdict verdict = judgeDepthRegistration(step, reg.rms_distance_mm, reg.views);
          log << "  camera " << c << ": depth scale x" << std::setprecision(5) << reg.scale_factor << " over "
              << reg.views << " views, depth to colour " << std::setprecision(3) << t_mm << " mm, " << r_deg
              << " deg" << std::setprecision(6) << "\n";
          if (verdict.pass) {
            cal.depth_scale = rig_.metresPerDepthUnit(c) * reg.scale_factor;
            cal.depth_scale_fitted = true;
            if (t_mm > kDepthRegistrationIdentityMm || r_deg > kDepthRegistrationIdentityDeg) {
              cal.depth_intrinsics = cal.intrinsics;
              cal.T_colour_depth = toMat4(reg.T_colour_depth);
            } else {
              cal.depth_intrinsics.reset();
              cal.T_colour_depth = mat4(1.0f);
            }
          }
          addVerdict(out, log, verdict);
        } catch (const InputError& e) {
          StepVerdict verdict = judgeDepthRegistration(step, std::numeric_limits<double>::quiet_NaN(),
                                                       static_cast<int>(pairs.size()));
          verdict.hint = e.what();
          addVerdict(out, log, verdict);
        }
      }
    }

    // Colour: the view with the most squares found whose white is not clipped.
    std::vector<std::size_t> order(views.size());
    for (std::size_t v = 0; v < order.size(); ++v) order[v] = v;
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return views[a].detection.image_points.size() > views[b].detection.image_points.size();
    });
    std::string refusal;
    for (const std::size_t v : order) {
      try {
        levels.push_back(measureBoardSquares(board, views[v].frame.colour, views[v].detection, label));
        levelled.push_back(i);
        refusal.clear();
        break;
      } catch (const InputError& e) {
        if (refusal.empty()) refusal = e.what();
      }
    }
    if (!refusal.empty()) {
      StepVerdict verdict = judgeColourGains("colour gains camera " + std::to_string(c), vec3(0.0f));
      verdict.hint = refusal;
      addVerdict(out, log, verdict);
    }
  }
  // Matching needs at least two cameras to match.
  if (levels.size() < 2) return;
  const std::vector<vec3> gains = matchCameraColours(levels);
  for (std::size_t k = 0; k < levelled.size(); ++k) {
    const vec3 g = gains[k];
    const StepVerdict verdict = judgeColourGains("colour gains camera " + std::to_string(levelled[k]), g);
    log << "  camera " << levelled[k] << ": colour gains R " << std::setprecision(4) << g.r << " G " << g.g
        << " B " << g.b << std::setprecision(6) << "\n";
    if (verdict.pass) cameras_[levelled[k]].colour_gains = g;
    addVerdict(out, log, verdict);
  }
}

StepOutcome CalibrationSession::measurePoses(std::ostream& log, const PreviewCallback& on_preview) {
  StepOutcome out;
  const int cameras = rig_.cameraCount();
  log << "  board " << config_.placement_board.describe() << " at the marked spots, in camera order\n";
  rig_.begin(RigActivity::PlacementBoard);
  placement_observations_.assign(static_cast<std::size_t>(cameras), {});
  loop_closures_.clear();
  ExtrinsicsProblem problem;
  for (int c = 0; c < cameras; ++c) {
    problem.cameras.push_back(cameras_[static_cast<std::size_t>(c)].intrinsics);
    problem.placements.push_back({config_.placements[static_cast<std::size_t>(c)], true});
  }
  // Frames in which both the spot's camera and another camera saw the board: (spot, other camera,
  // observation index of each) for the loop closure once the poses are known.
  struct SharedView {
    int spot, other;
    std::size_t spot_obs, other_obs;
  };
  std::vector<SharedView> shared;
  std::vector<double> fractions(static_cast<std::size_t>(cameras), 0.0);
  std::vector<BoardDetection> previous(static_cast<std::size_t>(cameras));
  std::int64_t tick = 0;
  for (int spot = 0; spot < cameras; ++spot) {
    int steady = 0;
    bool taken = false;
    cv::Mat last_picture;
    while (true) {
      if (tick >= config_.max_frames_per_step)
        throw InputError(cameraLabel(rig_, spot), "placement board",
                         "the board seen still at marked spot " + std::to_string(spot) + " within " +
                             std::to_string(config_.max_frames_per_step) + " frames",
                         "not seen: stand it on its spot, uncovered, facing the camera");
      std::vector<RgbdFrame> frames;
      for (int c = 0; c < cameras; ++c) {
        std::optional<RgbdFrame> frame = rig_.nextFrame(c);
        if (!frame)
          throw InputError(cameraLabel(rig_, c), "placement board",
                           "frames until the board was seen still at marked spot " + std::to_string(spot),
                           "the frames ended first (board never seen there?)");
        frames.push_back(std::move(*frame));
      }
      ++tick;
      std::vector<BoardFrameObservation> seen(static_cast<std::size_t>(cameras));
      for (int c = 0; c < cameras; ++c) {
        const auto i = static_cast<std::size_t>(c);
        BoardFrameObservation& obs = seen[i];
        obs.camera = c;
        obs.frame = tick - 1;
        obs.device_time = frames[i].device_time;
        obs.detection = detectBoard(config_.placement_board, frames[i].colour);
        if (obs.detection.usable() && previous[i].usable())
          obs.motion_px = cornerMotion(previous[i], obs.detection);
        obs.steady = obs.detection.usable() &&
                     (rig_.stills() || (obs.motion_px >= 0 && obs.motion_px < kSteadyMotionPx));
        previous[i] = obs.detection;
      }
      const auto s = static_cast<std::size_t>(spot);
      if (taken) {
        if (!seen[s].detection.usable()) break;  // carried away: on to the next spot
        continue;
      }
      if (!seen[s].steady) {
        steady = 0;
        continue;
      }
      ++steady;
      seen[s].kept = true;
      fractions[s] = seen[s].detection.widthFraction(frames[s].colour.cols);
      last_picture = drawDetection(config_.placement_board, frames[s].colour, seen[s].detection);
      problem.observations.push_back({spot, spot, seen[s].detection});
      placement_observations_[s].push_back(seen[s]);
      for (int c = 0; c < cameras; ++c)
        if (c != spot && seen[static_cast<std::size_t>(c)].steady) {
          seen[static_cast<std::size_t>(c)].kept = true;
          placement_observations_[static_cast<std::size_t>(c)].push_back(seen[static_cast<std::size_t>(c)]);
          shared.push_back({spot, c, placement_observations_[s].size() - 1,
                            placement_observations_[static_cast<std::size_t>(c)].size() - 1});
        }
      if (steady >= kPlacementSteadyFrames) {
        taken = true;
        out.files.emplace_back("placement_camera" + std::to_string(spot) + ".png", last_picture);
        preview(out, on_preview, cameraLabel(rig_, spot), last_picture);
        if (spot == cameras - 1) break;  // nothing left to wait for
      }
    }
  }
  const ExtrinsicsResult poses = calibrateExtrinsics(problem, "board placements");
  for (int c = 0; c < cameras; ++c) {
    const auto i = static_cast<std::size_t>(c);
    cameras_[i].T_world_camera = toMat4(poses.T_world_camera[i]);
    for (BoardFrameObservation& obs : placement_observations_[i])
      obs.T_camera_board = boardPose(obs.detection, cameras_[i].intrinsics);
    const auto& p = poses.T_world_camera[i];
    log << "  camera " << c << ": position " << p(0, 3) << " " << p(1, 3) << " " << p(2, 3) << " m\n";
    addVerdict(out, log,
               judgeExtrinsics("pose camera " + std::to_string(c), poses.camera_rms[i],
                               poses.camera_corners[i], fractions[i]));
  }
  // Loop closure: where two cameras saw the board at once.
  for (const SharedView& view : shared) {
    const auto& a = placement_observations_[static_cast<std::size_t>(view.spot)][view.spot_obs];
    const auto& b = placement_observations_[static_cast<std::size_t>(view.other)][view.other_obs];
    if (!a.T_camera_board || !b.T_camera_board) continue;
    const cv::Matx44d through_board = *a.T_camera_board * rigidInverse(*b.T_camera_board);
    const cv::Matx44d through_poses =
        rigidInverse(poses.T_world_camera[static_cast<std::size_t>(view.spot)]) *
        poses.T_world_camera[static_cast<std::size_t>(view.other)];
    auto it = std::find_if(loop_closures_.begin(), loop_closures_.end(), [&](const LoopClosure& l) {
      return l.camera_i == view.spot && l.camera_j == view.other;
    });
    if (it == loop_closures_.end())
      it = loop_closures_.insert(loop_closures_.end(), {view.spot, view.other, 0, 0, 0});
    ++it->frames;
    it->translation_mm =
        std::max(it->translation_mm, 1000.0 * translationError(through_board, through_poses));
    it->rotation_deg = std::max(it->rotation_deg, rotationErrorDeg(through_board, through_poses));
  }
  if (loop_closures_.empty()) log << "  loop closure: no two cameras saw the board at once\n";
  for (const LoopClosure& l : loop_closures_) {
    log << "  loop closure cameras " << l.camera_i << "-" << l.camera_j << ": " << l.translation_mm << " mm, "
        << l.rotation_deg << " deg (worst of " << l.frames << " frames)\n";
    addVerdict(out, log,
               judgeLoopClosure(
                   "loop closure cameras " + std::to_string(l.camera_i) + "-" + std::to_string(l.camera_j),
                   l.translation_mm, l.rotation_deg));
  }
  return out;
}

StepOutcome CalibrationSession::measureBackground(std::ostream& log, bool quiet,
                                                  const PreviewCallback& on_preview) {
  StepOutcome out;
  log << "  " << config_.background_frames << " frames per camera\n";
  rig_.begin(RigActivity::EmptyHall);
  hall_frames_.assign(static_cast<std::size_t>(rig_.cameraCount()), {});
  for (int c = 0; c < rig_.cameraCount(); ++c) {
    std::vector<RgbdFrame> frames;
    {
      ProgressReporter progress(config_.background_frames, "camera " + std::to_string(c) + " background",
                                quiet);
      for (int k = 0; k < config_.background_frames; ++k) {
        std::optional<RgbdFrame> frame = rig_.nextFrame(c);
        if (!frame)
          throw InputError(cameraLabel(rig_, c), "background frames",
                           std::to_string(config_.background_frames) + " frames of the empty hall",
                           "the frames ended after " + std::to_string(k));
        frames.push_back(std::move(*frame));
        if (on_preview)
          on_preview(c, cameraLabel(rig_, c) + ", frame " + std::to_string(k + 1), frames.back().colour);
        progress.update();
      }
    }
    hall_frames_[static_cast<std::size_t>(c)] = frames.front();
    const BackgroundModel model = captureBackground(frames, "camera " + std::to_string(c));
    out.files.emplace_back("background_camera" + std::to_string(c) + ".png", model.colour);
    cv::Mat depth_mm;
    model.depth.convertTo(depth_mm, CV_16U, 1000.0);  // PNG depth in millimetres, 0 = invalid
    out.files.emplace_back("background_depth_camera" + std::to_string(c) + ".png", depth_mm);
    out.previews.emplace_back(cameraLabel(rig_, c), model.colour);
    log << "  camera " << c << ": " << model.invalid_samples << " invalid depth samples, colour MAD "
        << model.colour_mad << "\n";
    addVerdict(
        out, log,
        judgeBackground("background camera " + std::to_string(c), model.invalid_fraction, model.colour_mad));
  }
  return out;
}

StepOutcome CalibrationSession::measurePanorama(std::ostream& log, const PreviewCallback& on_preview) {
  StepOutcome out;
  const cv::Mat panorama = rig_.panorama();
  // Every camera votes; the best-correlated one decides (the others may see mostly the pyramid).
  YawFit best{0.0f, -2.0};
  for (int c = 0; c < rig_.cameraCount(); ++c) {
    const CameraModel model = toCameraModel(cameras_[static_cast<std::size_t>(c)]);
    const RgbdFrame& frame = hall_frames_[static_cast<std::size_t>(c)];
    preview(out, on_preview, cameraLabel(rig_, c), frame.colour);
    const YawFit fit = alignPanoramaYaw(panorama, model, frame.colour, "camera " + std::to_string(c));
    log << "  camera " << c << ": yaw " << fit.yaw_rad * 180.0f / kPi << " deg, correlation "
        << fit.correlation << "\n";
    if (fit.correlation > best.correlation) best = fit;
  }
  pyramid_.panorama_yaw_rad = best.yaw_rad;
  pyramid_.panorama_position = config_.panorama_position;
  // The panorama as it will be used: turned by the fitted yaw (a horizontal roll of its columns).
  const cv::Mat picture = panoramaPicture(panorama);
  const int shift =
      static_cast<int>(std::lround(best.yaw_rad / (2.0f * kPi) * static_cast<float>(picture.cols)));
  cv::Mat turned(picture.size(), picture.type());
  for (int x = 0; x < picture.cols; ++x)
    picture.col(((x + shift) % picture.cols + picture.cols) % picture.cols).copyTo(turned.col(x));
  out.files.emplace_back("panorama_aligned.png", turned);
  preview(out, on_preview, "panorama turned by the fitted yaw", turned);
  addVerdict(out, log, judgePanorama("panorama yaw", best.correlation));
  return out;
}

StepOutcome CalibrationSession::measureDisplay(std::ostream& log, const PreviewCallback& on_preview) {
  StepOutcome out;
  log << "  test pattern " << config_.face_view.width << "x" << config_.face_view.height << "\n";
  const auto dots = testPatternDots(config_.face_view);
  for (int f = 0; f < kPyramidFaces; ++f) {
    const FaceFit fit = estimateFaceAlignment(dots, rig_.observedTestPattern(f, config_.face_view),
                                              config_.face_view, "face " + std::to_string(f));
    pyramid_.faces[static_cast<std::size_t>(f)] = fit.alignment;
    cv::Mat shown;
    cv::warpAffine(drawTestPattern(config_.face_view, f), shown,
                   cv::Mat(faceTransform(fit.alignment, config_.face_view)), config_.face_view);
    out.files.emplace_back("display_face" + std::to_string(f) + ".png", shown);
    preview(out, on_preview, "face " + std::to_string(f), shown);
    log << "  face " << f << ": offset " << fit.alignment.offset_px.x << " " << fit.alignment.offset_px.y
        << " px, scale " << fit.alignment.scale << ", rotation " << fit.alignment.rotation_deg << " deg"
        << (fit.alignment.mirror ? ", mirrored" : "") << "\n";
    addVerdict(out, log, judgeDisplay("display face " + std::to_string(f), fit.residual_px));
  }
  return out;
}

StepOutcome CalibrationSession::measureVerification(std::ostream& log, const PreviewCallback& on_preview) {
  StepOutcome out;
  rig_.begin(RigActivity::VerificationJig);
  for (int c = 0; c < rig_.cameraCount(); ++c) {
    const std::string label = cameraLabel(rig_, c);
    const CameraModel camera = toCameraModel(cameras_[static_cast<std::size_t>(c)]);
    const std::vector<EdgeSegment> edges = verificationTargetEdges(verificationTargetPose(c));
    // Frames until one shows the jig's squares near where the calibration puts them (a recording
    // or a live camera may still show the hall before the jig is on); the closest is judged.
    std::optional<EdgeAlignment> best;
    cv::Mat best_colour;
    int frames = 0;
    while (frames < config_.max_frames_per_step) {
      std::optional<RgbdFrame> frame = rig_.nextFrame(c);
      if (!frame) break;
      ++frames;
      const EdgeAlignment alignment = measureEdgeAlignment(frame->colour, camera, edges, label);
      if (on_preview) on_preview(c, label + ", frame " + std::to_string(frames), frame->colour);
      if (!best || alignment.chamfer_aligned_px < best->chamfer_aligned_px) {
        best = alignment;
        best_colour = frame->colour;
      }
      if (alignment.chamfer_aligned_px < kVerificationMaxEdgePx) break;
    }
    if (!best)
      throw InputError(label, "verification frames", "a frame with the verification jig mounted",
                       "the frames ended");
    const EdgeAlignment& alignment = *best;
    std::ostringstream figures;
    figures << std::fixed << std::setprecision(2) << "edges " << alignment.chamfer_px << " px; off "
            << alignment.position_error_mm << " mm, " << alignment.rotation_error_deg << " deg";
    log << "  camera " << c << ": " << figures.str() << " (" << 100.0 * alignment.seen_fraction
        << "% of the jig in view; " << frames << " frames looked at)\n";
    const cv::Mat picture = drawEdgeAlignment(best_colour, camera, edges, alignment);
    out.files.emplace_back("verification_camera" + std::to_string(c) + ".png", picture);
    preview(out, on_preview, label + "\n" + figures.str(), picture);
    addVerdict(out, log, judgeVerification("verification camera " + std::to_string(c), alignment));
  }
  return out;
}

std::vector<fs::path> CalibrationSession::save(const fs::path& out_dir, std::ostream& log) const {
  for (int s = 0; s < kMeasuringSteps; ++s) HOLO_ASSERT(outcomes_[static_cast<std::size_t>(s)].has_value());
  fs::create_directories(out_dir);
  std::vector<fs::path> written;
  for (const CameraCalibration& cal : cameras_) {
    written.push_back(cameraCalibrationPath(out_dir, cal.serial));
    saveCameraCalibration(written.back(), cal);
  }
  written.push_back(pyramidCalibrationPath(out_dir));
  savePyramidCalibration(written.back(), pyramid_);
  for (int s = 0; s < kMeasuringSteps; ++s)
    for (const auto& file : outcomes_[static_cast<std::size_t>(s)]->files) {
      // Not a structured binding: clang 14 (the fuzz and sanitizer builds) cannot capture one.
      const cv::Mat& image = file.second;
      written.push_back(out_dir / file.first);
      writeAtomically(written.back(), [&](const fs::path& tmp) {
        if (!cv::imwrite(tmp.string(), image)) throw Error("could not write " + tmp.string());
      });
    }
  const AutoCalibrationReport summary = report();
  log << (summary.allPassed() ? "calibration saved: every step passed\n"
                              : "calibration saved, but some steps failed: see the hints above\n");
  return written;
}

const std::vector<BoardFrameObservation>& CalibrationSession::boardObservations(CalibrationStep step,
                                                                                int camera) const {
  static const std::vector<BoardFrameObservation> kNone;
  if (step != CalibrationStep::Intrinsics && step != CalibrationStep::Poses) return kNone;
  const auto& per_camera =
      step == CalibrationStep::Intrinsics ? intrinsics_observations_ : placement_observations_;
  return camera >= 0 && camera < static_cast<int>(per_camera.size())
             ? per_camera[static_cast<std::size_t>(camera)]
             : kNone;
}

AutoCalibrationReport CalibrationSession::report() const {
  AutoCalibrationReport out;
  for (const auto& outcome : outcomes_)
    if (outcome) out.verdicts.insert(out.verdicts.end(), outcome->verdicts.begin(), outcome->verdicts.end());
  out.cameras = cameras_;
  out.pyramid = pyramid_;
  return out;
}

}  // namespace holo::calib
