// The exhibit's playlist on the simulated museum: entries that do not load are left out and
// reported, the kiosk's pipeline source shows the others in turn (by duration and on NextRelic)
// with a picture on every frame, a reload adds a relic without a restart, the effect plan follows
// the relic on screen (refraction only for glass) and a turntable turns the relic, not the hall.
// Small views and a small panorama keep it quick; no timing is asserted.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#include "holo/core/config.hpp"
#include "holo/core/error.hpp"
#include "holo/core/stopwatch.hpp"
#include "holo/pipeline/exhibit_config.hpp"
#include "holo/pipeline/frame_loop.hpp"
#include "holo/pipeline/installation.hpp"
#include "holo/pipeline/kiosk_frame_source.hpp"
#include "holo/relics/relics.hpp"
#include "holo/simulated/museum_installation.hpp"
#include "shared_data.hpp"

namespace holo::pipeline {
namespace {

namespace fs = std::filesystem;
constexpr int kViewSize = 48;
constexpr int kPanoramaWidth = 128;

// The playlist `relics` (the YAML list's entries, one a line) loaded into the simulated museum.
Installation museumWithPlaylist(const std::string& relics, bool paced = true,
                                const std::string& scene = "museum") {
  const fs::path dir = test::scratchDir("exhibit_playlist");
  const fs::path file = dir / "appliance.yaml";
  std::ofstream(file) << "exhibit:\n  relics:\n" << relics;
  const ConfigNode root = ConfigNode::loadFile(file);
  Installation installation = simulated::museumInstallation(scene, paced, kPanoramaWidth);
  loadPlaylist(root["exhibit"], parseExhibitConfig(root["exhibit"]), installation);
  return installation;
}

bool hasError(const kiosk::FrameReport& report, const std::string& text) {
  return std::any_of(report.errors.begin(), report.errors.end(),
                     [&](const std::string& e) { return e.find(text) != std::string::npos; });
}

kiosk::FrameRequest request(std::int64_t index, std::vector<kiosk::KioskAction> actions = {}) {
  kiosk::FrameRequest r;
  r.index = index;
  r.actions = std::move(actions);
  return r;
}

TEST(ExhibitPlaylist, EntriesThatDoNotLoadAreLeftOutAndReported) {
  const Installation installation = museumWithPlaylist(
      "    - {relic: vase, scale: 0.5, height: 0.1, yaw: 90}\n"
      "    - {relic: no_such_relic.glb}\n"
      "    - {relic: crystal, duration_s: 0}\n"
      "    - {relic: glass-vase, turntable_deg_per_s: 20, crossfade_s: 0}\n");
  ASSERT_EQ(installation.playlist.size(), 2u);
  EXPECT_EQ(installation.playlist[0].name, "vase");
  EXPECT_EQ(installation.playlist[1].name, "glass-vase");
  EXPECT_EQ(installation.playlist[1].index, 3);
  EXPECT_EQ(installation.playlist[1].turntable_deg_per_s, 20.0);
  EXPECT_EQ(installation.relic_name, "vase");
  // Placement: half the fitted size, lifted 10 cm.
  const Bounds3 placed = installation.playlist[0].relic.bounds();
  Model fitted = relics::makeRelic("vase");
  relics::fitOnPedestal(fitted);
  EXPECT_NEAR(placed.extent().y, 0.5f * fitted.bounds().extent().y, 1e-4f);
  EXPECT_NEAR(placed.lo.y, 0.1f, 1e-4f);
  // Entries without a panorama are shown in the museum's own hall: its pixels, shared.
  EXPECT_EQ(installation.playlist[0].panorama.data, installation.panorama.data);
  ASSERT_EQ(installation.exhibit_problems.size(), 2u);
  // Parse problems come first, then the files'.
  EXPECT_NE(installation.exhibit_problems[0].find("entry 2 (crystal)"), std::string::npos);
  EXPECT_NE(installation.exhibit_problems[0].find("exhibit.relics[2].duration_s"), std::string::npos);
  EXPECT_NE(installation.exhibit_problems[1].find("entry 1 (no_such_relic.glb)"), std::string::npos);
  EXPECT_NE(installation.exhibit_problems[1].find("exhibit.relics[1].relic"), std::string::npos);
  EXPECT_NE(installation.exhibit_problems[1].find("no such file"), std::string::npos);
}

TEST(ExhibitPlaylist, APlaylistWithNoEntryThatLoadsFailsNamingTheList) {
  try {
    (void)museumWithPlaylist("    - {relic: missing_a.glb}\n    - {relic: missing_b.glb}\n", false);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.field()).find("exhibit.relics"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("missing_b.glb"), std::string::npos) << e.what();
  }
}

TEST(ExhibitPlaylist, TheKioskSourceShowsEachRelicInTurnWithAPictureOnEveryFrame) {
  Installation installation = museumWithPlaylist(
      "    - {relic: vase, duration_s: 0.01, crossfade_s: 0}\n"
      "    - {relic: broken.glb}\n"
      "    - {relic: glass-vase, duration_s: 0.01, crossfade_s: 0.02}\n"
      "    - {relic: kettle, duration_s: 0.01, turntable_deg_per_s: 90}\n");
  ASSERT_EQ(installation.playlist.size(), 3u);
  kiosk::RenderFrame source =
      pipelineFrameSource(display::DisplayConfig{}, /*headless=*/true, std::move(installation), kViewSize,
                          {.wait_for_next_relic = true, .control = nullptr});
  const auto after = [](const std::string& relic) -> std::string {
    return relic == "vase" ? "glass-vase" : relic == "glass-vase" ? "kettle" : "vase";
  };
  std::vector<std::string> shown;
  for (int i = 0; i < 7; ++i) {
    const kiosk::FrameReport report = source(request(i));
    EXPECT_TRUE(report.presented);
    EXPECT_FALSE(hasError(report, "black frame")) << "frame " << i;
    ASSERT_EQ(report.exhibit_problems.size(), 1u);
    EXPECT_NE(report.exhibit_problems[0].find("entry 1 (broken.glb)"), std::string::npos);
    EXPECT_EQ(report.next_relic, after(report.relic)) << "frame " << i;
    // Every relic's time (10 ms) is up by the next frame: each frame shows the next relic.
    if (!shown.empty()) {
      EXPECT_EQ(report.relic, after(shown.back())) << "frame " << i;
    }
    shown.push_back(report.relic);
  }
  EXPECT_EQ(std::set<std::string>(shown.begin(), shown.end()).size(), 3u);
}

TEST(ExhibitPlaylist, NextRelicAdvancesAndAReloadAddsARelicWithoutARestart) {
  Installation installation = museumWithPlaylist(
      "    - {relic: vase, duration_s: 600}\n"
      "    - {relic: tripod, duration_s: 600}\n");
  auto control = std::make_shared<ExhibitControl>();
  kiosk::RenderFrame source =
      pipelineFrameSource(display::DisplayConfig{}, true, std::move(installation), kViewSize,
                          {.wait_for_next_relic = true, .control = control});
  EXPECT_EQ(source(request(0)).relic, "vase");
  EXPECT_EQ(source(request(1)).relic, "vase");  // ten minutes on show
  kiosk::FrameReport report = source(request(2, {kiosk::KioskAction::NextRelic}));
  EXPECT_EQ(report.relic, "tripod");
  EXPECT_EQ(report.next_relic, "vase");
  // The reload: the same two and a third; the relic on screen stays, the new one comes after it.
  Installation reloaded = museumWithPlaylist(
      "    - {relic: vase, duration_s: 600}\n"
      "    - {relic: tripod, duration_s: 600}\n"
      "    - {relic: sphere, duration_s: 600}\n"
      "    - {relic: gone.glb}\n");
  control->replace(std::move(reloaded.playlist), std::move(reloaded.exhibit_problems));
  report = source(request(3));
  EXPECT_EQ(report.relic, "tripod");
  EXPECT_EQ(report.next_relic, "sphere");
  ASSERT_EQ(report.exhibit_problems.size(), 1u);
  EXPECT_NE(report.exhibit_problems[0].find("gone.glb"), std::string::npos);
  report = source(request(4, {kiosk::KioskAction::NextRelic}));
  EXPECT_EQ(report.relic, "sphere");
  EXPECT_FALSE(hasError(report, "black frame"));
  report = source(request(5, {kiosk::KioskAction::NextRelic}));
  EXPECT_EQ(report.relic, "vase");
}

// The frame loop itself, deterministic, eyes at their default places.
struct StillLoop {
  FrameLoopOptions options = [] {
    FrameLoopOptions o;
    o.view_size = kViewSize;
    o.panorama_width = kPanoramaWidth;
    o.track_eyes = false;
    return o;
  }();
  Installation installation = simulated::installationFor(options);
  cv::Mat panorama = installation.panorama;
  float yaw = installation.panorama_yaw_rad;
  reflect::PanoramaProxy proxy = installation.panorama_proxy;
  FrameLoop loop{options, std::move(installation), nullptr};

  RelicStage stage(const std::string& builtin) const {
    Model relic = relics::makeRelic(builtin);
    relics::fitOnPedestal(relic);
    return buildStage(builtin, relic, panorama, yaw, proxy, &loop.stage());
  }
  std::vector<cv::Mat> views() const {
    std::vector<cv::Mat> out;
    for (const reflect::ViewImages& v : loop.lastResult().views) out.push_back(v.display.clone());
    return out;
  }
  std::vector<cv::Mat> coverage() const {
    std::vector<cv::Mat> out;
    for (const reflect::ViewImages& v : loop.lastResult().views) out.push_back(v.coverage.clone());
    return out;
  }
};

double difference(const std::vector<cv::Mat>& a, const std::vector<cv::Mat>& b) {
  double sum = 0;
  for (std::size_t v = 0; v < a.size() && v < b.size(); ++v) sum += cv::norm(a[v], b[v], cv::NORM_L1);
  return sum;
}

TEST(ExhibitPlaylist, TheEffectPlanIsTheShownRelicsRefractionOnlyForGlass) {
  StillLoop still;
  still.loop.setStage(still.stage("kettle"));
  FrameReport report = still.loop.step();
  EXPECT_EQ(report.refraction_rays, 0u);
  EXPECT_EQ(report.pass_ms[static_cast<std::size_t>(reflect::Pass::Refraction)], 0.0);
  EXPECT_EQ(report.plan.find("Refraction"), std::string::npos) << report.plan;
  const std::vector<cv::Mat> kettle = still.views();

  const RelicStage glass = still.stage("glass-vase");
  EXPECT_EQ(glass.ibl, still.loop.stage().ibl) << "the same hall's IBL is shared, not prefiltered again";
  still.loop.setStage(glass);
  report = still.loop.step();
  EXPECT_GT(report.refraction_rays, 0u);
  EXPECT_GT(report.pass_ms[static_cast<std::size_t>(reflect::Pass::Refraction)], 0.0);
  EXPECT_NE(report.plan.find("Refraction"), std::string::npos) << report.plan;
  EXPECT_GT(report.relic_pixels, 0u);
  EXPECT_GT(difference(kettle, still.views()), 0.0);

  still.loop.setStage(still.stage("vase"));
  report = still.loop.step();
  EXPECT_EQ(report.refraction_rays, 0u);
}

TEST(ExhibitPlaylist, ATurntableTurnsTheRelicNotTheHallAndKeepsItsScenes) {
  StillLoop still;
  still.loop.setStage(still.stage("kettle"));  // not a solid of revolution: a turn shows
  const reflect::RenderScene* scene = &still.loop.renderScene();
  still.loop.setTurn(0.0f);
  still.loop.step();
  const std::vector<cv::Mat> unturned = still.views(), unturned_coverage = still.coverage();
  // Still eyes and a fixed turn: the static passes are reused as without a turntable.
  EXPECT_EQ(still.loop.step().static_reused_views, 4);

  still.loop.setTurn(1.0f);
  const FrameReport turned_report = still.loop.step();
  EXPECT_EQ(turned_report.static_reused_views, 0) << "the eyes moved around the relic";
  const std::vector<cv::Mat> turned = still.views(), turned_coverage = still.coverage();
  EXPECT_EQ(&still.loop.renderScene(), scene) << "the relic's ray scenes are kept";
  EXPECT_GT(difference(unturned, turned), 0.0);
  EXPECT_EQ(still.loop.step().static_reused_views, 4);  // the same turn again

  for (std::size_t v = 0; v < turned.size(); ++v) {
    // The relic's outline turns with it (a kettle's spout and handle swing round).
    EXPECT_GT(cv::norm(unturned_coverage[v], turned_coverage[v], cv::NORM_L1), 0.0) << "view " << v;
    // What shows no relic in either picture stays as it was: the pyramid shows the relic alone.
    const cv::Mat outside = (unturned_coverage[v] == 0.0f) & (turned_coverage[v] == 0.0f);
    cv::Mat a, b;
    unturned[v].copyTo(a, outside);
    turned[v].copyTo(b, outside);
    EXPECT_EQ(cv::norm(a, b, cv::NORM_L1), 0.0) << "view " << v;
    EXPECT_GT(cv::countNonZero(outside), 0);
  }
}

TEST(ExhibitPlaylist, ATexturedKhronosModelFromTheSharedDataPlays) {
  HOLO_REQUIRE_SHARED_DATA("models/khronos_clearcoat_wicker.glb");
  const std::string file = test::sharedData("models/khronos_clearcoat_wicker.glb").string();
  Installation installation = museumWithPlaylist(
      "    - {relic: vase, duration_s: 3600, crossfade_s: 0}\n"
      "    - {relic: '" +
      file + "', fit_relic: true, duration_s: 3600}\n");
  ASSERT_EQ(installation.playlist.size(), 2u) << installation.exhibit_problems.front();
  EXPECT_FALSE(installation.playlist[1].relic.textures.empty());
  kiosk::RenderFrame source =
      pipelineFrameSource(display::DisplayConfig{}, true, std::move(installation), kViewSize,
                          {.wait_for_next_relic = true, .control = nullptr});
  source(request(0));
  // Advanced by NextRelic, not by a duration: how long a frame takes must not decide the relic.
  const kiosk::FrameReport report = source(request(1, {kiosk::KioskAction::NextRelic}));
  EXPECT_EQ(report.relic, file);
  EXPECT_FALSE(hasError(report, "black frame"));
}

// Opt-in (HOLO_PLAYLIST_MEASURE=1): the frame time of a still and of a turning relic and the time
// of a switch, at HOLO_PLAYLIST_VIEW pixels (default 160), printed, not asserted.
TEST(ExhibitPlaylist, MeasureTurntableAndSwitch) {
  if (std::getenv("HOLO_PLAYLIST_MEASURE") == nullptr) GTEST_SKIP() << "set HOLO_PLAYLIST_MEASURE=1";
  const char* view = std::getenv("HOLO_PLAYLIST_VIEW");
  StillLoop still;
  still.loop.setQuality(view ? std::atoi(view) : 160, true);
  constexpr int kFrames = 30;
  for (const std::string relic : {"kettle", "glass-vase"}) {
    Stopwatch build;
    RelicStage stage = still.stage(relic);
    const double build_ms = build.ms();
    Stopwatch swap;
    still.loop.setStage(std::move(stage));
    const double swap_ms = swap.ms();
    for (const bool turning : {false, true}) {
      still.loop.setTurn(turning ? std::optional<float>(0.0f) : std::nullopt);
      still.loop.step();
      double total = 0, render = 0;
      int reused = 0;
      for (int i = 0; i < kFrames; ++i) {
        if (turning) still.loop.setTurn(0.02f * float(i + 1));  // 18 degrees a second at 30 fps
        const FrameReport report = still.loop.step();
        total += report.times.total;
        render += report.times.statics + report.times.dynamic + report.times.composition;
        reused += report.static_reused_views;
      }
      // The whole frame includes simulating the four cameras (deterministic mode).
      std::cout << relic << (turning ? " turning" : " still") << ": reflections " << render / kFrames
                << " ms a frame (whole frame " << total / kFrames << " ms), " << reused << " of "
                << 4 * kFrames << " views reused\n";
    }
    std::cout << relic << ": stage built in " << build_ms << " ms (IBL shared), switched in " << swap_ms
              << " ms\n";
  }
}

// Opt-in (HOLO_PLAYLIST_SOAK_S=SECONDS, e.g. 600): the playlist run in the kiosk's pipeline
// source: an opaque turning relic, a glass one and a textured Khronos model (../shared/data), and a
// broken fourth entry; halfway a reload adds a fifth relic. Every frame's presented picture is read
// back (the headless source's check: its non-black pixel count); printed and held to: no black
// frame, every relic shown, the broken entry reported, the added relic shown after the reload.
TEST(ExhibitPlaylist, Soak) {
  const char* seconds_text = std::getenv("HOLO_PLAYLIST_SOAK_S");
  if (seconds_text == nullptr) GTEST_SKIP() << "set HOLO_PLAYLIST_SOAK_S=600";
  HOLO_REQUIRE_SHARED_DATA("models/khronos_clearcoat_wicker.glb");
  const double seconds = std::atof(seconds_text);
  const char* view = std::getenv("HOLO_PLAYLIST_VIEW");
  const std::string wicker = test::sharedData("models/khronos_clearcoat_wicker.glb").string();
  const std::string playlist =
      "    - {relic: kettle, duration_s: 20, turntable_deg_per_s: 18}\n"
      "    - {relic: glass-vase, duration_s: 20, turntable_deg_per_s: -10}\n"
      "    - {relic: '" +
      wicker +
      "', fit_relic: true, duration_s: 20}\n"
      "    - {relic: missing_relic.glb}\n";
  // Small cameras, as the kiosk process tests run it: simulating four full-size cameras would take
  // the machine's cores from the renderer.
  const fs::path scene = test::scratchDir("exhibit_playlist_scene") / "small_museum.yaml";
  std::ofstream(scene) << "base: museum\ncamera: {width: 160, height: 90, fps: 10}\n";
  Installation installation = museumWithPlaylist(playlist, true, scene.string());
  auto control = std::make_shared<ExhibitControl>();
  kiosk::RenderFrame source =
      pipelineFrameSource(display::DisplayConfig{}, true, std::move(installation),
                          view ? std::atoi(view) : 96, {.wait_for_next_relic = false, .control = control});
  std::int64_t frames = 0, black = 0, switches = 0, other_errors = 0;
  std::set<std::string> shown;
  std::vector<double> frame_ms, switch_frame_ms;
  std::string relic;
  bool reloaded = false;
  std::vector<std::string> problems;
  const auto start = std::chrono::steady_clock::now();
  const auto elapsed = [&] {
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  };
  while (elapsed() < seconds) {
    if (!reloaded && elapsed() > seconds / 2) {
      Installation added =
          museumWithPlaylist(playlist + "    - {relic: sphere, duration_s: 20}\n", true, scene.string());
      control->replace(std::move(added.playlist), std::move(added.exhibit_problems));
      reloaded = true;
    }
    Stopwatch frame;
    const kiosk::FrameReport report = source(request(frames));
    frame_ms.push_back(frame.ms());
    ++frames;
    for (const std::string& e : report.errors)
      (e.find("black frame") != std::string::npos ? black : other_errors)++;
    if (report.relic != relic) {
      if (!relic.empty()) {
        ++switches;
        switch_frame_ms.push_back(frame_ms.back());
      }
      relic = report.relic;
      shown.insert(relic);
    }
    problems = report.exhibit_problems;
  }
  std::sort(frame_ms.begin(), frame_ms.end());
  std::cout << "soak: " << elapsed() << " s, " << frames << " frames, " << black << " black, " << other_errors
            << " other errors, " << switches << " switches, " << shown.size()
            << " relics shown, median frame " << frame_ms[frame_ms.size() / 2] << " ms, max "
            << frame_ms.back() << " ms, switch frames max "
            << (switch_frame_ms.empty() ? 0.0
                                        : *std::max_element(switch_frame_ms.begin(), switch_frame_ms.end()))
            << " ms\n";
  for (const std::string& p : problems) std::cout << "  exhibit_problems: " << p << "\n";
  EXPECT_EQ(black, 0);
  EXPECT_EQ(shown.size(), 4u) << "kettle, glass-vase, wicker, and the sphere added by the reload";
  EXPECT_TRUE(shown.count("sphere"));
  ASSERT_EQ(problems.size(), 1u);
  EXPECT_NE(problems[0].find("entry 3 (missing_relic.glb)"), std::string::npos);
}

}  // namespace
}  // namespace holo::pipeline
