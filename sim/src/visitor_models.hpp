// What the two visitor models (visitor_plan.hpp) do differently: their pace, pose, looks and
// geometry. visitors.cpp plans the lanes, the close visitors' places and what is carried for both
// and calls these.
#pragma once

#include <functional>
#include <string>

#include "holo/core/mesh.hpp"
#include "holo/sim/sensor_noise.hpp"
#include "holo/sim/visitor_plan.hpp"

namespace holo::sim::detail {

// A new mesh of one material (name suffix, baked radiance) for the visitor being built; the
// reference stays valid while that visitor is built.
using VisitorPart = std::function<TriangleMesh&(const std::string& what, const vec3& radiance)>;

// The body's frame at its pose: origin on the floor between the feet, +Y up, +Z forward.
mat4 visitorFrame(const VisitorPose& pose);

// Mean walking speed, m/s, from a uniform draw u in [0, 1).
float figureMeanSpeed(float u);
float bodyMeanSpeed(float u);

// The close visitor's reach (VisitorPlan::reach) bringing its hand a quarter metre from the glass.
float figureReach(const VisitorPlan& p);
float bodyReach(const VisitorPlan& p);

// Skin from a draw of the visitor's stream; the figures' and the bodies' palettes differ.
vec3 figureSkin(std::uint64_t draw);
vec3 bodySkin(std::uint64_t draw);
// Build, hair, sleeves and shoes from the bodies' own looks stream.
void drawBodyLooks(VisitorPlan& p, PixelRng extra);

VisitorPose figurePose(const VisitorPlan& plan, float t);
VisitorPose bodyPose(const VisitorPlan& plan, float t);

// The visitor's meshes at its pose; `world` is visitorFrame(pose).
void buildFigure(const VisitorPlan& p, const VisitorPose& pose, const mat4& world, const VisitorPart& part);
void buildBody(const VisitorPlan& p, const VisitorPose& pose, const mat4& world, const VisitorPart& part);

}  // namespace holo::sim::detail
