// A real installation's calibration end to end, on files: `holopyramid simulate --calibration`
// records the simulated museum as four cameras whose colour and depth are two devices (depth 15
// ms later, its scale 2% off, each camera's own white balance), `holopyramid eval calibration`
// calibrates the recording and measures it against the truth the recording carries: the fitted
// figures within their bars, and the loop's displayed images with that calibration closer to the
// true calibration's than without depth registration and colour matching.
//
// Small for CI: 3 visitor frames through the loop at 96-pixel views, 3 background frames, a
// 512-pixel panorama (the cameras keep their 640x360, which the board detection needs).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "command_output.hpp"
#include "holo/eval/acceptance_bars.hpp"
#include "run_holopyramid.hpp"
#include "shared_data.hpp"

namespace {

namespace fs = std::filesystem;
using holo::test::logText;
using holo::test::readJson;

TEST(EvalCalibration, FittedCalibrationWithinTheBarsAndRegistrationMatters) {
  const fs::path dir = holo::test::scratchDir("eval_calibration");
  const fs::path rec = dir / "rec", out = dir / "eval";
  ASSERT_EQ(
      holo::test::runHolopyramid("simulate --scene museum --frames 3 --calibration --background-frames 3 "
                                 "--panorama-width 512 -q --out " +
                                     rec.string(),
                                 dir / "simulate.log"),
      0)
      << logText(dir / "simulate.log");

  // Depth is a second device: every depth frame is stamped 15 ms after its colour frame.
  std::ifstream associations(rec / "cam0" / "associations.txt");
  std::string line;
  int pairs = 0;
  while (std::getline(associations, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    double t_rgb = 0, t_depth = 0;
    std::string rgb, depth;
    ASSERT_TRUE(fields >> t_rgb >> rgb >> t_depth >> depth) << line;
    EXPECT_NEAR(t_depth - t_rgb, 0.015, 1e-5) << line;
    ++pairs;
  }
  EXPECT_GT(pairs, 50);
  ASSERT_TRUE(fs::exists(rec / "truth" / "calibration" / "pyramid.yml"));

  const int status = holo::test::runHolopyramid(
      "eval calibration -q --frames 3 --view-size 96 --background-frames 3 "
      "--recording " +
          rec.string() + " --out " + out.string(),
      dir / "eval.log");
  std::cout << logText(dir / "eval.log");
  ASSERT_EQ(status, 0) << "a figure outside its bar (the table above)";
  const nlohmann::json j = readJson(out / "calibration_eval.json");
  ASSERT_TRUE(j["calibration_passed"].get<bool>());
  const nlohmann::json& worst = j["worst"];
  EXPECT_LT(worst["intrinsics_error_pct"].get<double>(), holo::eval::kMaxIntrinsicsErrorPct);
  EXPECT_LT(worst["position_error_mm"].get<double>(), holo::eval::kMaxPositionErrorMm);
  EXPECT_LT(worst["rotation_error_deg"].get<double>(), holo::eval::kMaxRotationErrorDeg);
  EXPECT_LT(worst["depth_scale_error_pct"].get<double>(), holo::eval::kMaxDepthScaleErrorPct);
  EXPECT_LT(worst["gain_error_pct"].get<double>(), holo::eval::kMaxGainErrorPct);
  ASSERT_EQ(j["cameras"].size(), 4u);
  ASSERT_EQ(j["frames"].get<int>(), 3);
  const double fitted = j["displayed"][0]["mean_codes"].get<double>();
  const double without = j["displayed"][1]["mean_codes"].get<double>();
  EXPECT_LT(fitted, holo::eval::kMaxDisplayedErrorCodes);
  EXPECT_GT(without, fitted) << "switching off depth registration and colour matching must show";
  EXPECT_TRUE(fs::exists(out / "calibration_eval.png"));
  EXPECT_TRUE(fs::exists(out / "run_fitted.yaml"));  // reruns the fitted calibration's loop
}

}  // namespace
