// The frame renderer's composition pass (internal): psi_f = psi_d w + psi_s (1 - w) per sample
// (composition.hpp) plus the diffuse, averaged over each pixel's samples. Where a sample has
// material layers (refraction_pass.hpp) two more terms of the same form are added: the clearcoat
// (its scale times the same foreground over its own environment) and the transmitted light (its
// scale times the foreground its exit ray met, weight w_t, over the IBL behind).
#pragma once

#include <cstddef>
#include <vector>

#include <opencv2/core.hpp>

#include "holo/reflect/foreground_pyramid.hpp"
#include "holo/reflect/hit_points.hpp"
#include "holo/reflect/prefiltered_ibl.hpp"
#include "refraction_pass.hpp"

namespace holo::reflect {

// psi_f of pixel p: the mean over its samples of the composed specular plus the diffuse, misses
// black (so coverage is built in); `weight` gets the mean foreground weight, in [0, 1]. fg (per
// entry of hits.hits) null: no foreground anywhere (w = 0, the static image). layers null: no
// sample has material layers; their transmitted_fg is read only with fg and when it is sized.
vec3 composePixel(const HitPointBuffer& hits, const std::vector<SplitSumShading>& shading,
                  const std::vector<ForegroundSample>* fg, std::size_t p, float& weight,
                  const LayerBuffers* layers = nullptr);

// Rewrites the static image (hdr) at the covered pixels some of whose samples have layers.
void composeLayeredStatic(const HitPointBuffer& hits, const std::vector<SplitSumShading>& shading,
                          const LayerBuffers& layers, cv::Mat& hdr);

// Writes composePixel into hdr and weight (view-sized CV_32FC3 / CV_32FC1, holding the static
// image and zero weights) at the covered pixels where some sample's foreground weight is > 0,
// leaving every other pixel as it is; with exposure > 0 also tone-maps those pixels into display
// (CV_8UC3). Returns the number of pixels written. With layers, a pixel whose exit rays met
// foreground is composed too.
std::size_t composeForeground(const HitPointBuffer& hits, const std::vector<SplitSumShading>& shading,
                              const std::vector<ForegroundSample>& fg, float exposure, cv::Mat& hdr,
                              cv::Mat& weight, cv::Mat& display, const LayerBuffers* layers = nullptr);

}  // namespace holo::reflect
