// Whether a relic lets light through, the test every caustic tracer asks before it traces a photon
// (an opaque relic casts no caustic and pays nothing for one).
#pragma once

#include "holo/core/mesh.hpp"

namespace holo::reflect {

// Some material that one of the model's meshes uses has a transmission factor above zero (glTF's
// transmission texture scales that factor, so a texture alone lets nothing through).
bool modelTransmits(const Model& model);

}  // namespace holo::reflect
