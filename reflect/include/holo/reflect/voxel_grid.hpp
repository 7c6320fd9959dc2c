// The foreground voxel grid: the foreground point cloud binned into cubic voxels over fixed world
// bounds around the pyramid, rebuilt every frame, for the reflection tracer's voxel walk.
// Units: metres (world = pyramid frame), linear radiance.
//
// Layout. Voxel (i, j, k) covers [origin + voxel_size * (i, j, k), origin + voxel_size * (i+1,
// j+1, k+1)) (half-open). A coarse level groups brick_size^3 voxels into one brick and counts the
// occupied voxels in each, so a walk can step over empty bricks; the occupied voxel bounds let a
// walk clip rays to the part of the grid that holds anything at all.
//
// Cost. Clearing touches only the voxels and bricks the last build filled, so a frame costs
// O(points), not O(voxels): a 128^3 grid (8 MiB of voxel indices) is allocated once.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "holo/core/math.hpp"
#include "holo/depthfilter/foreground_cloud.hpp"

namespace holo::reflect {

struct VoxelGridSettings {
  // World box the grid covers (metres; world = pyramid frame, y = 0 on the base top, the floor
  // about 1 m below). The default holds visitors standing up to 2 m from the relic axis, from
  // the floor to 2.2 m above it: 128 x 71 x 128 voxels of 3.125 cm.
  Bounds3 bounds{vec3(-2.0f, -1.0f, -2.0f), vec3(2.0f, 1.2f, 2.0f)};
  float voxel_size = 0.03125f;  // edge length, metres
  int brick_size = 4;           // voxels per brick edge for skipping, 1..64 (4: fastest in bench_voxel_walk)

  // Throws InputError naming `source` (a config file or "VoxelGridSettings") and the field.
  void validate(const std::string& source = "VoxelGridSettings") const;
};

// What a voxel keeps of the points that fell into it: the highest-weight point (its source
// camera and pixel index that camera's blurred pyramids), and how many points landed there.
struct VoxelSample {
  vec3 radiance{0.0f};  // linear RGB of the kept point
  float weight = 0.0f;  // mask weight of the kept point, (0, 1]
  std::uint16_t camera = 0;
  std::uint16_t x = 0;            // source pixel column
  std::uint16_t y = 0;            // source pixel row
  std::uint16_t point_count = 0;  // points binned here, saturating at 65535
};

class VoxelGrid {
 public:
  // Throws InputError on invalid settings (see VoxelGridSettings::validate).
  explicit VoxelGrid(const VoxelGridSettings& settings = {});

  // Empties the grid, then bins every point inside the bounds. Points outside the bounds or
  // with non-finite positions are skipped and counted in droppedPoints().
  void build(const depthfilter::ForegroundCloud& cloud);
  // Empties the grid in O(occupied voxels).
  void clear();

  const VoxelGridSettings& settings() const { return settings_; }
  glm::ivec3 dims() const { return dims_; }
  glm::ivec3 brickDims() const { return brick_dims_; }
  int brickSize() const { return settings_.brick_size; }
  vec3 origin() const { return settings_.bounds.lo; }
  float voxelSize() const { return settings_.voxel_size; }
  // 1 / voxelSize() and 1 / brickSize(), computed once: every walk scales its ray by them.
  float inverseVoxelSize() const { return inverse_voxel_size_; }
  float inverseBrickSize() const { return inverse_brick_size_; }

  bool contains(const glm::ivec3& v) const {
    return v.x >= 0 && v.y >= 0 && v.z >= 0 && v.x < dims_.x && v.y < dims_.y && v.z < dims_.z;
  }
  // Linear index of an in-range voxel (x fastest).
  std::int64_t linearIndex(const glm::ivec3& v) const {
    return (std::int64_t(v.z) * dims_.y + v.y) * dims_.x + v.x;
  }
  // Sample index of an in-range voxel, or -1 when it is empty.
  std::int32_t sampleIndex(const glm::ivec3& v) const { return cell_[std::size_t(linearIndex(v))]; }
  bool occupied(const glm::ivec3& v) const { return contains(v) && occupiedBit(v); }
  // Occupancy of an in-range voxel from the brick-major bit mask: the walk's inner loop reads
  // this (one cache line per 8^3 brick) instead of the 4-byte-per-voxel index array.
  bool occupiedBit(const glm::ivec3& v) const {
    const std::uint64_t bit = bitIndex(v);
    return (bits_[bit >> 6] >> (bit & 63)) & 1u;
  }
  // For a walk that already knows the voxel's brick: voxel `local` (each coordinate in
  // [0, brick_size)) of in-range brick `brick`. occupiedInBrick is occupiedBit without its
  // divisions by the brick size; sampleInBrick, for an occupied voxel only, is sampleIndex read
  // from the occupied bricks' own index blocks (a few hundred KiB, cache-resident) rather than
  // the 8 MiB voxel array, whose line a walk's hit would otherwise miss.
  bool occupiedInBrick(const glm::ivec3& brick, const glm::ivec3& local) const {
    const std::uint64_t bit = brickIndex(brick) * brick_volume_ + localIndex(local);
    return (bits_[bit >> 6] >> (bit & 63)) & 1u;
  }
  std::int32_t sampleInBrick(const glm::ivec3& brick, const glm::ivec3& local) const {
    const std::uint64_t block = std::uint64_t(brick_block_[std::size_t(brickIndex(brick))]);
    return brick_samples_[std::size_t(block * brick_volume_ + localIndex(local))];
  }
  const VoxelSample& sample(std::int32_t index) const { return samples_[std::size_t(index)]; }

  // Occupied voxels in brick b (in-range brick coordinates).
  std::uint32_t brickCount(const glm::ivec3& b) const {
    return brick_count_[std::size_t((b.z * brick_dims_.y + b.y) * brick_dims_.x + b.x)];
  }

  // Chebyshev distance, in bricks, from brick b to the nearest brick holding an occupied voxel
  // (0 for such a brick, saturating at 255; 255 everywhere when the grid is empty): every brick
  // within distance - 1 of b is empty, so a walk may jump over that whole cube.
  std::uint8_t brickDistance(const glm::ivec3& b) const {
    return brick_distance_[std::size_t((b.z * brick_dims_.y + b.y) * brick_dims_.x + b.x)];
  }

  // Voxel coordinates of a world point (floor((p - origin) / voxel_size)); may be out of range.
  glm::ivec3 voxelOf(const vec3& p) const;
  // World box of a voxel.
  Bounds3 voxelBounds(const glm::ivec3& v) const;

  std::size_t occupiedCount() const { return samples_.size(); }
  // Calls fn(v, sample) for every occupied voxel v, skipping empty bricks, in a fixed order (bricks
  // z, y, x, then the voxels within each brick z, y, x), so sums over it are deterministic.
  template <class Fn>
  void forEachOccupied(Fn&& fn) const {
    const int b = settings_.brick_size;
    for (int bz = 0; bz < brick_dims_.z; ++bz)
      for (int by = 0; by < brick_dims_.y; ++by)
        for (int bx = 0; bx < brick_dims_.x; ++bx) {
          if (brickCount({bx, by, bz}) == 0) continue;
          for (int z = bz * b; z < (bz + 1) * b; ++z)
            for (int y = by * b; y < (by + 1) * b; ++y)
              for (int x = bx * b; x < (bx + 1) * b; ++x) {
                const glm::ivec3 v(x, y, z);
                if (occupied(v)) fn(v, samples_[std::size_t(sampleIndex(v))]);
              }
        }
  }
  std::size_t droppedPoints() const { return dropped_; }
  bool empty() const { return samples_.empty(); }
  // Occupied voxel range: [occupiedLo, occupiedHi) in voxel coordinates; lo >= hi when empty.
  glm::ivec3 occupiedLo() const { return occ_lo_; }
  glm::ivec3 occupiedHi() const { return occ_hi_; }

  // A box of voxels [lo, hi) in voxel coordinates.
  struct VoxelBox {
    glm::ivec3 lo{0}, hi{0};
  };
  static constexpr std::size_t kMaxOccupiedGroups = 8;
  // At most kMaxOccupiedGroups boxes that together hold every occupied voxel (none when the grid is
  // empty), each the exact voxel bounds of a group of occupied bricks: the bricks' 26-connected
  // groups, the smaller groups beyond that count merged into the larger ones where the box grows
  // least. Visitors standing apart get boxes apart, where the one occupied box spans the space
  // between them (around the pyramid, the relic too): a ray that meets none of these boxes meets
  // no occupied voxel. The same cloud gives the same boxes in the same order.
  const std::vector<VoxelBox>& occupiedGroups() const { return groups_; }

 private:
  std::size_t brickLinear(const glm::ivec3& v) const;
  void computeBrickDistances();
  void groupOccupiedBricks();
  std::uint64_t brickIndex(const glm::ivec3& brick) const {
    return std::uint64_t((brick.z * brick_dims_.y + brick.y) * brick_dims_.x + brick.x);
  }
  std::uint64_t localIndex(const glm::ivec3& local) const {
    const int b = settings_.brick_size;
    return std::uint64_t((local.z * b + local.y) * b + local.x);
  }
  std::uint64_t bitIndex(const glm::ivec3& v) const {
    const glm::ivec3 brick = v / settings_.brick_size;
    return brickIndex(brick) * brick_volume_ + localIndex(v - brick * settings_.brick_size);
  }

  VoxelGridSettings settings_;
  glm::ivec3 dims_{0};
  glm::ivec3 brick_dims_{0};
  std::vector<std::int32_t> cell_;            // per voxel: index into samples_, or -1
  std::vector<std::uint32_t> brick_count_;    // per brick: occupied voxels
  std::vector<std::uint8_t> brick_distance_;  // per brick: see brickDistance
  std::vector<int> distance_scratch_;         // computeBrickDistances' working copy, kept
  std::vector<std::int64_t> point_voxel_;     // build's linear voxel of each point (-1: dropped), kept
  std::vector<std::uint64_t> bits_;           // occupancy bits, brick-major (see bitIndex)
  // Per brick: its block in brick_samples_ (-1: empty); per occupied brick, brick_volume_ sample
  // indices in bitIndex's order within the brick, valid where the voxel's bit is set.
  std::vector<std::int32_t> brick_block_;
  std::vector<std::int32_t> brick_samples_;
  std::int32_t blocks_used_ = 0;
  // Per occupied brick, in the order of their blocks: the brick and its occupied voxels' bounds.
  std::vector<glm::ivec3> block_brick_;
  std::vector<VoxelBox> block_bounds_;
  std::vector<std::int32_t> block_group_;  // groupOccupiedBricks' union-find parents, kept
  std::vector<VoxelBox> groups_;
  float inverse_voxel_size_ = 0.0f;
  float inverse_brick_size_ = 0.0f;
  std::uint64_t brick_volume_ = 0;          // brick_size^3
  std::vector<VoxelSample> samples_;        // occupied voxels, in first-touch order
  std::vector<std::int64_t> sample_voxel_;  // linear voxel index of each sample (for clear)
  glm::ivec3 occ_lo_{0};
  glm::ivec3 occ_hi_{0};
  std::size_t dropped_ = 0;
};

}  // namespace holo::reflect
