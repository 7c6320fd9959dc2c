#include "holo/reference/voxel_emitters.hpp"

namespace holo::reference {

using reflect::VoxelGrid;
using reflect::VoxelSample;

Model voxelEmitters(const VoxelGrid& grid) {
  Model model;
  if (grid.empty()) return model;
  const glm::ivec3 lo = grid.occupiedLo(), hi = grid.occupiedHi();
  // The 12 triangles of a unit cube over its 8 corners (bit 0: x, bit 1: y, bit 2: z), outward.
  static constexpr unsigned kTriangles[12][3] = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6},
                                                 {0, 1, 5}, {0, 5, 4}, {2, 6, 7}, {2, 7, 3},
                                                 {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  for (int z = lo.z; z < hi.z; ++z)
    for (int y = lo.y; y < hi.y; ++y)
      for (int x = lo.x; x < hi.x; ++x) {
        const glm::ivec3 v(x, y, z);
        if (!grid.occupiedBit(v)) continue;
        const VoxelSample& s = grid.sample(grid.sampleIndex(v));
        const Bounds3 b = grid.voxelBounds(v);
        Material m;
        m.name = "voxel";
        m.base_colour = vec3(0.0f);
        m.emission = s.radiance;
        TriangleMesh mesh;
        mesh.material = int(model.materials.size());
        for (unsigned c = 0; c < 8; ++c)
          mesh.positions.push_back(
              vec3((c & 1) ? b.hi.x : b.lo.x, (c & 2) ? b.hi.y : b.lo.y, (c & 4) ? b.hi.z : b.lo.z));
        for (const auto& t : kTriangles) mesh.triangles.push_back(uvec3(t[0], t[1], t[2]));
        mesh.computeNormals();
        model.materials.push_back(m);
        model.meshes.push_back(std::move(mesh));
      }
  return model;
}

}  // namespace holo::reference
