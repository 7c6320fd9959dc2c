#include "compose_pass.hpp"

#include <algorithm>
#include <atomic>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include "holo/core/image.hpp"
#include "holo/reflect/composition.hpp"
#include "holo/reflect/tone_map.hpp"

namespace holo::reflect {

vec3 composePixel(const HitPointBuffer& hits, const std::vector<SplitSumShading>& shading,
                  const std::vector<ForegroundSample>* fg, std::size_t p, float& weight,
                  const LayerBuffers* layers) {
  const std::size_t first = hits.firstSample(p);
  const bool transmitted_fg = fg && layers && layers->transmitted_fg.size() == hits.hits.size();
  const int count = hits.sampleCount(p);
  vec3 sum(0.0f);
  float wsum = 0.0f;
  for (std::size_t i = first; i < first + std::size_t(count); ++i) {
    if (!hits.valid[i]) continue;
    const SplitSumShading& sh = shading[i];
    const vec3 psi_s = sh.specular_scale * sh.environment;
    const float w = fg ? (*fg)[i].weight : 0.0f;
    const vec3 psi_d = fg ? sh.specular_scale * (*fg)[i].radiance : vec3(0.0f);
    sum += composeReflection(psi_d, psi_s, w) + composeReflection(sh.diffuse, vec3(0.0f), 1.0f);
    wsum += w;
    if (layers && layers->layered[i]) {
      const SampleLayers& l = layers->layers[i];
      const vec3 fg_radiance = fg ? (*fg)[i].radiance : vec3(0.0f);
      sum += composeReflection(l.coat_scale * fg_radiance, l.coat_scale * l.coat_environment, w);
      const ForegroundSample seen = transmitted_fg ? layers->transmitted_fg[i] : ForegroundSample{};
      sum += composeReflection(l.transmit_scale * seen.radiance, l.transmit_scale * l.transmit_environment,
                               seen.weight);
    }
  }
  const float inv = 1.0f / float(count);
  weight = std::clamp(wsum * inv, 0.0f, 1.0f);
  return sum * inv;
}

void composeLayeredStatic(const HitPointBuffer& hits, const std::vector<SplitSumShading>& shading,
                          const LayerBuffers& layers, cv::Mat& hdr) {
  const std::size_t w = std::size_t(hits.width);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, hits.covered.size(), 256),
                    [&](const tbb::blocked_range<std::size_t>& r) {
                      for (std::size_t k = r.begin(); k < r.end(); ++k) {
                        const std::size_t p = hits.covered[k];
                        const std::size_t first = hits.firstSample(p);
                        bool layered = false;
                        for (std::size_t i = first; i < first + std::size_t(hits.sampleCount(p)); ++i)
                          layered = layered || (hits.valid[i] && layers.layered[i]);
                        if (!layered) continue;
                        float weight = 0.0f;
                        setRgb(hdr, int(p % w), int(p / w),
                               composePixel(hits, shading, nullptr, p, weight, &layers));
                      }
                    });
}

std::size_t composeForeground(const HitPointBuffer& hits, const std::vector<SplitSumShading>& shading,
                              const std::vector<ForegroundSample>& fg, float exposure, cv::Mat& hdr,
                              cv::Mat& weight_image, cv::Mat& display, const LayerBuffers* layers) {
  const bool transmitted_fg = layers && layers->transmitted_fg.size() == hits.hits.size();
  const std::size_t w = std::size_t(hits.width);
  std::atomic<std::size_t> composed{0};
  const std::vector<std::uint32_t>& covered = hits.covered;
  tbb::parallel_for(
      tbb::blocked_range<std::size_t>(0, covered.size(), 256), [&](const tbb::blocked_range<std::size_t>& r) {
        std::size_t local = 0;
        for (std::size_t k = r.begin(); k < r.end(); ++k) {
          const std::size_t p = covered[k];
          const int x = int(p % w), y = int(p / w);
          const std::size_t first = hits.firstSample(p);
          bool reached = false;
          for (std::size_t i = first; i < first + std::size_t(hits.sampleCount(p)); ++i)
            reached =
                reached || fg[i].weight > 0.0f || (transmitted_fg && layers->transmitted_fg[i].weight > 0.0f);
          if (!reached) continue;
          float weight = 0.0f;
          const vec3 c = composePixel(hits, shading, &fg, p, weight, layers);
          setRgb(hdr, x, y, c);
          weight_image.at<float>(y, x) = weight;
          if (exposure > 0.0f) display.at<cv::Vec3b>(y, x) = toneMapPixel(c, exposure);
          ++local;
        }
        composed += local;
      });
  return composed;
}

}  // namespace holo::reflect
