// Procedural relics (fitted with fitOnPedestal): vase (surface of revolution), kettle (body, spout and
// handle: non-convex), tripod vessel (bowl, three legs, two handles) and a sphere, with a metal material
// from mirror (sphere, roughness 0) to rough (tripod, roughness 0.6); and two glass relics, closed
// solids with a KHR_materials_transmission + volume material: glass-vase (thick-walled tinted
// glass, IOR 1.5) and crystal (a faceted brilliant, IOR 2.42: many total internal reflections);
// and a thick open bowl (concave: its inside sees itself) in two materials: bowl (matte Lambert
// clay, no specular lobe) and metal-bowl (satin silver, roughness 0.4).
// Each is at most 0.28 m tall, standing on y = 0 and centred on the Y axis (the pyramid frame).
// Every mesh is wound counter-clockwise seen from outside (glTF's front face), as a volume needs.
#pragma once

#include <string>
#include <vector>

#include "holo/core/mesh.hpp"

namespace holo::relics {

// vase, kettle, tripod, sphere, glass-vase, crystal, bowl, metal-bowl
std::vector<std::string> relicNames();
std::string relicNameList();  // the same, joined with ", " (for help and errors)
// Builds a relic by name; throws InputError(origin, "relic", ...) listing the names otherwise.
Model makeRelic(const std::string& name, const std::string& origin = "built-in");

inline constexpr float kRelicHeight = 0.28f;    // metres, base top to the relic's top
inline constexpr float kRelicMaxWidth = 0.36f;  // fits well inside the pyramid over the base
// Scales `model` uniformly to kRelicHeight tall (or less, to stay kRelicMaxWidth wide), standing on
// y = 0 and centred on the Y axis. A model without extent is left as it is.
void fitOnPedestal(Model& model);

}  // namespace holo::relics
