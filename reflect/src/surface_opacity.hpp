// The opacity the relic's ray queries see (RenderScene installs it as the RayScene's hit
// opacity): a back face of a single-sided opaque material is culled (0), transmissive ones are
// not (a ray inside glass must leave it); alphaMode MASK gives 1 where alpha >= alphaCutoff, else
// 0; BLEND gives alpha; OPAQUE gives 1 whatever the alpha.
#pragma once

#include <cstddef>

#include "holo/core/mesh.hpp"
#include "holo/core/ray_scene.hpp"

namespace holo::reflect {

// The opacity of relic mesh `mesh` of `model` at `hit`, in [0, 1].
float surfaceOpacity(const Model& model, std::size_t mesh, const Ray& ray, const RayHit& hit);
// Whether a material needs surfaceOpacity at all (culled back faces, MASK or BLEND).
bool needsOpacity(const Material& material);

}  // namespace holo::reflect
