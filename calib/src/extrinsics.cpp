#include "holo/calib/extrinsics.hpp"

#include <cmath>
#include <opencv2/calib3d.hpp>

#include "holo/calib/board_tracking.hpp"
#include "holo/calib/pose.hpp"
#include "holo/core/error.hpp"

namespace holo::calib {

namespace {

cv::Matx33d cameraMatrix(const Intrinsics& K) {
  return {K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1};
}
cv::Vec<double, 5> distortion(const Intrinsics& K) {
  return {K.distortion[0], K.distortion[1], K.distortion[2], K.distortion[3], K.distortion[4]};
}

// The joint adjustment's unknowns: T_camera_world of every camera, then T_world_board of every
// unknown placement, each as a Rodrigues vector and a translation.
class JointAdjustment : public cv::LMSolver::Callback {
 public:
  JointAdjustment(const ExtrinsicsProblem& problem, std::vector<int> unknown_index)
      : problem_(problem), unknown_index_(std::move(unknown_index)) {
    for (const auto& o : problem.observations)
      residuals_ += 2 * static_cast<int>(o.detection.image_points.size());
  }

  int residualCount() const { return residuals_; }

  void residuals(const cv::Mat& param, cv::Mat& err) const {
    err.create(residuals_, 1, CV_64F);
    int row = 0;
    for (const auto& o : problem_.observations) {
      const cv::Matx44d T_world_board = boardPose(param, o.placement);
      std::vector<cv::Point3d> world;
      world.reserve(o.detection.object_points.size());
      for (const auto& p : o.detection.object_points)
        world.push_back(transform(T_world_board, cv::Point3d(p)));
      const double* c = param.ptr<double>() + 6 * o.camera;
      std::vector<cv::Point2d> projected;
      const Intrinsics& K = problem_.cameras[static_cast<std::size_t>(o.camera)];
      cv::projectPoints(world, cv::Vec3d(c[0], c[1], c[2]), cv::Vec3d(c[3], c[4], c[5]), cameraMatrix(K),
                        distortion(K), projected);
      for (std::size_t i = 0; i < projected.size(); ++i) {
        err.at<double>(row++) = projected[i].x - o.detection.image_points[i].x;
        err.at<double>(row++) = projected[i].y - o.detection.image_points[i].y;
      }
    }
  }

  bool compute(cv::InputArray param_in, cv::OutputArray err_out, cv::OutputArray J_out) const override {
    const cv::Mat param = param_in.getMat();
    cv::Mat err;
    residuals(param, err);
    err.copyTo(err_out);
    if (J_out.needed()) {
      // Central differences: the problem has a few dozen unknowns, so this costs little and
      // keeps the chain rule through board pose, camera pose and distortion out of the code.
      cv::Mat J(residuals_, param.rows, CV_64F);
      cv::Mat probe = param.clone(), plus, minus;
      for (int j = 0; j < param.rows; ++j) {
        const double h = 1e-6;
        probe.at<double>(j) = param.at<double>(j) + h;
        residuals(probe, plus);
        probe.at<double>(j) = param.at<double>(j) - h;
        residuals(probe, minus);
        probe.at<double>(j) = param.at<double>(j);
        cv::Mat column = (plus - minus) / (2 * h);
        column.copyTo(J.col(j));
      }
      J.copyTo(J_out);
    }
    return true;
  }

  cv::Matx44d boardPose(const cv::Mat& param, int placement) const {
    const int u = unknown_index_[static_cast<std::size_t>(placement)];
    if (u < 0) return problem_.placements[static_cast<std::size_t>(placement)].T_world_board;
    const double* b = param.ptr<double>() + 6 * (static_cast<int>(problem_.cameras.size()) + u);
    return poseFromRt({b[0], b[1], b[2]}, {b[3], b[4], b[5]});
  }

 private:
  const ExtrinsicsProblem& problem_;
  std::vector<int> unknown_index_;  // per placement: index among the unknowns, or -1 if known
  int residuals_ = 0;
};

}  // namespace

ExtrinsicsResult calibrateExtrinsics(const ExtrinsicsProblem& problem, const std::string& source) {
  const int cameras = static_cast<int>(problem.cameras.size());
  const int placements = static_cast<int>(problem.placements.size());
  for (const auto& o : problem.observations) {
    if (o.camera < 0 || o.camera >= cameras)
      throw InputError(source, "observation camera", "0.." + std::to_string(cameras - 1),
                       std::to_string(o.camera));
    if (o.placement < 0 || o.placement >= placements)
      throw InputError(source, "observation placement", "0.." + std::to_string(placements - 1),
                       std::to_string(o.placement));
  }
  // Usable observations only: fewer than 6 corners constrain a pose too weakly to trust.
  ExtrinsicsProblem used = problem;
  used.observations.clear();
  for (const auto& o : problem.observations)
    if (o.detection.usable()) used.observations.push_back(o);

  ExtrinsicsResult result;
  result.T_world_camera.resize(static_cast<std::size_t>(cameras));
  result.camera_rms.assign(static_cast<std::size_t>(cameras), 0.0);
  result.camera_corners.assign(static_cast<std::size_t>(cameras), 0);
  result.T_world_board.resize(static_cast<std::size_t>(placements));
  for (int p = 0; p < placements; ++p)
    result.T_world_board[static_cast<std::size_t>(p)] =
        problem.placements[static_cast<std::size_t>(p)].T_world_board;

  // 1. Each camera from the boards at known placements it sees.
  std::vector<cv::Vec3d> rvecs(static_cast<std::size_t>(cameras)), tvecs(static_cast<std::size_t>(cameras));
  for (int c = 0; c < cameras; ++c) {
    std::vector<cv::Point3d> world;
    std::vector<cv::Point2d> image;
    for (const auto& o : used.observations) {
      if (o.camera != c || !problem.placements[static_cast<std::size_t>(o.placement)].known) continue;
      const cv::Matx44d& T = problem.placements[static_cast<std::size_t>(o.placement)].T_world_board;
      for (std::size_t i = 0; i < o.detection.object_points.size(); ++i) {
        world.push_back(transform(T, cv::Point3d(o.detection.object_points[i])));
        image.emplace_back(o.detection.image_points[i]);
      }
    }
    if (world.size() < 6)
      throw InputError(source, "camera " + std::to_string(c),
                       "a view of a board at a known placement with at least 6 corners",
                       std::to_string(world.size()) + " corners");
    const Intrinsics& K = problem.cameras[static_cast<std::size_t>(c)];
    auto& rvec = rvecs[static_cast<std::size_t>(c)];
    auto& tvec = tvecs[static_cast<std::size_t>(c)];
    cv::solvePnP(world, image, cameraMatrix(K), distortion(K), rvec, tvec, false, cv::SOLVEPNP_ITERATIVE);
    cv::solvePnPRefineLM(world, image, cameraMatrix(K), distortion(K), rvec, tvec);
  }

  // 2. Unknown placements from the first camera that sees each.
  std::vector<int> unknown_index(static_cast<std::size_t>(placements), -1);
  int unknowns = 0;
  for (int p = 0; p < placements; ++p)
    if (!problem.placements[static_cast<std::size_t>(p)].known)
      unknown_index[static_cast<std::size_t>(p)] = unknowns++;
  cv::Mat param(6 * (cameras + unknowns), 1, CV_64F, cv::Scalar(0));
  for (int c = 0; c < cameras; ++c)
    for (int k = 0; k < 3; ++k) {
      param.at<double>(6 * c + k) = rvecs[static_cast<std::size_t>(c)][k];
      param.at<double>(6 * c + 3 + k) = tvecs[static_cast<std::size_t>(c)][k];
    }
  for (int p = 0; p < placements; ++p) {
    const int u = unknown_index[static_cast<std::size_t>(p)];
    if (u < 0) continue;
    bool seen = false;
    for (const auto& o : used.observations) {
      if (o.placement != p) continue;
      const Intrinsics& K = problem.cameras[static_cast<std::size_t>(o.camera)];
      cv::Vec3d rb, tb;
      cv::solvePnP(o.detection.object_points, o.detection.image_points, cameraMatrix(K), distortion(K), rb,
                   tb);
      const cv::Matx44d T_world_board = rigidInverse(poseFromRt(rvecs[static_cast<std::size_t>(o.camera)],
                                                                tvecs[static_cast<std::size_t>(o.camera)])) *
                                        poseFromRt(rb, tb);
      cv::Vec3d r, t;
      poseToRt(T_world_board, r, t);
      for (int k = 0; k < 3; ++k) {
        param.at<double>(6 * (cameras + u) + k) = r[k];
        param.at<double>(6 * (cameras + u) + 3 + k) = t[k];
      }
      seen = true;
      break;
    }
    if (!seen)
      throw InputError(source, "placement " + std::to_string(p),
                       "an unknown board placement seen by a camera", "no usable view");
  }

  // 3. Joint adjustment of everything that moves.
  const cv::Ptr<JointAdjustment> adjustment = cv::makePtr<JointAdjustment>(used, unknown_index);
  if (problem.joint_refinement && adjustment->residualCount() > param.rows)
    result.iterations = cv::LMSolver::create(adjustment, 100, 1e-10)->run(param);

  cv::Mat err;
  adjustment->residuals(param, err);
  double total = 0;
  int row = 0;
  std::vector<double> sums(static_cast<std::size_t>(cameras), 0.0);
  for (const auto& o : used.observations) {
    for (std::size_t i = 0; i < o.detection.image_points.size(); ++i, row += 2) {
      const double e2 =
          err.at<double>(row) * err.at<double>(row) + err.at<double>(row + 1) * err.at<double>(row + 1);
      sums[static_cast<std::size_t>(o.camera)] += e2;
      total += e2;
    }
    result.camera_corners[static_cast<std::size_t>(o.camera)] +=
        static_cast<int>(o.detection.image_points.size());
  }
  for (int c = 0; c < cameras; ++c) {
    const double* p = param.ptr<double>() + 6 * c;
    result.T_world_camera[static_cast<std::size_t>(c)] =
        rigidInverse(poseFromRt({p[0], p[1], p[2]}, {p[3], p[4], p[5]}));
    const int n = result.camera_corners[static_cast<std::size_t>(c)];
    result.camera_rms[static_cast<std::size_t>(c)] =
        n > 0 ? std::sqrt(sums[static_cast<std::size_t>(c)] / n) : 0.0;
  }
  for (int p = 0; p < placements; ++p)
    result.T_world_board[static_cast<std::size_t>(p)] = adjustment->boardPose(param, p);
  const int corners = row / 2;
  result.rms = corners > 0 ? std::sqrt(total / corners) : 0.0;
  return result;
}

RelativePose relativePoseFromSharedViews(const Intrinsics& a, const Intrinsics& b,
                                         const std::vector<SharedBoardView>& views,
                                         const std::string& source) {
  ExtrinsicsProblem problem;
  problem.cameras = {a, b};
  std::vector<std::pair<cv::Matx44d, cv::Matx44d>> pair_poses;  // T_a_board, T_b_board per used pair
  for (const SharedBoardView& view : views) {
    const auto pa = boardPose(view.a, a), pb = boardPose(view.b, b);
    if (!pa || !pb) continue;
    const int placement = static_cast<int>(problem.placements.size());
    // The first pair anchors the world (camera a's frame); the others are estimated jointly.
    problem.placements.push_back({*pa, placement == 0});
    problem.observations.push_back({0, placement, view.a});
    problem.observations.push_back({1, placement, view.b});
    pair_poses.emplace_back(*pa, *pb);
  }
  if (pair_poses.empty())
    throw InputError(source, "board views", "at least one moment both cameras saw the board", "none");
  const ExtrinsicsResult joint = calibrateExtrinsics(problem, source);
  RelativePose out;
  out.T_a_b = rigidInverse(joint.T_world_camera[0]) * joint.T_world_camera[1];
  out.pairs = static_cast<int>(pair_poses.size());
  out.rms_px = joint.rms;
  for (const auto& pair : pair_poses) {
    const cv::Matx44d own = pair.first * rigidInverse(pair.second);
    out.pair_translation_mm.push_back(1000.0 * translationError(own, out.T_a_b));
    out.pair_rotation_deg.push_back(rotationErrorDeg(own, out.T_a_b));
  }
  return out;
}

}  // namespace holo::calib
