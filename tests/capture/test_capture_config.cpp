// The capture section of the configuration: what it accepts, and errors naming file and field.
#include <gtest/gtest.h>

#include "holo/capture/capture_config.hpp"
#include "holo/core/error.hpp"

using namespace holo;
using namespace holo::capture;

namespace {

CaptureConfig parse(const std::string& text) {
  return parseCaptureConfig(ConfigNode::parse(text, "holo.yaml")["capture"]);
}

std::string errorOf(const std::string& text) {
  try {
    parse(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST(CaptureConfig, ParsesFacesBackendsFormatsAndScales) {
  const CaptureConfig c = parse(R"(
capture:
  grab_timeout_ms: 150
  max_backoff_ms: 3000
  cameras:
    - face: 2
      backend: v4l2
      color: {device: "serial:843112071234", pixel_format: YUYV, width: 640, height: 480, frame_rate: 30}
      depth: {device: "/dev/video4", pixel_format: Z16, depth_scale: 0.00025}
    - face: 0
      backend: aravis
      name: north
      color: {serial: GV-0001, pixel_format: BayerRG8, width: 640, height: 360}
      depth: {serial: GV-0002, pixel_format: Coord3D_C16, depth_scale: 0.001, packet_socket: off,
              features: {ExposureTime: 8000, GainAuto: "Off"}}
)");
  ASSERT_EQ(c.cameras.size(), 2u);
  EXPECT_EQ(c.options.grab_timeout.count(), 150);
  EXPECT_EQ(c.options.max_backoff.count(), 3000);
  const CameraEntry& north = c.cameras[0];  // sorted by face
  EXPECT_EQ(north.face, 0);
  EXPECT_EQ(north.backend, Backend::Aravis);
  EXPECT_EQ(north.name, "north");
  EXPECT_EQ(north.aravis.colour.serial, "GV-0001");
  EXPECT_EQ(north.aravis.colour.pixel_format, "BayerRG8");
  EXPECT_EQ(north.aravis.colour.width, 640);
  EXPECT_EQ(north.aravis.depth.pixel_format, "Coord3D_C16");
  EXPECT_EQ(north.aravis.depth.packet_socket, AravisStreamConfig::PacketSocket::Off);
  using Feature = std::pair<std::string, std::string>;
  EXPECT_EQ(north.aravis.depth.features,
            (std::vector<Feature>{{"ExposureTime", "8000"}, {"GainAuto", "Off"}}));
  const CameraEntry& south = c.cameras[1];
  EXPECT_EQ(south.face, 2);
  EXPECT_EQ(south.name, "face2");
  EXPECT_EQ(south.backend, Backend::V4l2);
  EXPECT_EQ(south.v4l2.colour.device, "serial:843112071234");
  EXPECT_EQ(south.v4l2.colour.pixel_format, "YUYV");
  EXPECT_DOUBLE_EQ(south.v4l2.colour.frame_rate, 30.0);
  EXPECT_DOUBLE_EQ(south.v4l2.depth.depth_scale, 0.00025);
  EXPECT_EQ(makeCaptureOptions(c, south).camera_id, 2);
  // Sources are built without opening anything.
  EXPECT_EQ(makeSource(north)->name(), "north");
  EXPECT_EQ(makeSource(south)->serial(), "serial:843112071234");
}

TEST(CaptureConfig, ErrorsNameTheFileAndTheField) {
  const std::string face =
      errorOf("capture:\n  cameras:\n    - {face: 5, backend: aravis, color: {serial: A}}\n");
  EXPECT_TRUE(contains(face, "holo.yaml")) << face;
  EXPECT_TRUE(contains(face, "capture.cameras[0].face")) << face;

  const std::string twice = errorOf(
      "capture:\n  cameras:\n    - {face: 1, backend: aravis, color: {serial: A}}\n"
      "    - {face: 1, backend: aravis, color: {serial: B}}\n");
  EXPECT_TRUE(contains(twice, "capture.cameras[1].face")) << twice;

  const std::string format = errorOf(
      "capture:\n  cameras:\n    - {face: 0, backend: v4l2, depth: {device: /dev/video2, pixel_format: "
      "YUYV}}\n");
  EXPECT_TRUE(contains(format, "capture.cameras[0].depth.pixel_format")) << format;
  EXPECT_TRUE(contains(format, "Z16")) << format;

  const std::string scale = errorOf(
      "capture:\n  cameras:\n    - {face: 0, backend: aravis, depth: {serial: D, depth_scale: -1}}\n");
  EXPECT_TRUE(contains(scale, "capture.cameras[0].depth.depth_scale")) << scale;
  // The old inverse convention (units per metre) is refused with the value to write instead.
  const std::string inverse = errorOf(
      "capture:\n  cameras:\n    - {face: 0, backend: aravis, depth: {serial: D, depth_scale: 1000}}\n");
  EXPECT_TRUE(contains(inverse, "capture.cameras[0].depth.depth_scale")) << inverse;
  EXPECT_TRUE(contains(inverse, "metres per raw depth unit")) << inverse;
  EXPECT_TRUE(contains(inverse, "write 0.001")) << inverse;
  const std::string coarse = errorOf(
      "capture:\n  cameras:\n    - {face: 0, backend: aravis, depth: {serial: D, depth_scale: 0.5}}\n");
  EXPECT_TRUE(contains(coarse, "(0, 0.1]")) << coarse;

  const std::string typo =
      errorOf("capture:\n  cameras:\n    - {face: 0, backend: aravis, colour: {serial: A}}\n");
  EXPECT_TRUE(contains(typo, "colour")) << typo;

  const std::string backend = errorOf("capture:\n  cameras:\n    - {face: 0, backend: gige}\n");
  EXPECT_TRUE(contains(backend, "capture.cameras[0].backend")) << backend;
  EXPECT_TRUE(contains(backend, "aravis, v4l2, recording or sim")) << backend;

  const std::string no_stream = errorOf("capture:\n  cameras:\n    - {face: 0, backend: aravis}\n");
  EXPECT_TRUE(contains(no_stream, "capture.cameras[0]")) << no_stream;

  EXPECT_TRUE(contains(errorOf("capture:\n  cameras: []\n"), "1 to 4 cameras"));
  EXPECT_TRUE(contains(errorOf("capture: {}\n"), "capture.cameras"));
}

TEST(CaptureConfig, RecordingBackendThatIsNoRecordingFailsWhenTheSourceIsMade) {
  const CaptureConfig c =
      parse("capture:\n  cameras:\n    - {face: 3, backend: recording, path: /nonexistent/rec}\n");
  ASSERT_EQ(c.cameras.size(), 1u);
  EXPECT_EQ(c.cameras[0].recording_camera, 3);
  EXPECT_THROW(makeSource(c.cameras[0]), InputError);
}

TEST(CaptureConfig, SimulatedBackendNamesASceneAndACamera) {
  const CaptureConfig c = parse(R"(
capture:
  cameras:
    - {face: 0, backend: sim, scene: room, paced: false}
    - {face: 1, backend: sim, scene: room, camera: 3}
)");
  ASSERT_EQ(c.cameras.size(), 2u);
  EXPECT_EQ(c.cameras[0].backend, Backend::Simulated);
  EXPECT_EQ(c.cameras[0].sim_camera, 0);
  EXPECT_FALSE(c.cameras[0].paced);
  EXPECT_EQ(c.cameras[1].sim_camera, 3);
  EXPECT_TRUE(c.cameras[1].paced);
  // Capture does not link the simulation: its sources come from the caller's factory
  // (tests/simulated: SimulatedSource.BuildsTheConfiguredSimCameras).
  EXPECT_THROW(makeSources(c), InputError);

  const std::string bad =
      errorOf("capture:\n  cameras:\n    - {face: 0, backend: sim, scene: room, camera: 7}\n");
  EXPECT_TRUE(contains(bad, "capture.cameras[0].camera")) << bad;
  const std::string streams =
      errorOf("capture:\n  cameras:\n    - {face: 0, backend: sim, scene: room, color: {serial: A}}\n");
  EXPECT_TRUE(contains(streams, "sim camera")) << streams;
}

TEST(CaptureConfig, PairToleranceReachesTwoDeviceCamerasWithItsDefaultStated) {
  const std::string cameras =
      "  cameras:\n    - {face: 0, backend: aravis, color: {serial: C}, depth: {serial: D}}\n"
      "    - {face: 1, backend: v4l2, color: {device: /dev/video0}, depth: {device: /dev/video1}}\n";
  const CaptureConfig defaults = parse("capture:\n" + cameras);
  EXPECT_DOUBLE_EQ(defaults.pair_tolerance_ms, 16.0);
  EXPECT_EQ(defaults.cameras[0].aravis.pair_tolerance, std::chrono::milliseconds(16));
  EXPECT_EQ(defaults.cameras[1].v4l2.pair_tolerance, std::chrono::milliseconds(16));
  const CaptureConfig loose = parse("capture:\n  pair_tolerance_ms: 25\n" + cameras);
  EXPECT_EQ(loose.cameras[0].aravis.pair_tolerance, std::chrono::milliseconds(25));
  EXPECT_EQ(loose.cameras[1].v4l2.pair_tolerance, std::chrono::milliseconds(25));
  const std::string zero = errorOf("capture:\n  pair_tolerance_ms: 0\n" + cameras);
  EXPECT_TRUE(contains(zero, "capture.pair_tolerance_ms")) << zero;
}
