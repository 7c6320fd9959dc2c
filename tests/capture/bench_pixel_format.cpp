// Conversion cost per frame for each camera pixel format at 640x360 and 1280x720: the share of a
// 33 ms frame budget that format conversion takes on the capture thread.
#include <benchmark/benchmark.h>

#include <opencv2/imgcodecs.hpp>
#include <random>
#include <vector>

#include "holo/capture/pixel_format.hpp"

using namespace holo::capture;

namespace {

// A camera-like buffer: seeded noise (so JPEG does not compress to nothing) for raw formats, a
// quality-90 JPEG of a noisy image for MJPG.
std::vector<std::uint8_t> makeBuffer(PixelFormat format, int width, int height) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> byte(0, 255);
  if (format == PixelFormat::MJPEG) {
    cv::Mat image(height, width, CV_8UC3);
    for (auto it = image.begin<cv::Vec3b>(); it != image.end<cv::Vec3b>(); ++it)
      *it = cv::Vec3b(uchar(byte(rng) / 4 + it.pos().x % 192), uchar(it.pos().y % 256), uchar(byte(rng)));
    std::vector<std::uint8_t> jpeg;
    cv::imencode(".jpg", image, jpeg, {cv::IMWRITE_JPEG_QUALITY, 90});
    return jpeg;
  }
  std::vector<std::uint8_t> buffer(static_cast<std::size_t>(width) * static_cast<std::size_t>(height) *
                                   static_cast<std::size_t>(bytesPerPixel(format)));
  for (auto& b : buffer) b = static_cast<std::uint8_t>(byte(rng));
  return buffer;
}

void BM_Convert(benchmark::State& state) {
  const auto format = static_cast<PixelFormat>(state.range(0));
  const int width = static_cast<int>(state.range(1));
  const int height = static_cast<int>(state.range(2));
  const auto buffer = makeBuffer(format, width, height);
  const RawImage raw{buffer.data(), buffer.size(), width, height, 0};
  const bool depth = isDepthFormat(format);
  for (auto _ : state) {
    cv::Mat out = depth ? convertToDepth(format, raw, 0.001) : convertToColour(format, raw);
    benchmark::DoNotOptimize(out.data);
  }
  state.SetLabel(toString(format) + " " + std::to_string(width) + "x" + std::to_string(height));
}

void formats(benchmark::internal::Benchmark* b) {
  for (const auto& name : pixelFormatNames())
    for (auto [w, h] : {std::pair{640, 360}, std::pair{1280, 720}})
      b->Args({static_cast<long>(pixelFormatFromName(name)), w, h});
}

}  // namespace

BENCHMARK(BM_Convert)->Apply(formats)->Unit(benchmark::kMicrosecond);
