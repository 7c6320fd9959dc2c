#include "holo/reflect/voxel_grid.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <limits>
#include <random>
#include <tuple>

#include "holo/core/error.hpp"
#include "synthetic_foreground.hpp"

namespace holo::reflect {
using depthfilter::ForegroundCloud;
using depthfilter::ForegroundPoint;

namespace {

ForegroundPoint point(const vec3& p, float weight, std::uint16_t camera, std::uint16_t x) {
  ForegroundPoint fp;
  fp.position = p;
  fp.radiance = vec3(float(x));
  fp.weight = weight;
  fp.camera = camera;
  fp.x = x;
  fp.y = 7;
  return fp;
}

VoxelGridSettings unitSettings() {
  VoxelGridSettings s;
  s.bounds = {vec3(-1.0f), vec3(1.0f)};
  s.voxel_size = 0.25f;  // 8^3 voxels
  s.brick_size = 4;      // 2^3 bricks
  return s;
}

TEST(VoxelGrid, DimensionsCoverTheBounds) {
  VoxelGridSettings s;
  s.bounds = {vec3(-1.6f, 0.0f, -1.6f), vec3(1.6f, 3.2f, 1.6f)};
  s.voxel_size = 0.025f;
  s.brick_size = 8;
  const VoxelGrid grid(s);
  EXPECT_EQ(grid.dims(), glm::ivec3(128));
  EXPECT_EQ(grid.brickDims(), glm::ivec3(16));
  // A partial last brick: 10 voxels in bricks of 4 need 3 bricks.
  s.bounds = {vec3(0.0f), vec3(1.0f)};
  s.voxel_size = 0.1f;
  s.brick_size = 4;
  EXPECT_EQ(VoxelGrid(s).brickDims(), glm::ivec3(3));
}

TEST(VoxelGrid, KeepsTheHighestWeightPointPerVoxel) {
  VoxelGrid grid(unitSettings());
  ForegroundCloud cloud;
  cloud.points = {point({0.1f, 0.1f, 0.1f}, 0.4f, 1, 10), point({0.2f, 0.05f, 0.01f}, 0.9f, 2, 20),
                  point({0.15f, 0.15f, 0.15f}, 0.6f, 3, 30), point({-0.9f, 0.9f, 0.0f}, 1.0f, 0, 40)};
  grid.build(cloud);
  ASSERT_EQ(grid.occupiedCount(), 2u);
  const glm::ivec3 v = grid.voxelOf({0.1f, 0.1f, 0.1f});
  EXPECT_EQ(v, glm::ivec3(4));
  const VoxelSample& s = grid.sample(grid.sampleIndex(v));
  EXPECT_EQ(s.camera, 2);
  EXPECT_EQ(s.x, 20);
  EXPECT_FLOAT_EQ(s.weight, 0.9f);
  EXPECT_EQ(s.point_count, 3);
  EXPECT_EQ(grid.occupiedLo(), glm::ivec3(0, 4, 4));
  EXPECT_EQ(grid.occupiedHi(), glm::ivec3(5, 8, 5));
  EXPECT_EQ(grid.brickCount({1, 1, 1}), 1u);
  EXPECT_EQ(grid.brickCount({0, 1, 1}), 1u);
  EXPECT_EQ(grid.brickCount({0, 0, 0}), 0u);
}

TEST(VoxelGrid, DropsOutsideAndNonFinitePointsAndCountsThem) {
  VoxelGrid grid(unitSettings());
  ForegroundCloud cloud;
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  cloud.points = {point({1.0f, 0.0f, 0.0f}, 1.0f, 0, 1),     // on the upper face: outside (half-open)
                  point({-1.0f, -1.0f, -1.0f}, 1.0f, 0, 2),  // on the lower corner: inside
                  point({5.0f, 0.0f, 0.0f}, 1.0f, 0, 3),    point({inf, 0.0f, 0.0f}, 1.0f, 0, 4),
                  point({nan, 0.0f, 0.0f}, 1.0f, 0, 5),     point({0.0f, 0.0f, -1e30f}, 1.0f, 0, 6)};
  grid.build(cloud);
  EXPECT_EQ(grid.occupiedCount(), 1u);
  EXPECT_EQ(grid.droppedPoints(), 5u);
  EXPECT_TRUE(grid.occupied({0, 0, 0}));
}

TEST(VoxelGrid, RebuildClearsThePreviousFrame) {
  VoxelGridSettings s = unitSettings();
  s.voxel_size = 0.05f;  // 40^3
  VoxelGrid grid(s);
  const ForegroundCloud first = holo::test::visitorCloud(2, 0.6f, 1);
  grid.build(first);
  const std::size_t first_count = grid.occupiedCount();
  ASSERT_GT(first_count, 100u);
  ForegroundCloud second;
  second.points = {point({0.0f, 0.0f, 0.0f}, 1.0f, 0, 1)};
  grid.build(second);
  EXPECT_EQ(grid.occupiedCount(), 1u);
  // Every voxel and brick except the one point's is empty again.
  std::size_t occupied = 0;
  for (int z = 0; z < grid.dims().z; ++z)
    for (int y = 0; y < grid.dims().y; ++y)
      for (int x = 0; x < grid.dims().x; ++x) occupied += grid.occupied({x, y, z}) ? 1 : 0;
  EXPECT_EQ(occupied, 1u);
  std::uint64_t bricks = 0;
  for (int z = 0; z < grid.brickDims().z; ++z)
    for (int y = 0; y < grid.brickDims().y; ++y)
      for (int x = 0; x < grid.brickDims().x; ++x) bricks += grid.brickCount({x, y, z});
  EXPECT_EQ(bricks, 1u);
  EXPECT_EQ(grid.occupiedLo(), grid.voxelOf(vec3(0.0f)));
  EXPECT_EQ(grid.occupiedHi(), grid.voxelOf(vec3(0.0f)) + 1);
  grid.clear();
  EXPECT_TRUE(grid.empty());
  EXPECT_FALSE(grid.occupied(grid.voxelOf(vec3(0.0f))));
}

TEST(VoxelGrid, BrickDistancesAreChebyshevToTheNearestOccupiedBrick) {
  VoxelGridSettings s;
  s.bounds = {vec3(0.0f), vec3(1.0f, 0.5f, 0.8f)};
  s.voxel_size = 0.05f;  // 20 x 10 x 16 voxels, bricks of 2: 10 x 5 x 8
  s.brick_size = 2;
  VoxelGrid grid(s);
  EXPECT_EQ(grid.brickDistance({3, 2, 1}), 255);  // empty grid: far everywhere
  ForegroundCloud cloud;
  cloud.points = {point({0.12f, 0.12f, 0.12f}, 1.0f, 0, 1),   // brick (1, 1, 1)
                  point({0.92f, 0.42f, 0.72f}, 1.0f, 0, 2)};  // brick (9, 4, 7)
  grid.build(cloud);
  for (int z = 0; z < 8; ++z)
    for (int y = 0; y < 5; ++y)
      for (int x = 0; x < 10; ++x) {
        const glm::ivec3 b(x, y, z);
        const glm::ivec3 d1 = glm::abs(b - glm::ivec3(1, 1, 1)), d2 = glm::abs(b - glm::ivec3(9, 4, 7));
        const int expected = std::min(std::max({d1.x, d1.y, d1.z}), std::max({d2.x, d2.y, d2.z}));
        ASSERT_EQ(grid.brickDistance(b), expected) << x << "," << y << "," << z;
      }
  grid.clear();
  EXPECT_EQ(grid.brickDistance({1, 1, 1}), 255);
}

TEST(VoxelGrid, BrickDistancesMatchABruteForceSearchOnRandomOccupancy) {
  VoxelGridSettings s;
  s.bounds = {vec3(0.0f), vec3(1.2f, 0.6f, 0.9f)};
  s.voxel_size = 0.05f;  // 24 x 12 x 18 voxels, bricks of 3: 8 x 4 x 6
  s.brick_size = 3;
  VoxelGrid grid(s);
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int round = 0; round < 5; ++round) {
    ForegroundCloud cloud;
    const int points = 1 + round * 3;
    for (int i = 0; i < points; ++i)
      cloud.points.push_back(point({1.2f * u(rng), 0.6f * u(rng), 0.9f * u(rng)}, 1.0f, 0, i));
    grid.build(cloud);
    const glm::ivec3 n = grid.brickDims();
    for (int z = 0; z < n.z; ++z)
      for (int y = 0; y < n.y; ++y)
        for (int x = 0; x < n.x; ++x) {
          int expected = 255;
          for (int oz = 0; oz < n.z; ++oz)
            for (int oy = 0; oy < n.y; ++oy)
              for (int ox = 0; ox < n.x; ++ox)
                if (grid.brickCount({ox, oy, oz}) > 0)
                  expected =
                      std::min(expected, std::max({std::abs(ox - x), std::abs(oy - y), std::abs(oz - z)}));
          ASSERT_EQ(grid.brickDistance({x, y, z}), expected)
              << "round " << round << " at " << x << "," << y << "," << z;
        }
  }
}

// The walk reads a voxel through its brick (occupiedInBrick, sampleInBrick's per-brick index
// blocks); over rebuilds whose bricks come and go (blocks handed out anew each frame) both must
// agree with the voxel array at every voxel, for brick sizes that divide the grid and that do not.
TEST(VoxelGrid, BrickLocalReadsAgreeWithTheVoxelArrayOverRebuilds) {
  for (const int brick_size : {1, 3, 4}) {
    VoxelGridSettings s;
    s.bounds = {vec3(0.0f), vec3(1.2f, 0.6f, 0.9f)};
    s.voxel_size = 0.05f;  // 24 x 12 x 18 voxels
    s.brick_size = brick_size;
    VoxelGrid grid(s);
    std::mt19937 rng{std::uint32_t(brick_size)};
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    for (int round = 0; round < 4; ++round) {
      ForegroundCloud cloud;
      const int points = round == 2 ? 1 : 200 + 150 * round;
      for (int i = 0; i < points; ++i)
        cloud.points.push_back(point({1.2f * u(rng), 0.6f * u(rng), 0.9f * u(rng)}, u(rng), 0, i));
      grid.build(cloud);
      std::size_t occupied = 0;
      for (int z = 0; z < grid.dims().z; ++z)
        for (int y = 0; y < grid.dims().y; ++y)
          for (int x = 0; x < grid.dims().x; ++x) {
            const glm::ivec3 v(x, y, z), brick = v / brick_size, local = v - brick * brick_size;
            const bool at_voxel = grid.occupied(v);
            ASSERT_EQ(grid.occupiedInBrick(brick, local), at_voxel)
                << "round " << round << " at " << x << "," << y << "," << z;
            if (!at_voxel) continue;
            ++occupied;
            ASSERT_EQ(grid.sampleInBrick(brick, local), grid.sampleIndex(v))
                << "round " << round << " at " << x << "," << y << "," << z;
          }
      EXPECT_EQ(occupied, grid.occupiedCount());
    }
  }
}

// The occupied bricks' 26-connected groups by a search over the brick grid, each as the exact
// bounds of its occupied voxels.
std::vector<std::pair<glm::ivec3, glm::ivec3>> searchedGroups(const VoxelGrid& grid) {
  const glm::ivec3 n = grid.brickDims();
  const int b = grid.brickSize();
  const auto index = [&](const glm::ivec3& c) { return std::size_t((c.z * n.y + c.y) * n.x + c.x); };
  std::vector<bool> seen(std::size_t(n.x * n.y * n.z), false);
  std::vector<std::pair<glm::ivec3, glm::ivec3>> groups;
  for (int z = 0; z < n.z; ++z)
    for (int y = 0; y < n.y; ++y)
      for (int x = 0; x < n.x; ++x) {
        if (seen[index({x, y, z})] || grid.brickCount({x, y, z}) == 0) continue;
        glm::ivec3 lo(std::numeric_limits<int>::max()), hi(std::numeric_limits<int>::min());
        std::vector<glm::ivec3> open = {{x, y, z}};
        seen[index({x, y, z})] = true;
        while (!open.empty()) {
          const glm::ivec3 c = open.back();
          open.pop_back();
          for (int v = 0; v < b * b * b; ++v) {
            const glm::ivec3 voxel = c * b + glm::ivec3(v % b, v / b % b, v / (b * b));
            if (!grid.occupied(voxel)) continue;
            lo = glm::min(lo, voxel);
            hi = glm::max(hi, voxel + 1);
          }
          for (int d = 0; d < 27; ++d) {
            const glm::ivec3 m = c + glm::ivec3(d % 3 - 1, d / 3 % 3 - 1, d / 9 - 1);
            if (glm::any(glm::lessThan(m, glm::ivec3(0))) || glm::any(glm::greaterThanEqual(m, n))) continue;
            if (seen[index(m)] || grid.brickCount(m) == 0) continue;
            seen[index(m)] = true;
            open.push_back(m);
          }
        }
        groups.push_back({lo, hi});
      }
  return groups;
}

using Boxes = std::vector<std::pair<glm::ivec3, glm::ivec3>>;

Boxes sorted(Boxes groups) {
  const auto key = [](const std::pair<glm::ivec3, glm::ivec3>& g) {
    return std::make_tuple(g.first.x, g.first.y, g.first.z, g.second.x, g.second.y, g.second.z);
  };
  std::sort(groups.begin(), groups.end(), [&](const auto& a, const auto& b) { return key(a) < key(b); });
  return groups;
}

Boxes groupsOf(const VoxelGrid& grid) {
  Boxes groups;
  for (const VoxelGrid::VoxelBox& g : grid.occupiedGroups()) groups.push_back({g.lo, g.hi});
  return groups;
}

// Every occupied voxel lies in one of the grid's group boxes.
void expectGroupsHoldEveryVoxel(const VoxelGrid& grid) {
  std::size_t held = 0;
  grid.forEachOccupied([&](const glm::ivec3& v, const VoxelSample&) {
    for (const VoxelGrid::VoxelBox& g : grid.occupiedGroups())
      if (glm::all(glm::greaterThanEqual(v, g.lo)) && glm::all(glm::lessThan(v, g.hi))) {
        ++held;
        return;
      }
  });
  EXPECT_EQ(held, grid.occupiedCount());
}

// A cluster of points around `centre` (metres), a visitor's worth of voxels.
void addCluster(ForegroundCloud& cloud, const vec3& centre, float radius, std::mt19937& rng) {
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int i = 0; i < 40; ++i)
    cloud.points.push_back(point(centre + radius * vec3(u(rng), u(rng), u(rng)), 1.0f, 0, std::uint16_t(i)));
}

VoxelGridSettings groupSettings() {
  VoxelGridSettings s;
  s.bounds = {vec3(0.0f), vec3(1.2f, 0.6f, 0.9f)};
  s.voxel_size = 0.05f;  // 24 x 12 x 18 voxels, bricks of 3: 8 x 4 x 6
  s.brick_size = 3;
  return s;
}

TEST(VoxelGrid, OccupiedGroupsAreTheExactBoundsOfConnectedBricks) {
  VoxelGrid grid(groupSettings());
  // Two visitors at opposite corners: two boxes, the space between them in neither.
  std::mt19937 rng(11);
  ForegroundCloud apart;
  addCluster(apart, vec3(0.15f, 0.15f, 0.15f), 0.08f, rng);
  addCluster(apart, vec3(1.0f, 0.45f, 0.75f), 0.08f, rng);
  grid.build(apart);
  ASSERT_EQ(grid.occupiedGroups().size(), 2u);
  EXPECT_EQ(sorted(groupsOf(grid)), sorted(searchedGroups(grid)));
  const glm::ivec3 middle = grid.voxelOf(vec3(0.6f, 0.3f, 0.45f));
  for (const VoxelGrid::VoxelBox& g : grid.occupiedGroups())
    EXPECT_FALSE(glm::all(glm::greaterThanEqual(middle, g.lo)) && glm::all(glm::lessThan(middle, g.hi)));
  // Rebuilds with a few clusters each, up to the kept count: exactly the searched groups.
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int round = 0; round < 6; ++round) {
    ForegroundCloud cloud;
    for (int c = 0; c < 1 + round; ++c)
      addCluster(cloud, vec3(1.2f * u(rng), 0.6f * u(rng), 0.9f * u(rng)), 0.02f + 0.1f * u(rng), rng);
    grid.build(cloud);
    const auto searched = searchedGroups(grid);
    ASSERT_LE(searched.size(), VoxelGrid::kMaxOccupiedGroups) << "round " << round;
    EXPECT_EQ(sorted(groupsOf(grid)), sorted(searched)) << "round " << round;
    expectGroupsHoldEveryVoxel(grid);
  }
  grid.build(ForegroundCloud{});
  EXPECT_TRUE(grid.occupiedGroups().empty());
}

TEST(VoxelGrid, OccupiedGroupsBeyondTheKeptCountAreMergedAndStillHoldEveryVoxel) {
  // Points in bricks two apart (none of them neighbours), a random choice of 9 to 24 of them.
  VoxelGrid grid(groupSettings());
  std::vector<vec3> apart;
  for (int z = 0; z < 6; z += 2)
    for (int y = 0; y < 4; y += 2)
      for (int x = 0; x < 8; x += 2) apart.push_back((vec3(x, y, z) * 3.0f + 1.5f) * 0.05f);
  std::mt19937 rng(5);
  for (int round = 0; round < 4; ++round) {
    std::shuffle(apart.begin(), apart.end(), rng);
    ForegroundCloud cloud;
    for (std::size_t i = 0; i < 9 + 5 * std::size_t(round); ++i)
      cloud.points.push_back(point(apart[i], 1.0f, 0, std::uint16_t(i)));
    grid.build(cloud);
    ASSERT_GT(searchedGroups(grid).size(), VoxelGrid::kMaxOccupiedGroups) << "round " << round;
    EXPECT_EQ(grid.occupiedGroups().size(), VoxelGrid::kMaxOccupiedGroups) << "round " << round;
    expectGroupsHoldEveryVoxel(grid);
  }
}

TEST(VoxelGrid, RejectsBadSettingsNamingTheField) {
  auto expectError = [](VoxelGridSettings s, const std::string& field) {
    try {
      VoxelGrid grid(s);
      ADD_FAILURE() << "no error for field " << field;
    } catch (const InputError& e) {
      EXPECT_EQ(e.field(), field);
      EXPECT_NE(std::string(e.what()).find("expected"), std::string::npos) << e.what();
    }
  };
  VoxelGridSettings s = unitSettings();
  s.voxel_size = 0.0f;
  expectError(s, "voxel_size");
  s.voxel_size = std::numeric_limits<float>::quiet_NaN();
  expectError(s, "voxel_size");
  s.voxel_size = 1e-5f;  // 2e5^3 voxels
  expectError(s, "voxel_size");
  s = unitSettings();
  s.brick_size = 0;
  expectError(s, "brick_size");
  s.brick_size = 65;
  expectError(s, "brick_size");
  s = unitSettings();
  s.bounds.hi.y = s.bounds.lo.y;
  expectError(s, "bounds");
  s.bounds.hi.y = std::numeric_limits<float>::infinity();
  expectError(s, "bounds");
}

}  // namespace
}  // namespace holo::reflect
