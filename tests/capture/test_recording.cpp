#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <random>

#include "holo/capture/recorder.hpp"
#include "holo/capture/recording_source.hpp"
#include "holo/core/error.hpp"
#include "shared_data.hpp"

using namespace holo;
using namespace holo::capture;

namespace {

RgbdFrame randomFrame(int camera, std::uint64_t seq, std::mt19937& rng) {
  RgbdFrame f;
  f.camera_id = camera;
  f.sequence = seq;
  f.device_time = std::chrono::milliseconds(1000 + 33 * static_cast<int>(seq));
  f.colour = cv::Mat(48, 64, CV_8UC3);
  cv::randu(f.colour, 0, 256);
  f.depth = cv::Mat(48, 64, CV_32FC1);
  std::uniform_real_distribution<float> metres(0.2f, 20.0f);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) f.depth.at<float>(y, x) = metres(rng);
  f.depth.at<float>(0, 0) = 0.0f;                                     // invalid stays invalid
  f.depth.at<float>(0, 1) = std::numeric_limits<float>::quiet_NaN();  // NaN -> invalid
  f.depth.at<float>(0, 2) = 100.0f;                                   // beyond 65.5 m -> clipped
  return f;
}

CameraModel testCamera(float x) {
  Intrinsics K = Intrinsics::fromFov(64, 48, 1.9f, 1.2f);
  K.distortion = {0.1f, -0.02f, 0.001f, 0.0f, 0.003f};
  mat4 T(1.0f);
  T[3] = vec4(x, 0.5f, -1.25f, 1.0f);
  return CameraModel(K, T);
}

}  // namespace

TEST(Recording, RoundTripIsBitExactInColourAndWithinOneStepInDepth) {
  const auto dir = test::scratchDir("recording_round_trip");
  std::mt19937 rng(7);
  std::vector<RgbdFrame> written;
  {
    Recorder rec(dir, {{"left", "SN-1", testCamera(1.0f)}, {"right", "SN-2", testCamera(-1.0f)}}, 1000.0, 2);
    for (std::uint64_t s = 0; s < 3; ++s)
      for (int cam = 0; cam < 2; ++cam) {
        written.push_back(randomFrame(cam, s, rng));
        rec.write(written.back());
      }
    EXPECT_EQ(rec.framesWritten(), 6);
    EXPECT_EQ(rec.depthClipped(), 6);  // one 100 m pixel per frame
  }
  ASSERT_TRUE(isRecordingFolder(dir));
  const Recording recording = readRecording(dir);
  EXPECT_EQ(recording.layout, "holopyramid");
  ASSERT_EQ(recording.cameras.size(), 2u);
  EXPECT_EQ(recording.cameras[1].name, "right");
  EXPECT_EQ(recording.cameras[1].serial, "SN-2");
  ASSERT_TRUE(recording.cameras[0].model.has_value());
  const CameraModel& m = *recording.cameras[0].model;
  const CameraModel ref = testCamera(1.0f);
  EXPECT_FLOAT_EQ(m.intrinsics().fx, ref.intrinsics().fx);
  EXPECT_FLOAT_EQ(m.intrinsics().cy, ref.intrinsics().cy);
  EXPECT_FLOAT_EQ(m.intrinsics().distortion[4], 0.003f);
  EXPECT_FLOAT_EQ(m.position().x, 1.0f);
  EXPECT_FLOAT_EQ(m.position().z, -1.25f);

  for (int cam = 0; cam < 2; ++cam) {
    RecordingSource source(recording.cameras[static_cast<std::size_t>(cam)]);
    source.open();
    source.start();
    for (std::uint64_t s = 0; s < 3; ++s) {
      const GrabResult r = source.grab(std::chrono::milliseconds(100));
      ASSERT_EQ(r.status, GrabStatus::Ok) << r.message;
      const RgbdFrame& orig = written[s * 2 + static_cast<std::size_t>(cam)];
      EXPECT_EQ(r.frame.sequence, s);
      EXPECT_EQ(r.frame.device_time, orig.device_time);
      EXPECT_EQ(cv::norm(r.frame.colour, orig.colour, cv::NORM_INF), 0.0);
      EXPECT_FLOAT_EQ(r.frame.depth.at<float>(0, 0), 0.0f);
      EXPECT_FLOAT_EQ(r.frame.depth.at<float>(0, 1), 0.0f);
      EXPECT_FLOAT_EQ(r.frame.depth.at<float>(0, 2), 0.0f);
      double worst = 0;
      for (int y = 1; y < 48; ++y)
        for (int x = 0; x < 64; ++x)
          worst =
              std::max(worst, std::abs(double(r.frame.depth.at<float>(y, x)) - orig.depth.at<float>(y, x)));
      EXPECT_LE(worst, 0.5 / 1000.0 + 1e-5);  // half a quantisation step (+ float rounding at 20 m)
      EXPECT_GT(worst, 0.0);                  // and it really was quantised
    }
    EXPECT_EQ(source.grab(std::chrono::milliseconds(10)).status, GrabStatus::EndOfStream);
  }
}

TEST(Recording, RefusesToOverwriteARecording) {
  const auto dir = test::scratchDir("recording_no_overwrite");
  { Recorder rec(dir, {{"a", "", std::nullopt}}); }
  EXPECT_THROW(Recorder(dir, {{"a", "", std::nullopt}}), InputError);
}

TEST(Recording, ReadsTheRealTumFrame) {
  HOLO_REQUIRE_SHARED_DATA("rgbd/tum/depth.png");
  const auto dir = test::sharedData("rgbd/tum");
  const Recording recording = readRecording(dir);
  EXPECT_EQ(recording.layout, "single-frame");
  ASSERT_EQ(recording.cameras.size(), 1u);
  const RecordedCamera& cam = recording.cameras[0];
  EXPECT_DOUBLE_EQ(cam.depth_scale, 5000.0);
  ASSERT_TRUE(cam.model.has_value());
  EXPECT_FLOAT_EQ(cam.model->intrinsics().fx, 525.0f);
  EXPECT_FLOAT_EQ(cam.model->intrinsics().cx, 319.5f);
  EXPECT_FLOAT_EQ(cam.model->intrinsics().cy, 239.5f);
  RecordingSource source(cam);
  const RgbdFrame f = source.load(0);
  EXPECT_EQ(f.colour.cols, 640);
  EXPECT_EQ(f.colour.rows, 480);
  ASSERT_EQ(f.depth.type(), CV_32FC1);
  // An office desk seen by a Kinect: most pixels valid, nearest surface beyond 0.3 m, the far wall
  // under 10 m (the PNG's 16-bit range at 5000 units/m ends at 13.1 m).
  const cv::Mat valid = f.depth > 0;
  const double valid_fraction = cv::countNonZero(valid) / double(f.depth.total());
  EXPECT_GT(valid_fraction, 0.5);
  double lo = 0, hi = 0;
  cv::minMaxLoc(f.depth, nullptr, &hi);
  cv::minMaxLoc(f.depth, &lo, nullptr, nullptr, nullptr, valid);
  EXPECT_GT(lo, 0.3);
  EXPECT_LT(hi, 10.0);
  const double mean_depth = cv::mean(f.depth, valid)[0];
  EXPECT_GT(mean_depth, 0.5);
  EXPECT_LT(mean_depth, 4.0);
}

TEST(Recording, MalformedFoldersNameTheProblem) {
  const auto dir = test::scratchDir("recording_malformed");
  try {
    readRecording(dir);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("color.png + depth.png"), std::string::npos) << e.what();
  }
  std::ofstream(dir / "rgb.txt") << "# comment\n1.0 rgb/a.png\n";
  std::ofstream(dir / "depth.txt") << "1.0\n";  // missing file column
  try {
    readRecording(dir);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("depth.txt"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("line 1"), std::string::npos) << e.what();
  }
}

TEST(Recording, TumSequenceAssociatesNearestTimestamps) {
  const auto dir = test::scratchDir("recording_tum_sequence");
  std::filesystem::create_directories(dir / "rgb");
  std::filesystem::create_directories(dir / "depth");
  std::ofstream(dir / "rgb.txt") << "# rgb\n10.000 rgb/a.png\n10.033 rgb/b.png\n10.500 rgb/c.png\n";
  std::ofstream(dir / "depth.txt") << "# depth\n10.005 depth/a.png\n10.030 depth/b.png\n";
  const Recording r = readRecording(dir);
  EXPECT_EQ(r.layout, "tum-sequence");
  ASSERT_EQ(r.cameras[0].frames.size(), 2u);  // c has no depth within 20 ms
  EXPECT_EQ(r.cameras[0].frames[0].depth.filename(), "a.png");
  EXPECT_EQ(r.cameras[0].frames[1].depth.filename(), "b.png");
  // Missing image files lose a frame, not the replay.
  RecordingSource source(r.cameras[0]);
  source.open();
  source.start();
  EXPECT_EQ(source.grab(std::chrono::milliseconds(10)).status, GrabStatus::Failed);
}

// A 100k-frame recording (an hour at 30 fps) reads: its index is all that is loaded up front.
TEST(Recording, HundredThousandFrameIndexReads) {
  const auto dir = test::scratchDir("recording_100k");
  {
    std::ofstream out(dir / "rgb.txt");
    std::ofstream depth(dir / "depth.txt");
    std::ofstream associations(dir / "associations.txt");
    for (int i = 0; i < 100000; ++i) {
      const std::string t = std::to_string(i / 30.0);
      out << t << " rgb/" << i << ".png\n";
      depth << t << " depth/" << i << ".png\n";
      associations << t << " rgb/" << i << ".png " << t << " depth/" << i << ".png\n";
    }
  }
  const Recording r = readRecording(dir);
  ASSERT_EQ(r.cameras.size(), 1u);
  ASSERT_EQ(r.cameras[0].frames.size(), 100000u);
  EXPECT_EQ(r.cameras[0].frames.back().depth.filename(), "99999.png");
}

// An index larger than the limit is refused by its size, before a line is read (the file here is
// sparse: no disk or memory is spent on it).
TEST(Recording, OversizedIndexIsRefusedByItsSize) {
  const auto dir = test::scratchDir("recording_huge_index");
  std::ofstream(dir / "rgb.txt") << "0.0 rgb/0.png\n";
  std::ofstream(dir / "depth.txt") << "0.0 depth/0.png\n";
  std::filesystem::resize_file(dir / "depth.txt", kMaxRecordingIndexBytes + 1);
  try {
    readRecording(dir);
    ADD_FAILURE() << "read a " << (kMaxRecordingIndexBytes >> 20) << " MiB index";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), (dir / "depth.txt").string());
    EXPECT_NE(std::string(e.what()).find("at most 64 MiB"), std::string::npos) << e.what();
  }
}

// A recording names only files inside its own folder: a camera folder or a frame path that is
// absolute, climbs out with '..' or goes through a symlink leading out is an InputError naming
// the file and the field, before anything outside is read. Symlinks that stay inside are fine.
TEST(Recording, PathsCannotLeaveTheRecordingsFolder) {
  namespace fs = std::filesystem;
  const auto outside = test::scratchDir("recording_outside");
  std::ofstream(outside / "associations.txt") << "0.0 rgb/0.png 0.0 depth/0.png\n";
  const auto dir = test::scratchDir("recording_confined");
  fs::create_directories(dir / "cam0");
  std::ofstream(dir / "cam0" / "associations.txt") << "0.0 rgb/0.png 0.0 depth/0.png\n";
  fs::create_directory_symlink(outside, dir / "link_out");
  fs::create_directory_symlink(dir / "cam0", dir / "link_in");
  const auto writeIndex = [&](const std::string& folder) {
    std::ofstream(dir / "recording.yaml") << "format: holopyramid-recording\ndepth_scale: 1000\n"
                                          << "cameras:\n  - name: front\n    folder: \"" << folder << "\"\n";
  };
  for (const std::string& folder : {outside.string(), std::string("../recording_outside"),
                                    std::string("cam0/../../recording_outside"), std::string("link_out")}) {
    writeIndex(folder);
    try {
      readRecording(dir);
      ADD_FAILURE() << "read the camera folder " << folder;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), (dir / "recording.yaml").string()) << folder;
      EXPECT_EQ(e.field(), "cameras[0].folder (line 5)") << folder;
      EXPECT_NE(std::string(e.what()).find(folder), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("inside the recording's folder"), std::string::npos) << e.what();
    }
  }
  for (const std::string folder : {"cam0", "link_in", "./cam0"}) {
    writeIndex(folder);
    EXPECT_EQ(readRecording(dir).cameras.at(0).frames.size(), 1u) << folder;
  }

  // Frame paths in an index: climbing out, absolute, and a frame that is a symlink leading out.
  writeIndex("cam0");
  fs::create_symlink(outside / "associations.txt", dir / "cam0" / "escape.png");
  for (const std::string& frame : {std::string("../../recording_outside/associations.txt"),
                                   (outside / "associations.txt").string(), std::string("escape.png")}) {
    std::ofstream(dir / "cam0" / "associations.txt") << "# index\n0.0 rgb/0.png 0.0 " << frame << "\n";
    try {
      readRecording(dir);
      ADD_FAILURE() << "accepted the frame " << frame;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), (dir / "cam0" / "associations.txt").string()) << frame;
      EXPECT_EQ(e.field(), "line 2") << frame;
      EXPECT_NE(std::string(e.what()).find(frame), std::string::npos) << e.what();
    }
  }
  // The same in a plain TUM sequence's rgb.txt.
  const auto tum = test::scratchDir("recording_tum_escape");
  std::ofstream(tum / "rgb.txt") << "1.0 /etc/passwd\n";
  std::ofstream(tum / "depth.txt") << "1.0 depth/a.png\n";
  try {
    readRecording(tum);
    ADD_FAILURE() << "accepted /etc/passwd as a frame";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), (tum / "rgb.txt").string());
    EXPECT_EQ(e.field(), "line 1");
  }
}
