// The cameras' timing in the health status: the skew between the cameras' frames a picture was
// made of, and for two-device cameras the colour/depth frames left unpaired and the last pair's
// skew, in the JSON and in the Prometheus metrics (seconds there), absent when not known.
#include <gtest/gtest.h>

#include "holo/kiosk/health_status.hpp"

namespace holo::kiosk {
namespace {

HealthStatus twoCameras() {
  HealthStatus h;
  CameraHealth a;
  a.name = "cam0";
  a.alive = true;
  a.unpaired = 12;
  a.pair_skew_ms = 15.5;
  CameraHealth b;
  b.name = "cam1";
  b.alive = true;
  h.cameras = {a, b};
  return h;
}

TEST(HealthCameraTiming, SkewAndUnpairedFramesAreInTheJsonAndTheMetrics) {
  HealthStatus h = twoCameras();
  h.camera_skew_ms = 21.25;
  const nlohmann::json j = h.toJson();
  EXPECT_DOUBLE_EQ(j["camera_skew_ms"].get<double>(), 21.25);
  EXPECT_EQ(j["cameras"][0]["unpaired"].get<std::int64_t>(), 12);
  EXPECT_DOUBLE_EQ(j["cameras"][0]["pair_skew_ms"].get<double>(), 15.5);
  EXPECT_EQ(j["cameras"][1]["unpaired"].get<std::int64_t>(), 0);
  const std::string metrics = h.toPrometheus();
  EXPECT_NE(metrics.find("holopyramid_camera_skew_seconds 0.02125\n"), std::string::npos) << metrics;
  EXPECT_NE(metrics.find("holopyramid_camera_unpaired_frames_total{camera=\"cam0\"} 12\n"), std::string::npos)
      << metrics;
  EXPECT_NE(metrics.find("holopyramid_camera_pair_skew_seconds{camera=\"cam0\"} 0.0155\n"), std::string::npos)
      << metrics;
  EXPECT_NE(metrics.find("# TYPE holopyramid_camera_unpaired_frames_total counter\n"), std::string::npos);

  // With fewer than two cameras there is no skew: null in the JSON, no sample in the metrics.
  const HealthStatus unknown = twoCameras();
  EXPECT_TRUE(unknown.toJson()["camera_skew_ms"].is_null());
  EXPECT_EQ(unknown.toPrometheus().find("holopyramid_camera_skew_seconds "), std::string::npos);
}

}  // namespace
}  // namespace holo::kiosk
