// Everything calibrated reaches the live loop: from a calibration folder beside a small recorded
// installation, loadInstallation picks up each camera's colour gains, the captured background
// (unless asked to relearn it), the panorama's capture point with the configured hall radius;
// the base's half width; the display settings take pyramid.yml's face alignment except where display.faces
// says otherwise, and a face placed by those settings lands where the calibration measured it.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "holo/calib/calibration_io.hpp"
#include "holo/calib/display_alignment.hpp"
#include "holo/capture/recorder.hpp"
#include "holo/core/error.hpp"
#include "holo/core/gltf_io.hpp"
#include "holo/core/hdr_io.hpp"
#include "holo/pipeline/calibrated_display.hpp"
#include "holo/pipeline/installation.hpp"
#include "holo/sim/museum.hpp"
#include "shared_data.hpp"

namespace holo::pipeline {
namespace {

namespace fs = std::filesystem;

void writeText(const fs::path& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
}

// Where the display puts unit point `unit` of face `face`, relative to the face's view.
vec2 displayed(const display::DisplayConfig& config, int face, cv::Size output, vec2 unit) {
  const display::FacePlacement placement = display::placeFace(config, face, output, {1.0f, 1.0f});
  return placement.apply(unit) - vec2(placement.view.x, placement.view.y);
}

// Where the calibration measured it: the face view's pixel under `unit` through faceTransform
// (pixel centres at integer coordinates there, at +0.5 on the display's pixel edges).
vec2 measured(const calib::FaceAlignment& alignment, int side, vec2 unit) {
  const cv::Matx23d A = calib::faceTransform(alignment, {side, side});
  const cv::Vec2d p = A * cv::Vec3d(unit.x * side - 0.5, unit.y * side - 0.5, 1.0);
  return {static_cast<float>(p[0] + 0.5), static_cast<float>(p[1] + 0.5)};
}

TEST(CalibratedDisplay, AFacePlacedByTheSettingsLandsWhereTheCalibrationMeasuredIt) {
  const int side = 540;
  calib::PyramidCalibration pyramid;
  pyramid.face_view_width = pyramid.face_view_height = side;
  const calib::FaceAlignment cases[] = {{{0.0f, 0.0f}, 1.0f, 0.0f, false},
                                        {{12.5f, -7.0f}, 0.97f, 3.5f, false},
                                        {{-20.0f, 4.0f}, 0.9f, -90.0f, true},
                                        {{3.0f, 6.0f}, 0.95f, 180.4f, true}};
  for (const display::LayoutKind layout : {display::LayoutKind::Monitors, display::LayoutKind::Cross}) {
    display::DisplayConfig config;
    config.layout = layout;
    // Views of `side` pixels in both layouts: a monitor of that size, or a cross a third of 1620.
    config.output_size =
        layout == display::LayoutKind::Monitors ? cv::Size(side, side) : cv::Size(1620, 1620);
    config.cross_view_size = 1.0f / 3.0f;
    config.cross_gap = 1.0f / 6.0f;
    for (int face = 0; face < display::kFaceCount; ++face) {
      const calib::FaceAlignment& alignment = cases[face];
      config.faces[static_cast<std::size_t>(face)] =
          faceSettingsFromCalibration(alignment, pyramid, layout, face);
      for (const vec2 unit : {vec2(0.0f), vec2(1.0f, 0.0f), vec2(0.25f, 0.75f), vec2(0.5f), vec2(1.0f)}) {
        const vec2 got = displayed(config, face, config.output_size, unit);
        const vec2 want = measured(alignment, side, unit);
        EXPECT_NEAR(glm::distance(got, want), 0.0f, 0.05f)
            << display::layoutName(layout) << " face " << face << " unit " << unit.x << "," << unit.y << ": "
            << got.x << "," << got.y << " against " << want.x << "," << want.y;
      }
    }
  }
}

// A small installation: a recording of the simulated museum at 160x96, relic, panorama and a
// calibration folder written as `holopyramid calibrate` writes it.
class CalibratedInstallation : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(test::scratchDir("pipeline_calibrated_" + std::to_string(getpid())));
    const fs::path& dir = *dir_;
    writeText(dir / "small_museum.yaml",
              "base: museum\ncamera: {width: 160, height: 96, hfov_deg: 110, vfov_deg: 70, fps: 30}\n");
    const sim::Museum museum(sim::loadScene((dir / "small_museum.yaml").string()));
    std::vector<capture::RecorderCamera> cameras;
    for (int i = 0; i < museum.cameraCount(); ++i)
      cameras.push_back({"cam" + std::to_string(i), "REC-" + std::to_string(i), museum.camera(i)});
    {
      capture::Recorder recorder(dir / "recording", cameras);
      for (int i = 0; i < museum.cameraCount(); ++i) {
        RgbdFrame frame = museum.renderCamera(i, 0, false).frame;
        frame.camera_id = i;
        recorder.write(frame);
      }
      recorder.finish();
    }
    saveGltf(dir / "relic.glb", museum.relic());
    saveHdr(dir / "hall.exr", museum.renderPanorama(64, 32));
    const fs::path calibration = dir / "calibration";
    fs::create_directories(calibration);
    for (int i = 0; i < museum.cameraCount(); ++i) {
      calib::CameraCalibration c = calib::fromCameraModel(museum.camera(i), "REC-" + std::to_string(i));
      c.colour_gains = {1.0f + 0.1f * static_cast<float>(i), 1.0f, 0.9f};
      // Camera 1's depth scale was fitted 2% above the recording's millimetres; camera 2's depth
      // comes from a second device of half the resolution, 5 cm to its side.
      if (i == 1) {
        c.depth_scale = 0.00102;
        c.depth_scale_fitted = true;
      }
      if (i == 2) {
        c.depth_intrinsics = Intrinsics::fromFov(80, 48, 1.9f, 1.2f);
        c.T_colour_depth = mat4(1.0f);
        c.T_colour_depth[3] = vec4(0.05f, 0.0f, 0.0f, 1.0f);
      }
      calib::saveCameraCalibration(calib::cameraCalibrationPath(calibration, c.serial), c);
      const RgbdFrame background = museum.backgroundFrame(i);
      cv::imwrite((calibration / ("background_camera" + std::to_string(i) + ".png")).string(),
                  background.colour);
      cv::Mat depth_mm;
      background.depth.convertTo(depth_mm, CV_16U, 1000.0);
      cv::imwrite((calibration / ("background_depth_camera" + std::to_string(i) + ".png")).string(),
                  depth_mm);
    }
    calib::PyramidCalibration pyramid;
    pyramid.panorama_yaw_rad = 0.25f;
    pyramid.panorama_position = {0.5f, 1.2f, -2.0f};
    for (int f = 0; f < 4; ++f)
      pyramid.faces[static_cast<std::size_t>(f)] = {
          {4.0f, -3.0f}, 0.98f, 90.0f * static_cast<float>(f) + 1.0f, true};
    calib::savePyramidCalibration(calib::pyramidCalibrationPath(calibration), pyramid);
  }
  static void TearDownTestSuite() {
    std::error_code ignored;
    fs::remove_all(*dir_, ignored);
    delete dir_;
  }

  static ConfigNode config(const std::string& name, const std::string& exhibit_extra,
                           const std::string& display = "display:\n  layout: monitors\n") {
    std::string text = "capture:\n  calibration_dir: calibration\n  cameras:\n";
    for (int i = 0; i < 4; ++i)
      text += "    - {face: " + std::to_string(i) +
              ", backend: recording, path: recording, camera: " + std::to_string(i) + "}\n";
    text += "exhibit:\n  relic: relic.glb\n  panorama: hall.exr\n  background_frames: 7\n" + exhibit_extra +
            display;
    writeText(*dir_ / name, text);
    return ConfigNode::loadFile(*dir_ / name);
  }

  static fs::path* dir_;
};

fs::path* CalibratedInstallation::dir_ = nullptr;

TEST_F(CalibratedInstallation, ColourGainsBackgroundAndPanoramaPositionReachTheLoop) {
  const Installation installation =
      loadInstallation(config("gains.yaml", "  hall_radius: 9.5\n  base_half_width: 0.25\n"));
  ASSERT_EQ(installation.colour_gains.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    EXPECT_FLOAT_EQ(installation.colour_gains[static_cast<std::size_t>(i)].r,
                    1.0f + 0.1f * static_cast<float>(i));
    EXPECT_FLOAT_EQ(installation.colour_gains[static_cast<std::size_t>(i)].b, 0.9f);
  }
  // The fitted depth scale against the recording's nominal millimetres; the second device's depth.
  ASSERT_EQ(installation.depth_correction.size(), 4u);
  EXPECT_FLOAT_EQ(installation.depth_correction[0], 1.0f);
  EXPECT_NEAR(installation.depth_correction[1], 1.02f, 1e-6f);
  ASSERT_EQ(installation.depth_to_colour.size(), 4u);
  EXPECT_FALSE(installation.depth_to_colour[1]);
  ASSERT_TRUE(installation.depth_to_colour[2]);
  EXPECT_EQ(installation.depth_to_colour[2]->depthSize(), cv::Size(80, 48));
  EXPECT_EQ(installation.depth_to_colour[2]->colourSize(), cv::Size(160, 96));
  // The captured background replaces the learning frames.
  ASSERT_EQ(installation.background.size(), 4u);
  EXPECT_EQ(installation.background_frames, 0);
  EXPECT_EQ(installation.background[2].colour.size(), cv::Size(160, 96));
  EXPECT_EQ(installation.background[2].depth.type(), CV_32FC1);
  double min_depth = 0, max_depth = 0;
  cv::minMaxLoc(installation.background[2].depth, &min_depth, &max_depth);
  EXPECT_GT(max_depth, 1.0);  // metres, not millimetres
  EXPECT_LT(max_depth, 30.0);
  // The hall's parallax: centred where the panorama was captured.
  EXPECT_FLOAT_EQ(installation.panorama_proxy.radius, 9.5f);
  EXPECT_FLOAT_EQ(installation.panorama_proxy.base_half_width, 0.25f);
  EXPECT_EQ(installation.panorama_proxy.centre, vec3(0.5f, 1.2f, -2.0f));
  EXPECT_FLOAT_EQ(installation.panorama_yaw_rad, 0.25f);

  // --relearn-background: the first frames teach it again.
  const Installation relearn = loadInstallation(config("relearn.yaml", ""), {.relearn_background = true});
  EXPECT_TRUE(relearn.background.empty());
  EXPECT_EQ(relearn.background_frames, 7);
  EXPECT_TRUE(relearn.panorama_proxy.infinite());           // no hall_radius: the hall at infinity
  EXPECT_EQ(relearn.panorama_proxy.base_half_width, 0.0f);  // no base_half_width: no base
}

TEST_F(CalibratedInstallation, DepthFilterSectionReachesTheLoopAndABadValueIsNamed) {
  const std::string display = "display:\n  layout: monitors\n";
  EXPECT_EQ(loadInstallation(config("default_filter.yaml", "", display)).depth_filter.levels,
            depthfilter::TemporalDepthFilterConfig{}.levels);
  const Installation installation =
      loadInstallation(config("filter.yaml", "", display + "depthfilter:\n  levels: 5\n  fill_radius: 2\n"));
  EXPECT_EQ(installation.depth_filter.levels, 5);
  EXPECT_EQ(installation.depth_filter.fill_radius, 2);
  try {
    (void)loadInstallation(config("bad_filter.yaml", "", display + "depthfilter:\n  levels: 0\n"));
    ADD_FAILURE() << "accepted levels 0";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("bad_filter.yaml"), std::string::npos) << what;
    EXPECT_NE(what.find("depthfilter.levels"), std::string::npos) << what;
    EXPECT_NE(what.find("[1, 8]"), std::string::npos) << what;
  }
}

TEST_F(CalibratedInstallation, DisplaySectionOverridesOnlyTheFieldsItSets) {
  const ConfigNode root = config("display.yaml", "",
                                 "display:\n  layout: monitors\n  faces:\n    - {}\n    - {rotation: 0}\n"
                                 "    - {mirror: false, scale: 1.5}\n    - {monitor: 2}\n");
  const display::DisplayConfig shown = calibratedDisplayConfig(root);
  const calib::PyramidCalibration pyramid =
      calib::loadPyramidCalibration(*dir_ / "calibration" / "pyramid.yml");
  for (int f = 0; f < 4; ++f) {
    const display::FaceSettings calibrated = faceSettingsFromCalibration(
        pyramid.faces[static_cast<std::size_t>(f)], pyramid, display::LayoutKind::Monitors, f);
    const display::FaceSettings& face = shown.faces[static_cast<std::size_t>(f)];
    EXPECT_FLOAT_EQ(face.rotation_deg, f == 1 ? 0.0f : calibrated.rotation_deg) << f;
    EXPECT_EQ(face.mirror, f == 2 ? false : true) << f;
    EXPECT_FLOAT_EQ(face.scale, f == 2 ? 1.5f : calibrated.scale) << f;
    EXPECT_EQ(face.offset, calibrated.offset) << f;
    EXPECT_EQ(face.monitor, f == 3 ? 2 : -1) << f;
  }
  // Calibrated: 1 degree counter-clockwise beyond the quarter turns, i.e. -1 - 90 f clockwise.
  EXPECT_NEAR(shown.faces[0].rotation_deg, -1.0f, 1e-4f);
  EXPECT_NEAR(shown.faces[2].rotation_deg, 179.0f, 1e-4f);
}

TEST_F(CalibratedInstallation, WrongBackgroundOrHallRadiusIsNamed) {
  try {
    (void)loadInstallation(config("small_hall.yaml", "  hall_radius: 1.0\n"));
    FAIL() << "a hall smaller than the distance to the pyramid accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("hall_radius"), std::string::npos) << e.what();
  }
  // 3 m clears the pyramid (2.39 m from the capture point) by 0.5 m, but not the corners of a
  // 0.3 m base (0.42 m further).
  EXPECT_NO_THROW((void)loadInstallation(config("hall_3m.yaml", "  hall_radius: 3.0\n")));
  try {
    (void)loadInstallation(config("base_outside.yaml", "  hall_radius: 3.0\n  base_half_width: 0.3\n"));
    FAIL() << "a base reaching beyond the hall accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("hall_radius"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("base_half_width"), std::string::npos) << e.what();
  }
  const fs::path broken = *dir_ / "broken_calibration";
  fs::create_directories(broken);
  cv::imwrite((broken / "background_camera0.png").string(), cv::Mat(48, 80, CV_8UC3, cv::Scalar::all(90)));
  cv::imwrite((broken / "background_depth_camera0.png").string(),
              cv::Mat(48, 80, CV_16UC1, cv::Scalar(2000)));
  try {
    (void)loadCalibratedBackground(broken, 0, {160, 96});
    FAIL() << "a background of the wrong size accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("background_camera0.png"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("160x96"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(loadCalibratedBackground(broken, 1, {160, 96}));
}

// The depthfilter: section reaches the installation (as loadInstallation and a run on the
// simulated museum read it), a document without one leaves the defaults, and a bad value is
// refused naming the file and the field.
TEST(DepthFilterSection, TunesTheInstallationAndABadValueIsRefusedNamingTheField) {
  Installation tuned;
  readDepthFilterSection(
      ConfigNode::parse("depthfilter:\n  levels: 4\n  foreground_scale: 2\n  full_size_outline: true\n",
                        "museum.yaml"),
      tuned);
  EXPECT_EQ(tuned.depth_filter.levels, 4);
  EXPECT_EQ(tuned.foreground_scale, 2);
  EXPECT_TRUE(tuned.foreground_full_size_outline);

  Installation untouched;
  readDepthFilterSection(ConfigNode::parse("display:\n  layout: cross\n", "museum.yaml"), untouched);
  EXPECT_EQ(untouched.foreground_scale, depthfilter::kDefaultForegroundScale);
  EXPECT_FALSE(untouched.foreground_full_size_outline);
  try {
    readDepthFilterSection(ConfigNode::parse("depthfilter:\n  full_size_outline: true\n", "museum.yaml"),
                           untouched);
    ADD_FAILURE() << "full_size_outline without a reduced foreground was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "museum.yaml");
    EXPECT_NE(std::string(e.what()).find("depthfilter.full_size_outline"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace holo::pipeline
