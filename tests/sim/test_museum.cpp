#include <gtest/gtest.h>
#include <tbb/global_control.h>
#include <algorithm>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <tuple>
#include <vector>

#include "holo/core/equirect.hpp"
#include "holo/core/error.hpp"
#include "holo/core/image.hpp"
#include "holo/sim/halls.hpp"
#include "holo/sim/museum.hpp"
#include "holo/sim/visitors.hpp"
#include "shared_data.hpp"

namespace holo::sim {
namespace {

SceneDescription small(const std::string& name, int width = 96, int height = 54) {
  SceneDescription d = loadScene(name);
  d.camera.width = width;
  d.camera.height = height;
  return d;
}

bool identical(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0.0;
}

TEST(Museum, SameDescriptionGivesBitIdenticalFrames) {
  const Museum a(small("museum")), b(small("museum"));
  for (int cam = 0; cam < 4; cam += 3) {
    const SimulatedFrame fa = a.renderCamera(cam, 7), fb = b.renderCamera(cam, 7);
    EXPECT_TRUE(identical(fa.frame.colour, fb.frame.colour));
    EXPECT_TRUE(identical(fa.frame.depth, fb.frame.depth));
    EXPECT_TRUE(identical(fa.true_depth, fb.true_depth));
    EXPECT_TRUE(identical(fa.foreground, fb.foreground));
  }
  EXPECT_TRUE(identical(a.renderPanorama(64, 32), b.renderPanorama(64, 32)));
}

// Rows are split between threads however oneTBB likes; the pixels must not care.
TEST(Museum, OneThreadGivesTheSameFrames) {
  const Museum m(small("museum"));
  const SimulatedFrame parallel = m.renderCamera(1, 12);
  const cv::Mat pano = m.renderPanorama(64, 32);
  const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  const SimulatedFrame serial = m.renderCamera(1, 12);
  EXPECT_TRUE(identical(parallel.frame.colour, serial.frame.colour));
  EXPECT_TRUE(identical(parallel.frame.depth, serial.frame.depth));
  EXPECT_TRUE(identical(pano, m.renderPanorama(64, 32)));
}

TEST(Museum, DifferentSeedsDiffer) {
  SceneDescription d = small("museum");
  const Museum a(d);
  d.seed = 2;
  const Museum b(d);
  EXPECT_NE(a.visitorHeads(0)[0], b.visitorHeads(0)[0]);
  // Same visitors aside, the sensor noise itself differs with the seed.
  const RgbdFrame ba = a.backgroundFrame(0), bb = b.backgroundFrame(0);
  EXPECT_FALSE(identical(ba.depth, bb.depth));
}

TEST(Museum, FramesAreValidRgbdFrames) {
  const Museum m(small("museum"));
  const SimulatedFrame f = m.renderCamera(2, 3);
  EXPECT_NO_THROW(f.frame.validate());
  EXPECT_EQ(f.frame.camera_id, 2);
  EXPECT_EQ(f.frame.sequence, 3u);
  EXPECT_EQ(f.frame.device_time.count(), 100'000'000);  // frame 3 at 30 fps
  EXPECT_EQ(f.true_depth.type(), CV_32FC1);
  EXPECT_EQ(f.foreground.type(), CV_8UC1);
  EXPECT_GT(cv::countNonZero(f.true_depth), f.true_depth.total() * 9 / 10);  // a closed hall
}

// Camera 1 looks along +X at the gallery's east wall (x = 8): where a pixel's ray reaches that
// wall unobstructed (above the bench, between the paintings), the true depth is analytic.
TEST(Museum, TrueDepthMatchesAnalyticWall) {
  SceneDescription d = small("empty", 160, 90);
  const Museum m(d);
  const SimulatedFrame f = m.renderCamera(1, 0, false);
  const CameraModel& cam = m.camera(1);
  int checked = 0;
  for (int y = 0; y < cam.height(); ++y)
    for (int x = 0; x < cam.width(); ++x) {
      const Ray ray = cam.ray({float(x), float(y)});
      if (ray.direction.x <= 0.0f || ray.direction.y <= 0.02f) continue;
      const float t = (8.0f - ray.origin.x) / ray.direction.x;
      const vec3 p = ray.origin + t * ray.direction;
      if (std::abs(p.z) > 2.0f || p.y > 3.0f) continue;
      const float z = glm::dot(p - cam.position(), vec3(cam.T_world_camera()[2]));  // camera-frame depth
      EXPECT_NEAR(f.true_depth.at<float>(y, x), z, 1e-3f * z) << x << "," << y;
      ++checked;
    }
  EXPECT_GT(checked, 300);
}

TEST(Museum, ForegroundMaskIsWhereVisitorsAre) {
  SceneDescription d = small("museum", 160, 90);
  const Museum m(d);
  int with_people = 0;
  for (int cam = 0; cam < 4; ++cam) {
    const SimulatedFrame f = m.renderCamera(cam, 0);
    const SimulatedFrame empty = m.renderCamera(cam, 0, false);
    EXPECT_EQ(cv::countNonZero(empty.foreground), 0);
    // Foreground pixels are nearer than the empty hall behind them; background pixels are not.
    for (int y = 0; y < f.foreground.rows; ++y)
      for (int x = 0; x < f.foreground.cols; ++x) {
        const float zf = f.true_depth.at<float>(y, x), ze = empty.true_depth.at<float>(y, x);
        if (f.foreground.at<std::uint8_t>(y, x)) {
          if (zf > 0 && ze > 0) {
            EXPECT_LT(zf, ze);
          }
        } else {
          EXPECT_EQ(zf, ze);
        }
      }
    // A visitor whose head projects into this camera shows up in its mask near that pixel's column.
    for (const vec3& head : m.visitorHeads(0)) {
      float depth = 0;
      const auto px = m.camera(cam).project(head, &depth);
      if (!px || depth <= 0.3f || px->x < 2 || px->y < 2 || px->x > 157 || px->y > 87) continue;
      const cv::Rect window(int(px->x) - 2, int(px->y) - 2, 5, 5);
      if (cv::countNonZero(f.foreground(window)) > 0) ++with_people;
    }
  }
  EXPECT_GE(with_people, 1);
}

TEST(Museum, VisitorsWalkAroundThePyramidOutsideTheBase) {
  const Museum m(small("atrium"));
  for (int frame = 0; frame < 300; frame += 25)
    for (const vec3& head : m.visitorHeads(frame)) {
      const float r = std::hypot(head.x, head.z);
      EXPECT_GT(r, 1.0f);
      EXPECT_LT(r, 3.5f);
      EXPECT_GT(head.y, 0.3f);  // 1.55-1.9 m tall, floor at -1
    }
  // They move: a walker stands still for at most 3.7 s of its pace cycle, so within 10 s every
  // head gets well away from where it started.
  const auto start = m.visitorHeads(0);
  std::vector<float> farthest(start.size(), 0.0f);
  for (int frame = 0; frame <= 300; frame += 10) {
    const auto now = m.visitorHeads(frame);
    for (std::size_t i = 0; i < start.size(); ++i)
      farthest[i] = std::max(farthest[i], glm::length(now[i] - start[i]));
  }
  for (std::size_t i = 0; i < start.size(); ++i) EXPECT_GT(farthest[i], 1.0f) << "visitor " << i;
}

// The bodies model: once per pace cycle a walker stops: the feet stay put, the body turns to face
// the pyramid's axis and leans towards it, the legs stand together; then it walks on along its lane.
TEST(Museum, BodiesStopTurnToThePyramidAndWalkOn) {
  const auto plans = planVisitors(3, 7, "atrium", VisitorModel::bodies);
  for (const VisitorPlan& plan : plans) {
    int standing = 0, walking = 0;
    for (int frame = 0; frame < 900; ++frame) {  // 30 s, at least one pace cycle
      const float t = static_cast<float>(frame) / 30.0f;
      const VisitorPose pose = poseAt(plan, t), next = poseAt(plan, t + 1.0f / 30.0f);
      const vec3 inward = -glm::normalize(vec3(pose.feet.x, 0.0f, pose.feet.z));
      if (pose.facing_pyramid == 1.0f) {
        ++standing;
        if (next.facing_pyramid == 1.0f) {
          EXPECT_LT(glm::length(next.feet - pose.feet), 1e-4f) << t;
        }
        EXPECT_NEAR(glm::dot(pose.forward, inward), 1.0f, 1e-5f) << t;
        EXPECT_EQ(pose.swing, 0.0f) << t;
        EXPECT_GT(pose.lean, 0.05f) << t;
      } else if (pose.facing_pyramid == 0.0f) {
        ++walking;
        EXPECT_LT(std::abs(glm::dot(pose.forward, inward)), 1e-4f) << t;
        EXPECT_GT(glm::length(next.feet - pose.feet), 1e-3f) << t;
      }
    }
    EXPECT_GT(standing, 30) << "stands at least a second";
    EXPECT_GT(walking, 300) << "walks most of the time";
  }
}

// The bodies: ~5k triangles per visitor in smooth closed parts, the lower foot on the floor, the
// same mesh for the same time.
TEST(Museum, VisitorBodiesAreClosedAndStandOnTheFloor) {
  const auto plans = planVisitors(4, 11, "gallery", VisitorModel::bodies);
  for (float t : {0.0f, 1.3f, 7.9f}) {
    const Model people = buildVisitors(plans, t);
    EXPECT_GE(people.triangleCount(), 4u * 4500u);
    EXPECT_LE(people.triangleCount(), 4u * 6000u);
    std::vector<float> lowest(plans.size(), 1e9f);
    for (const TriangleMesh& mesh : people.meshes) {
      const std::size_t who = std::stoul(mesh.name.substr(7));  // "visitor<i>_<part>"
      for (const vec3& v : mesh.positions) lowest[who] = std::min(lowest[who], v.y);
      // Closed: with the seams' duplicated vertices welded, every edge has exactly two triangles.
      std::map<std::tuple<float, float, float>, unsigned> weld;
      std::vector<unsigned> id(mesh.positions.size());
      for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
        const vec3 q = glm::round(mesh.positions[i] * 1e5f);
        id[i] =
            weld.emplace(std::make_tuple(q.x, q.y, q.z), static_cast<unsigned>(weld.size())).first->second;
      }
      std::map<std::pair<unsigned, unsigned>, int> edges;
      for (const uvec3& tri : mesh.triangles) {
        const unsigned v[3] = {id[tri[0]], id[tri[1]], id[tri[2]]};
        if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) continue;  // a closing point's fan
        for (int e = 0; e < 3; ++e) ++edges[{std::min(v[e], v[(e + 1) % 3]), std::max(v[e], v[(e + 1) % 3])}];
      }
      int open = 0;
      for (const auto& [edge, count] : edges) open += count != 2;
      EXPECT_EQ(open, 0) << mesh.name << " at " << t;
    }
    for (float y : lowest) EXPECT_NEAR(y, -kBaseHeight, 0.005f) << t;
    const Model again = buildVisitors(plans, t);
    ASSERT_EQ(again.meshes.size(), people.meshes.size());
    for (std::size_t i = 0; i < people.meshes.size(); ++i)
      EXPECT_EQ(again.meshes[i].positions, people.meshes[i].positions);
  }
}

// The bodies are the default; a scene file or the description picks the figures, which share the
// bodies' lanes and clothes but not their pace; a bad name is an error naming the field.
TEST(Museum, VisitorModelComesFromTheScene) {
  EXPECT_EQ(loadScene("museum").visitor_model, VisitorModel::bodies);
  EXPECT_EQ(SceneDescription{}.visitor_model, VisitorModel::bodies);
  const auto a = planVisitors(3, 1, "gallery", VisitorModel::figures), b = planVisitors(3, 1, "gallery");
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].lane_radius, b[i].lane_radius);
    EXPECT_EQ(a[i].shirt, b[i].shirt);
    EXPECT_EQ(a[i].carried, b[i].carried);
    EXPECT_NE(a[i].angular_speed, b[i].angular_speed);
  }
  const Model few = buildVisitors(a, 1.0f), many = buildVisitors(b, 1.0f);
  EXPECT_LT(few.triangleCount(), 3u * 1500u);
  EXPECT_GT(many.triangleCount(), 3u * 4500u);

  const auto dir = test::scratchDir("sim_visitor_model");
  std::ofstream(dir / "figures.yaml") << "base: museum\nvisitor_model: figures\nclose_visitors: 1\n";
  const SceneDescription figures = loadScene((dir / "figures.yaml").string());
  EXPECT_EQ(figures.visitor_model, VisitorModel::figures);
  EXPECT_EQ(Museum(figures).visitors(0).triangleCount(),
            buildVisitors(
                [&] {
                  auto plans = planVisitors(3, 1, "gallery", VisitorModel::figures);
                  plans.push_back(planCloseVisitors(1, 1, "gallery", VisitorModel::figures)[0]);
                  return plans;
                }(),
                0.0f)
                .triangleCount());
  std::ofstream(dir / "bad.yaml") << "base: museum\nvisitor_model: robots\n";
  try {
    loadScene((dir / "bad.yaml").string());
    ADD_FAILURE() << "robots accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("visitor_model"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("robots"), std::string::npos) << e.what();
  }
}

// The gallery's east wall (+X) is blue and its west wall (-X) red; a ceiling lamp hangs at
// x = 1, y = 3.5, z = 0. Each must appear where core/equirect.hpp says.
TEST(Museum, PanoramaFollowsTheEquirectConvention) {
  const Museum m(small("empty"));
  const int W = 256, H = 128;
  const cv::Mat pano = m.renderPanorama(W, H);
  auto at = [&](const vec3& direction) {
    const vec2 uv = equirect::directionToUv(glm::normalize(direction));
    return rgbAt(pano, std::min(int(uv.x * W), W - 1), std::min(int(uv.y * H), H - 1));
  };
  const vec3 east = at({1, 0, 0}), west = at({-1, 0, 0});
  EXPECT_GT(east.b, 3.0f * east.r);
  EXPECT_GT(west.r, 3.0f * west.b);
  const vec3 lamp = at(vec3(1.0f, 3.49f, 0.0f) - m.description().panorama_position);
  EXPECT_GT(luminance(lamp), 20.0f);
  // Next to the lamp, the ceiling is dim.
  EXPECT_LT(luminance(at(vec3(2.0f, 3.49f, 0.0f) - m.description().panorama_position)), 1.0f);
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) ASSERT_TRUE(isFinite(rgbAt(pano, x, y)));
}

TEST(Museum, EveryBuiltinSceneRenders) {
  for (const auto& name : builtinSceneNames()) {
    SCOPED_TRACE(name);
    const Museum m(small(name, 48, 27));
    EXPECT_GT(m.relic().triangleCount(), 100u);
    const Bounds3 b = m.relic().bounds();
    EXPECT_NEAR(b.lo.y, 0.0f, 1e-4f);
    EXPECT_LE(b.hi.y, 0.2801f);
    const SimulatedFrame f = m.renderCamera(0, 0);
    EXPECT_GT(cv::mean(f.frame.colour)[0] + cv::mean(f.frame.colour)[1] + cv::mean(f.frame.colour)[2], 10.0);
  }
}

// Every hall has a strongly coloured object (one channel at least 3x another) within 1 m of the
// pyramid axis, outside the base: something for the relic to reflect up close.
TEST(Halls, StronglyColouredObjectsNearThePyramid) {
  for (const std::string hall : {"room", "gallery", "atrium"}) {
    SCOPED_TRACE(hall);
    const Model m = makeHall(hall);
    bool found = false;
    for (const auto& mesh : m.meshes) {
      const vec3 e = m.materials[static_cast<std::size_t>(mesh.material)].emission;
      const float hi = std::max({e.r, e.g, e.b}), lo = std::min({e.r, e.g, e.b});
      if (hi < 0.2f || hi < 3.0f * lo) continue;
      for (const vec3& p : mesh.positions) {
        const float r = std::hypot(p.x, p.z);
        if (r < 1.0f && r > kBaseHalfWidth * 1.5f) found = true;
      }
    }
    EXPECT_TRUE(found);
  }
  EXPECT_TRUE(makeHall("none").meshes.empty());
  EXPECT_THROW(makeHall("cellar"), InputError);
}

TEST(Museum, UnknownSceneNameListsTheNames) {
  try {
    loadScene("no-such-scene");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("museum"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("no-such-scene"), std::string::npos);
  }
}

}  // namespace
}  // namespace holo::sim
