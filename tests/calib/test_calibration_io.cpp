// Calibration files: round trip, stock OpenCV reads them, every corrupt field is named in the
// error, and neither a failed save nor a killed one loses the previous calibration.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fstream>
#include <map>
#include <opencv2/core.hpp>

#include "holo/calib/calibration_io.hpp"
#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "shared_data.hpp"

namespace holo::calib {
namespace {

namespace fs = std::filesystem;

CameraCalibration sampleCamera(float fx = 612.5f) {
  CameraCalibration c;
  c.serial = "AZ-0042";
  c.intrinsics.width = 640;
  c.intrinsics.height = 480;
  c.intrinsics.fx = fx;
  c.intrinsics.fy = 611.25f;
  c.intrinsics.cx = 321.5f;
  c.intrinsics.cy = 238.75f;
  c.intrinsics.distortion = {-0.21f, 0.05f, 0.001f, -0.0005f, 0.01f};
  c.T_world_camera = lookAtCameraToWorld({0.3f, 0.1f, 0.45f}, {0.0f, 0.3f, 2.0f});
  c.depth_scale = 0.001;
  c.rms = 0.31;
  return c;
}

TEST(CalibrationIo, CameraRoundTripKeepsEveryField) {
  const fs::path dir = test::scratchDir("calib_roundtrip");
  const CameraCalibration in = sampleCamera();
  const fs::path path = cameraCalibrationPath(dir, in.serial);
  EXPECT_EQ(path.filename(), "camera_AZ-0042.yml");
  saveCameraCalibration(path, in);
  const CameraCalibration out = loadCameraCalibration(path);
  EXPECT_EQ(out.serial, in.serial);
  EXPECT_EQ(out.intrinsics.width, 640);
  EXPECT_EQ(out.intrinsics.height, 480);
  EXPECT_FLOAT_EQ(out.intrinsics.fx, in.intrinsics.fx);
  EXPECT_FLOAT_EQ(out.intrinsics.fy, in.intrinsics.fy);
  EXPECT_FLOAT_EQ(out.intrinsics.cx, in.intrinsics.cx);
  EXPECT_FLOAT_EQ(out.intrinsics.cy, in.intrinsics.cy);
  for (std::size_t i = 0; i < 5; ++i)
    EXPECT_FLOAT_EQ(out.intrinsics.distortion[i], in.intrinsics.distortion[i]);
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) EXPECT_FLOAT_EQ(out.T_world_camera[c][r], in.T_world_camera[c][r]);
  EXPECT_DOUBLE_EQ(out.depth_scale, 0.001);
  EXPECT_DOUBLE_EQ(out.rms, 0.31);
  EXPECT_EQ(out.date.size(), 20u);  // filled in on save: 2026-11-23T09:15:00Z
  EXPECT_EQ(out.date.back(), 'Z');

  // The camera model built from the file projects exactly as the original.
  const CameraModel a = toCameraModel(in), b = toCameraModel(out);
  const vec3 p{0.1f, 0.4f, 1.5f};
  ASSERT_TRUE(a.project(p) && b.project(p));
  EXPECT_NEAR(glm::distance(*a.project(p), *b.project(p)), 0.0f, 1e-4f);
  const CameraCalibration back = fromCameraModel(b, "AZ-0042", 0.31);
  EXPECT_FLOAT_EQ(back.intrinsics.fx, in.intrinsics.fx);
}

TEST(CalibrationIo, StockOpenCvReadsTheRosKeys) {
  const fs::path dir = test::scratchDir("calib_stock");
  const fs::path path = cameraCalibrationPath(dir, "cam1");
  CameraCalibration in = sampleCamera();
  in.serial = "cam1";
  saveCameraCalibration(path, in);
  cv::FileStorage fs(path.string(), cv::FileStorage::READ);
  ASSERT_TRUE(fs.isOpened());
  cv::Mat K, dist, T;
  fs["camera_matrix"] >> K;
  fs["distortion_coefficients"] >> dist;
  fs["T_world_camera"] >> T;
  EXPECT_EQ(static_cast<int>(fs["image_width"]), 640);
  EXPECT_EQ(static_cast<int>(fs["image_height"]), 480);
  EXPECT_EQ(static_cast<std::string>(fs["camera_name"]), "cam1");
  EXPECT_EQ(static_cast<std::string>(fs["distortion_model"]), "plumb_bob");
  ASSERT_EQ(K.size(), cv::Size(3, 3));
  EXPECT_NEAR(K.at<double>(0, 0), 612.5, 1e-9);
  EXPECT_NEAR(K.at<double>(1, 2), 238.75, 1e-9);
  ASSERT_EQ(dist.total(), 5u);
  EXPECT_NEAR(dist.at<double>(0), -0.21, 1e-6);
  ASSERT_EQ(T.size(), cv::Size(4, 4));
  EXPECT_NEAR(cv::determinant(T(cv::Rect(0, 0, 3, 3))), 1.0, 1e-6);
  EXPECT_NEAR(static_cast<double>(fs["rms"]), 0.31, 1e-12);
}

TEST(CalibrationIo, PyramidRoundTrip) {
  const fs::path dir = test::scratchDir("calib_pyramid");
  PyramidCalibration in;
  in.faces[1] = {{3.5f, -2.0f}, 0.98f, 90.0f, true};
  in.faces[3] = {{-1.0f, 4.0f}, 1.02f, 270.0f, false};
  in.panorama_yaw_rad = 0.4f;
  in.panorama_position = {0.0f, 0.35f, 0.0f};
  savePyramidCalibration(pyramidCalibrationPath(dir), in);
  const PyramidCalibration out = loadPyramidCalibration(pyramidCalibrationPath(dir));
  EXPECT_FLOAT_EQ(out.faces[1].offset_px.x, 3.5f);
  EXPECT_FLOAT_EQ(out.faces[1].scale, 0.98f);
  EXPECT_FLOAT_EQ(out.faces[1].rotation_deg, 90.0f);
  EXPECT_TRUE(out.faces[1].mirror);
  EXPECT_FALSE(out.faces[3].mirror);
  EXPECT_FLOAT_EQ(out.faces[3].offset_px.y, 4.0f);
  EXPECT_FLOAT_EQ(out.faces[0].scale, 1.0f);
  EXPECT_FLOAT_EQ(out.panorama_yaw_rad, 0.4f);
  EXPECT_FLOAT_EQ(out.panorama_position.y, 0.35f);
}

// Writes a camera file field by field with stock OpenCV so a test can break exactly one field.
struct CameraFields {
  std::map<std::string, std::function<void(cv::FileStorage&, const std::string&)>> write;
  CameraFields() {
    const CameraCalibration c = sampleCamera();
    write["image_width"] = [](cv::FileStorage& fs, const std::string& k) { fs << k << 640; };
    write["image_height"] = [](cv::FileStorage& fs, const std::string& k) { fs << k << 480; };
    write["camera_name"] = [](cv::FileStorage& fs, const std::string& k) { fs << k << "cam"; };
    write["camera_matrix"] = [](cv::FileStorage& fs, const std::string& k) {
      fs << k << cv::Mat(cv::Matx33d(600, 0, 320, 0, 600, 240, 0, 0, 1));
    };
    write["distortion_model"] = [](cv::FileStorage& fs, const std::string& k) { fs << k << "plumb_bob"; };
    write["distortion_coefficients"] = [](cv::FileStorage& fs, const std::string& k) {
      fs << k << cv::Mat(cv::Matx<double, 1, 5>(-0.1, 0.01, 0, 0, 0));
    };
    write["T_world_camera"] = [](cv::FileStorage& fs, const std::string& k) {
      fs << k << cv::Mat(cv::Matx44d(0, 0, 1, 0.1, 0, -1, 0, 0.2, 1, 0, 0, 0.3, 0, 0, 0, 1));
    };
    write["depth_scale"] = [](cv::FileStorage& fs, const std::string& k) { fs << k << 0.001; };
    write["date"] = [](cv::FileStorage& fs, const std::string& k) { fs << k << "2026-11-23T09:00:00Z"; };
    write["rms"] = [](cv::FileStorage& fs, const std::string& k) { fs << k << 0.3; };
  }
  void save(const fs::path& path) const {
    cv::FileStorage fs(path.string(), cv::FileStorage::WRITE);
    for (const auto& [key, w] : write)
      if (w) w(fs, key);
  }
};

struct Corruption {
  std::string name;
  std::string field;  // the field the error must name
  std::function<void(CameraFields&)> apply;
};

TEST(CalibrationIo, EveryCorruptFieldIsNamed) {
  const fs::path dir = test::scratchDir("calib_corrupt");
  {
    CameraFields good;
    good.save(dir / "good.yml");
    EXPECT_NO_THROW(loadCameraCalibration(dir / "good.yml"));
  }
  using M = cv::Mat;
  auto set = [](const std::string& key, std::function<void(cv::FileStorage&, const std::string&)> w) {
    return [key, w](CameraFields& f) { f.write[key] = w; };
  };
  auto drop = [](const std::string& key) { return [key](CameraFields& f) { f.write[key] = nullptr; }; };
  auto mat = [](M m) { return [m](cv::FileStorage& fs, const std::string& k) { fs << k << m; }; };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<Corruption> cases = {
      {"negative width", "image_width", set("image_width", [](auto& fs, auto& k) { fs << k << -640; })},
      {"width as text", "image_width", set("image_width", [](auto& fs, auto& k) { fs << k << "wide"; })},
      {"missing height", "image_height", drop("image_height")},
      {"missing name", "camera_name", drop("camera_name")},
      {"serial with slash", "camera_name", set("camera_name", [](auto& fs, auto& k) { fs << k << "../x"; })},
      {"K 3x2", "camera_matrix", set("camera_matrix", mat(M(cv::Matx32d(600, 0, 0, 600, 320, 240))))},
      {"K NaN", "camera_matrix",
       set("camera_matrix", mat(M(cv::Matx33d(nan, 0, 320, 0, 600, 240, 0, 0, 1))))},
      {"K negative fx", "camera_matrix",
       set("camera_matrix", mat(M(cv::Matx33d(-600, 0, 320, 0, 600, 240, 0, 0, 1))))},
      {"K not a matrix", "camera_matrix", set("camera_matrix", [](auto& fs, auto& k) { fs << k << 600; })},
      {"K last row", "camera_matrix",
       set("camera_matrix", mat(M(cv::Matx33d(600, 0, 320, 0, 600, 240, 0, 0, 2))))},
      {"fisheye model", "distortion_model",
       set("distortion_model", [](auto& fs, auto& k) { fs << k << "equidistant"; })},
      {"4 coefficients", "distortion_coefficients",
       set("distortion_coefficients", mat(M(cv::Matx41d(0.1, 0, 0, 0))))},
      {"inf coefficient", "distortion_coefficients",
       set("distortion_coefficients", mat(M(cv::Matx<double, 1, 5>(0.1, inf, 0, 0, 0))))},
      {"missing pose", "T_world_camera", drop("T_world_camera")},
      {"scaled rotation", "T_world_camera",
       set("T_world_camera", mat(M(cv::Matx44d(1.1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1))))},
      {"mirror (det -1)", "T_world_camera",
       set("T_world_camera", mat(M(cv::Matx44d(-1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1))))},
      {"sheared", "T_world_camera",
       set("T_world_camera", mat(M(cv::Matx44d(1, 0.2, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1))))},
      {"pose NaN", "T_world_camera",
       set("T_world_camera", mat(M(cv::Matx44d(1, 0, 0, nan, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1))))},
      {"projective last row", "T_world_camera",
       set("T_world_camera", mat(M(cv::Matx44d(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0.5, 0, 1))))},
      {"pose 3x4", "T_world_camera",
       set("T_world_camera", mat(M(cv::Matx34d(1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0))))},
      {"zero depth scale", "depth_scale", set("depth_scale", [](auto& fs, auto& k) { fs << k << 0.0; })},
      {"NaN depth scale", "depth_scale", set("depth_scale", [nan](auto& fs, auto& k) { fs << k << nan; })},
      {"negative rms", "rms", set("rms", [](auto& fs, auto& k) { fs << k << -0.5; })},
      {"missing date", "date", drop("date")},
  };
  for (const Corruption& c : cases) {
    CameraFields fields;
    c.apply(fields);
    const fs::path path = dir / "bad.yml";
    fields.save(path);
    try {
      (void)loadCameraCalibration(path);
      ADD_FAILURE() << c.name << ": loaded without error";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), c.field) << c.name << ": " << e.what();
      EXPECT_EQ(e.file(), path.string()) << c.name;
      EXPECT_NE(std::string(e.what()).find(c.field), std::string::npos) << e.what();
    }
  }
}

TEST(CalibrationIo, TruncatedGarbageAndMissingFilesAreInputErrors) {
  const fs::path dir = test::scratchDir("calib_truncated");
  const fs::path good = dir / "camera_good.yml";
  saveCameraCalibration(good, sampleCamera());
  const std::string text = readFile(good);
  // Every cut of the file either fails with InputError or (cut after the last field) loads.
  int failures = 0;
  for (std::size_t cut = 0; cut < text.size(); cut += 37) {
    const fs::path path = dir / "cut.yml";
    writeFileAtomically(path, text.substr(0, cut));
    try {
      (void)loadCameraCalibration(path);
    } catch (const InputError& e) {
      ++failures;
      EXPECT_EQ(e.file(), path.string());
    }
  }
  EXPECT_GT(failures, 10);
  writeFileAtomically(dir / "garbage.yml", "%YAML:1.0\n---\ncamera_matrix: [1, 2\n  : : {\n");
  EXPECT_THROW(loadCameraCalibration(dir / "garbage.yml"), InputError);
  writeFileAtomically(dir / "empty.yml", "");
  EXPECT_THROW(loadCameraCalibration(dir / "empty.yml"), InputError);
  EXPECT_THROW(loadCameraCalibration(dir / "absent.yml"), InputError);
  EXPECT_THROW(cameraCalibrationPath(dir, "a/b"), InputError);
}

// A matrix node's rows and cols are checked before OpenCV allocates them: the fuzzer's file
// (tests/fuzz/regressions/fuzz_config) made OpenCV ask for 85 GB; 20000 x 20000 doubles would be
// 3.2 GB that a machine with overcommit grants.
TEST(CalibrationIo, AMatrixClaimingHugeDimensionsIsRefusedBeforeAllocating) {
  const fs::path dir = test::scratchDir("calib_huge_matrix");
  const fs::path good = dir / "camera_good.yml";
  saveCameraCalibration(good, sampleCamera());
  std::string text = readFile(good);
  const auto at = text.find("rows: 3", text.find("camera_matrix"));
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 7, "rows: 20000");
  const auto cols = text.find("cols: 3", at);
  ASSERT_NE(cols, std::string::npos);
  text.replace(cols, 7, "cols: 20000");
  writeFileAtomically(dir / "huge.yml", text);
  try {
    (void)loadCameraCalibration(dir / "huge.yml");
    ADD_FAILURE() << "loaded a 20000x20000 camera matrix";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("camera_matrix"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("rows 20000, cols 20000"), std::string::npos) << e.what();
  }
}

// The camera files fuzz_config once crashed the reader with (after its first byte, which picks
// the reader): each is an InputError now.
TEST(CalibrationIo, FuzzRegressionsAreInputErrors) {
  const fs::path dir = test::scratchDir("calib_fuzz_regressions");
  int files = 0;
  for (const auto& entry :
       fs::directory_iterator(fs::path(HOLO_SOURCE_DIR) / "tests/fuzz/regressions/fuzz_config")) {
    const std::string bytes = readFile(entry.path());
    ASSERT_FALSE(bytes.empty());
    if (bytes[0] % 4 != 2) continue;  // not a camera calibration
    writeFileAtomically(dir / "camera.yml", bytes.substr(1));
    EXPECT_THROW((void)loadCameraCalibration(dir / "camera.yml"), InputError) << entry.path();
    ++files;
  }
  EXPECT_GE(files, 2);
}

TEST(CalibrationIo, CorruptPyramidFieldsAreNamed) {
  const fs::path dir = test::scratchDir("calib_pyramid_corrupt");
  auto expectField = [&](const std::string& text, const std::string& field) {
    writeFileAtomically(dir / "p.yml", "%YAML:1.0\n---\n" + text);
    try {
      (void)loadPyramidCalibration(dir / "p.yml");
      ADD_FAILURE() << field << ": loaded without error";
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), field) << e.what();
    }
  };
  const std::string face = "{ offset_x: 0, offset_y: 0, scale: 1, rotation_deg: 0, mirror: 0 }";
  const std::string tail =
      "panorama_yaw_rad: 0.1\npanorama_position: !!opencv-matrix\n  rows: 3\n  cols: 1\n  dt: d\n"
      "  data: [ 0., 0.35, 0. ]\ndate: \"x\"\n";
  const std::string four = "faces:\n  - " + face + "\n  - " + face + "\n  - " + face + "\n  - ";
  expectField("faces:\n  - " + face + "\n" + tail, "faces");
  expectField(four + "{ offset_x: 0, offset_y: 0, scale: 0, rotation_deg: 0, mirror: 0 }\n" + tail,
              "faces[3].scale");
  expectField(four + "{ offset_x: 0, offset_y: 0, scale: 1, rotation_deg: 0, mirror: 2 }\n" + tail,
              "faces[3].mirror");
  expectField(four + "{ offset_x: 0, scale: 1, rotation_deg: 0, mirror: 0 }\n" + tail, "faces[3].offset_y");
  expectField(four + face + "\npanorama_yaw_rad: .nan\n", "panorama_yaw_rad");
  writeFileAtomically(dir / "ok.yml", "%YAML:1.0\n---\n" + four + face + "\n" + tail);
  EXPECT_FLOAT_EQ(loadPyramidCalibration(dir / "ok.yml").panorama_yaw_rad, 0.1f);
}

TEST(CalibrationIo, SaveKeepsPreviousAsBackup) {
  const fs::path dir = test::scratchDir("calib_backup");
  const fs::path path = cameraCalibrationPath(dir, "AZ-0042");
  saveCameraCalibration(path, sampleCamera(500.0f));
  EXPECT_FALSE(fs::exists(backupPath(path)));
  saveCameraCalibration(path, sampleCamera(600.0f));
  EXPECT_FLOAT_EQ(loadCameraCalibration(path).intrinsics.fx, 600.0f);
  EXPECT_FLOAT_EQ(loadCameraCalibration(backupPath(path)).intrinsics.fx, 500.0f);
}

TEST(CalibrationIo, FailedSaveLeavesPreviousFileUntouched) {
  const fs::path dir = test::scratchDir("calib_failed_save");
  const fs::path path = cameraCalibrationPath(dir, "AZ-0042");
  saveCameraCalibration(path, sampleCamera(500.0f));
  const std::string before = readFile(path);

  CameraCalibration bad = sampleCamera(std::numeric_limits<float>::quiet_NaN());
  EXPECT_THROW(saveCameraCalibration(path, bad), InputError);
  bad = sampleCamera();
  bad.T_world_camera[0][0] = 2.0f;  // not a rotation
  EXPECT_THROW(saveCameraCalibration(path, bad), InputError);

  // A writer that produces an unreadable file is caught by the read-back before the rename.
  EXPECT_THROW(saveWithBackup(
                   path, [](const fs::path& tmp) { writeFileAtomically(tmp, "image_width: [\n"); },
                   [](const fs::path& tmp) { (void)loadCameraCalibration(tmp); }),
               InputError);
  EXPECT_EQ(readFile(path), before);
  EXPECT_FALSE(fs::exists(backupPath(path)));
  int leftovers = 0;
  for (const auto& entry : fs::directory_iterator(dir)) leftovers += entry.path() != path;
  EXPECT_EQ(leftovers, 0) << "temporary files left behind";
}

// The bar: kill the program in the middle of a save; the previous calibration must stay
// readable. A child process starts a real save and is SIGKILLed half-way through writing the
// temporary file, and (second run) after the temporary is complete but before the rename.
TEST(CalibrationIo, KilledSaveLeavesPreviousCalibrationReadable) {
  const fs::path dir = test::scratchDir("calib_killed_save");
  const fs::path path = cameraCalibrationPath(dir, "AZ-0042");
  saveCameraCalibration(path, sampleCamera(500.0f));
  saveCameraCalibration(dir / "next.yml", sampleCamera(700.0f));
  const std::string next = readFile(dir / "next.yml");

  for (const bool during_write : {true, false}) {
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      saveWithBackup(
          path,
          [&](const fs::path& tmp) {
            std::ofstream out(tmp, std::ios::binary);
            out << next.substr(0, during_write ? next.size() / 2 : next.size());
            out.flush();
            if (during_write) ::raise(SIGKILL);
          },
          [](const fs::path& tmp) { (void)loadCameraCalibration(tmp); },
          [](const fs::path&) { ::raise(SIGKILL); });
      ::_exit(0);  // not reached
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status)) << "the save was not interrupted";
    EXPECT_EQ(WTERMSIG(status), SIGKILL);
    EXPECT_FLOAT_EQ(loadCameraCalibration(path).intrinsics.fx, 500.0f) << "during_write=" << during_write;
  }
  // The next save succeeds despite the stale temporary files of the killed ones.
  saveCameraCalibration(path, sampleCamera(700.0f));
  EXPECT_FLOAT_EQ(loadCameraCalibration(path).intrinsics.fx, 700.0f);
  EXPECT_FLOAT_EQ(loadCameraCalibration(backupPath(path)).intrinsics.fx, 500.0f);
}

}  // namespace
}  // namespace holo::calib
