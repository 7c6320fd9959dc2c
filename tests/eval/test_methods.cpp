// The method factory: every IBL knob reaches the map the view is shaded with.
#include <gtest/gtest.h>

#include "holo/core/error.hpp"
#include "holo/eval/methods.hpp"
#include "holo/eval/reflection_scene.hpp"
#include "holo/sim/halls.hpp"
#include "holo/simulated/museum_installation.hpp"

namespace holo::eval {
namespace {

// The kettle (rough, 0.35: it reads the map's rough levels, whose width the density sets) alone in
// the empty hall (its rendered panorama), a 32-pixel view of face 0.
SceneOptions kettleAlone() {
  SceneOptions options;
  options.relic = "kettle";
  return options;
}

ViewOptions smallView() {
  ViewOptions view;
  view.width = view.height = 32;
  return view;
}

struct SmallScene {
  ReflectionScene scene = loadReflectionScene(kettleAlone());
  CameraModel camera = viewCamera(smallView(), scene);
};

const SmallScene& smallScene() {
  static const SmallScene s;
  return s;
}

cv::Mat renderAtDensity(const std::string& method, int texel_density) {
  MethodSettings settings;
  settings.ibl_levels = 4;
  settings.ibl_texel_density = texel_density;
  return renderMethod(method, smallScene().scene, smallScene().camera, settings).image;
}

class IblMethods : public ::testing::TestWithParam<std::string> {};

TEST_P(IblMethods, TheTexelDensityChangesTheImage) {
  const cv::Mat coarse = renderAtDensity(GetParam(), 2);
  const cv::Mat fine = renderAtDensity(GetParam(), 40);
  ASSERT_EQ(coarse.size(), cv::Size(32, 32));
  ASSERT_GT(cv::norm(fine, cv::NORM_L1), 0.0) << "the relic is not in the view";
  EXPECT_GT(cv::norm(coarse, fine, cv::NORM_L1), 1e-3 * cv::norm(fine, cv::NORM_L1));
  // The same density twice renders the same image: the difference is the knob's.
  EXPECT_EQ(cv::norm(fine, renderAtDensity(GetParam(), 40), cv::NORM_L1), 0.0);
}

INSTANTIATE_TEST_SUITE_P(Methods, IblMethods, ::testing::Values("ibl", "ibl-baseline"));

TEST(RenderMethod, AnUnknownMethodIsAnInputError) {
  EXPECT_THROW(renderMethod("raytrace", smallScene().scene, smallScene().camera, {}), InputError);
}

// The live renderers read a hall's panorama where the hall is (its mean distance, about 4 m in the
// gallery, and the pyramid's base below the relic); a panorama with no hall stays at infinity, and
// --panorama-at-infinity puts a hall's there too.
TEST(ReflectionScene, AHallPlacesItsPanoramaAtTheHallsDistance) {
  SceneOptions options;
  options.scene = "gallery";
  options.relic = "vase";
  const reflect::PanoramaProxy proxy = loadReflectionScene(options).panorama_proxy;
  ASSERT_FALSE(proxy.infinite());
  EXPECT_GT(proxy.radius, 3.0f);
  EXPECT_LT(proxy.radius, 6.0f);
  EXPECT_EQ(proxy.base_half_width, sim::kBaseHalfWidth);

  options.panorama_at_infinity = true;
  const reflect::PanoramaProxy at_infinity = loadReflectionScene(options).panorama_proxy;
  EXPECT_TRUE(at_infinity.infinite());
  EXPECT_EQ(at_infinity.base_half_width, 0.0f);
  EXPECT_TRUE(smallScene().scene.panorama_proxy.infinite());
}

// The live simulated museum reads the hall where the evaluations measure it: the same proxy for
// the same scene.
TEST(ReflectionScene, TheLiveSimulatedInstallationReadsThePanoramaThroughTheSameProxy) {
  SceneOptions options;
  options.scene = "gallery";
  options.relic = "vase";
  const reflect::PanoramaProxy evaluated = loadReflectionScene(options).panorama_proxy;
  const reflect::PanoramaProxy live =
      simulated::museumInstallation(options.scene, /*paced=*/false, 64, options.relic).panorama_proxy;
  ASSERT_FALSE(live.infinite());
  EXPECT_EQ(live.radius, evaluated.radius);
  EXPECT_EQ(live.centre, evaluated.centre);
  EXPECT_EQ(live.base_half_width, 0.3f);
  EXPECT_EQ(live.base_half_width, evaluated.base_half_width);
}

}  // namespace
}  // namespace holo::eval
