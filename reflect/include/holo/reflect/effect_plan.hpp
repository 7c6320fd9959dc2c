// The frame renderer's effect plan: which passes a frame runs, derived from the scene before any
// work is done, so a disabled or pointless effect costs nothing. The foreground passes (voxel
// grid, pyramids, voxel walk, composition) run only when there is foreground near the relic, a
// camera to read it from, a relic material glossy enough to reflect it, and the effect is on.
#pragma once

#include <string>
#include <vector>

#include "holo/core/math.hpp"

namespace holo::reflect {

enum class Pass {
  VoxelGrid,           // bin the foreground cloud
  Pyramids,            // Kawase colour and mask pyramids per camera
  RoughForegroundMap,  // the visitors prefiltered around the relic, for its roughest materials
  HitPoints,           // primary rays against the relic (psi_r, coverage)
  StaticReflections,   // prefiltered IBL (psi_s) and diffuse
  ForegroundWalk,      // voxel walk + pyramid reads (psi_d, w)
  Composition,         // psi_d * w + psi_s * (1 - w)
  ToneMap,             // exposure, tone mapping, sRGB
};

const char* passName(Pass pass);

// A relic material this rough or rougher (and not metallic-textured) is treated as not glossy:
// its reflection lobe is wider than ~80 degrees and the foreground reads the top pyramid level.
inline constexpr float kGlossyRoughnessLimit = 0.9f;

struct EffectInputs {
  bool foreground_enabled = true;  // the user's switch
  bool relic_empty = false;
  bool relic_glossy = true;  // some relic material below kGlossyRoughnessLimit
  bool relic_rough = false;  // some relic material takes its foreground from the rough map
  std::size_t foreground_points = 0;
  std::size_t cameras = 0;
  Bounds3 relic_bounds;
  Bounds3 foreground_bounds;             // empty when there is no foreground
  float max_reflection_distance = 3.0f;  // metres: the voxel walk's reach
};

struct EffectPlan {
  std::vector<Pass> passes;
  std::string foreground_reason;  // why the foreground passes run or not, for the statistics
  bool has(Pass pass) const;
  std::string describe() const;  // "HitPoints,StaticReflections,ToneMap (no foreground points)"
};

EffectPlan planEffects(const EffectInputs& inputs);

}  // namespace holo::reflect
