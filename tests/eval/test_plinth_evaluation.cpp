// The virtual plinth under the relic (core/plinth.hpp) and the transmissive relic's caustic on it
// in the live views (reflect/caustic_tracer.hpp): a scene file's plinth section is checked; the
// effect plan runs the caustic only for a transmissive relic over a plinth (counters 0 otherwise);
// on a glass sphere on a plinth under a small lamp (eval/plinth_evaluation.hpp) the live view's
// plinth is measured against the path-traced truth, and switching the caustic off, or the shadow
// and the caustic, makes its error worse. CI size: a 40^2 view, 96 spp of truth.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "holo/core/error.hpp"
#include "holo/core/stats.hpp"
#include "holo/eval/caustic_evaluation.hpp"
#include "holo/eval/methods.hpp"
#include "holo/eval/plinth_evaluation.hpp"
#include "holo/reflect/frame_renderer.hpp"
#include "holo/sim/museum.hpp"

namespace holo::eval {
namespace {

namespace fs = std::filesystem;

TEST(Plinth, SceneFileFieldsAreChecked) {
  const fs::path file = fs::temp_directory_path() / ("holo_plinth_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(file) << "base: empty\nrelic: glass-vase\nplinth: {half_width: 0.2, albedo: 0.5}\n";
  const sim::SceneDescription good = sim::loadScene(file.string());
  ASSERT_TRUE(good.plinth);
  EXPECT_FLOAT_EQ(good.plinth->half_width, 0.2f);
  EXPECT_FLOAT_EQ(good.plinth->albedo.y, 0.5f);
  EXPECT_FALSE(sim::loadScene("empty").plinth);  // default off
  std::ofstream(file) << "base: empty\nplinth: {half_width: 0.2, albedo: 7}\n";
  try {
    (void)sim::loadScene(file.string());
    ADD_FAILURE() << "an albedo of 7 was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), file.string());
    EXPECT_EQ(e.field().substr(0, e.field().find(" (line ")), "plinth.albedo");
  }
  fs::remove(file);
}

struct Frame {
  reflect::FrameResult result;
  std::int64_t live_photons = 0;  // the counter "Caustics/Live photons traced" over the frame
};

Frame renderSphere(bool glass, bool plinth) {
  PlinthEvaluationOptions o;
  ReflectionScene scene = plinthScene(o);
  if (!glass) scene.relic = causticSphere(CausticScene{}, true);
  const reflect::RenderScene rs(scene.relic, {});
  MethodSettings ms;
  const auto ibl = staticIbl(scene, ms);
  reflect::TracerSettings t;
  if (plinth) t.plinth = scene.plinth;
  t.caustic_photons = 4096;
  reflect::FrameRenderer renderer(rs, *ibl, t);
  auto& counter = stats::counter("Caustics/Live photons traced");
  const std::int64_t before = counter.load();
  Frame f;
  f.result = renderer.render({}, {}, {plinthCamera(scene, 24)});
  f.live_photons = counter.load() - before;
  return f;
}

TEST(Plinth, PlanRunsTheCausticOnlyForATransmissiveRelicOverAPlinth) {
  const Frame glass = renderSphere(true, true);
  EXPECT_TRUE(glass.result.plan.has(reflect::Pass::Plinth));
  EXPECT_TRUE(glass.result.plan.has(reflect::Pass::Caustics)) << glass.result.plan.describe();
  EXPECT_EQ(glass.result.caustic_photons_traced, 4096u);
  EXPECT_GT(glass.result.caustic_photons_stored, 0u);
  EXPECT_EQ(glass.live_photons, 4096);
  EXPECT_GT(glass.result.views.at(0).plinth_pixels, 0u);

  const Frame opaque = renderSphere(false, true);
  EXPECT_TRUE(opaque.result.plan.has(reflect::Pass::Plinth));
  EXPECT_FALSE(opaque.result.plan.has(reflect::Pass::Caustics)) << opaque.result.plan.describe();
  EXPECT_EQ(opaque.result.caustic_photons_traced, 0u);
  EXPECT_EQ(opaque.live_photons, 0);
  EXPECT_GT(opaque.result.plinth_shadow_rays, 0u);

  const Frame none = renderSphere(true, false);
  EXPECT_FALSE(none.result.plan.has(reflect::Pass::Plinth));
  EXPECT_FALSE(none.result.plan.has(reflect::Pass::Caustics));
  EXPECT_EQ(none.live_photons, 0);
  EXPECT_EQ(none.result.plinth_shadow_rays, 0u);
  EXPECT_EQ(none.result.views.at(0).plinth_pixels, 0u);
}

TEST(Plinth, CausticAndShadowBringThePlinthCloserToTheTruth) {
  PlinthEvaluationOptions o;
  o.size = 40;
  o.truth_spp = 96;
  o.caustic_photons = 1u << 18;
  const PlinthEvaluation e = evaluatePlinth(o);
  ASSERT_GT(e.plinth_pixels, 200);
  ASSERT_GT(e.caustic_pixels, 0);
  RecordProperty("plinth_error", std::to_string(e.error));
  RecordProperty("plinth_error_no_caustic", std::to_string(e.error_no_caustic));
  RecordProperty("plinth_error_unshadowed", std::to_string(e.error_unshadowed));
  // Switching the caustic off makes the plinth measurably worse, over the caustic most of all.
  EXPECT_LT(e.error, 0.8 * e.error_no_caustic);
  EXPECT_LT(e.caustic_error, 0.5 * e.caustic_error_no_caustic);
  // Without the relic's shadow too, worse still than with it.
  EXPECT_LT(e.error, e.error_unshadowed);
}

}  // namespace
}  // namespace holo::eval
