// Evaluation only: a reference for measuring the appliance's renderer, never linked by it
// (reference/CMakeLists.txt).
// The reconstructed foreground as path-traceable geometry: every occupied voxel of the grid as a
// cube that emits its voxel's radiance (a diffuse emitter, as RenderScene treats the hall and the
// visitors). Path tracing the relic with these cubes and the static panorama is the MCPT baseline
// of the tracer evaluation (path tracing of the reconstructed scene: voxels plus panorama): it sees exactly
// what ours sees, the foreground cloud, so its error at infinite samples is the reconstruction's
// and its error at few samples is noise. One mesh and one material per voxel (a material carries
// the emission); 12 triangles each, faces between two occupied voxels included (they are never
// reached from outside, so they cost build time only).
// Units: metres (world = pyramid frame), linear radiance.
#pragma once

#include "holo/core/mesh.hpp"
#include "holo/reflect/voxel_grid.hpp"

namespace holo::reference {

// An empty Model for an empty grid.
Model voxelEmitters(const reflect::VoxelGrid& grid);

}  // namespace holo::reference
