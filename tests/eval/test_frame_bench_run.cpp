// `bench frame` taken a frame at a time (FrameBenchRun): two runs whose frames alternate, as bench
// scaling's threads sweep runs its points, each show exactly the pictures the run shows alone.
#include <gtest/gtest.h>

#include <fstream>

#include "holo/eval/frame_benchmark.hpp"
#include "shared_data.hpp"

namespace fs = std::filesystem;
using holo::eval::FrameBenchmark;
using holo::eval::FrameBenchOptions;
using holo::eval::FrameBenchRun;

namespace {

FrameBenchOptions smallMuseum(const fs::path& dir) {
  const fs::path scene = dir / "small_museum.yaml";
  std::ofstream(scene)
      << "base: museum\ncamera: {width: 160, height: 96, hfov_deg: 110, vfov_deg: 70, fps: 30}\n";
  FrameBenchOptions options;
  options.loop.scene = scene.string();
  options.loop.view_size = 32;
  options.loop.overlap = false;
  options.warmup = 1;
  options.frames = 3;
  options.digest = true;
  return options;
}

}  // namespace

TEST(FrameBenchRun, RunsWhoseFramesAlternateEachShowWhatTheyShowAlone) {
  const FrameBenchOptions options = smallMuseum(holo::test::scratchDir("eval_frame_bench_run"));
  const FrameBenchmark alone = holo::eval::benchFrame(options);
  ASSERT_TRUE(alone.display_digest.has_value());

  FrameBenchRun first(options), second(options);
  for (int i = 0; i < options.frames; ++i) {
    first.measureFrame();
    second.measureFrame();
  }
  for (FrameBenchRun* run : {&first, &second}) {
    const FrameBenchmark b = run->finish();
    ASSERT_TRUE(b.display_digest.has_value());
    EXPECT_EQ(*b.display_digest, *alone.display_digest);
    EXPECT_EQ(b.reports.size(), static_cast<std::size_t>(options.frames));
    EXPECT_EQ(b.frame_cpu_ms.size(), static_cast<std::size_t>(options.frames));
    EXPECT_GT(b.floor_ms, 0.0);
  }
}
