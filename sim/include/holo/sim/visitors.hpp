// Visitors: articulated figures built from primitives (legs, torso, arms, neck, head) that walk
// seeded paths around the pyramid, some carrying a book or a bag in a saturated colour.
//
// Each visitor walks its own lane (a ring between the hall's inner and outer radius, so visitors
// never walk through each other), with a slowly varying speed (0.4 to 0.9 m/s on average, slowing
// down and speeding up), a radial sway inside the lane and a leg/arm swing tied to the distance
// walked. A pose is a closed-form function of time, so any frame can be rendered on its own.
// Every surface is an emitter with baked radiance, like the hall (see museum.hpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "holo/core/mesh.hpp"

namespace holo::sim {

enum class Carried { nothing, book, bag };

struct VisitorPlan {
  float lane_radius = 1.5f;  // metres from the pyramid axis
  float sway = 0.05f;        // radial sway amplitude, metres
  float sway_hz = 0.1f;
  float start_angle = 0.0f;    // radians, azimuth at t = 0 (0 = +Z, pi/2 = +X)
  float angular_speed = 0.4f;  // mean, radians per second; the sign gives the direction
  float pace_hz = 0.08f;       // how often the visitor slows down and speeds up
  float pace_phase = 0.0f;
  float height = 1.75f;  // metres, feet to the top of the head
  vec3 skin{0.6f}, shirt{0.5f}, trousers{0.1f};
  Carried carried = Carried::nothing;
  vec3 carried_colour{0.0f};
  // A close visitor (planCloseVisitors) stands facing the pyramid's axis instead of walking: the
  // legs stay still, the azimuth shuffles by +-drift radians around start_angle (angular_speed
  // 0), and the free arm is raised forward by `reach` radians (0: it swings as usual).
  bool faces_pyramid = false;
  float drift = 0.0f;  // radians
  float drift_hz = 0.0f;
  float reach = 0.0f;  // radians from hanging down, towards the pyramid
};

// `count` visitors for a hall (room, gallery, atrium, none), from the seed.
std::vector<VisitorPlan> planVisitors(int count, std::uint64_t seed, const std::string& hall);

// `count` visitors who stand close to the pyramid looking at it (feet 0.45-0.6 m from the base's
// side, i.e. 0.75-0.9 m from the axis, leaning in and out by 5 cm), one arm reaching out towards
// it (the hand ~0.25 m from the glass), the first one carrying a bag in the other hand. Each
// stands in front of its own face, away from the hall's furniture near the pyramid; at most 4.
// Their random stream is apart from planVisitors', so adding them changes no walking visitor.
std::vector<VisitorPlan> planCloseVisitors(int count, std::uint64_t seed, const std::string& hall);

struct VisitorPose {
  vec3 feet;            // world position of the point between the feet (on the floor)
  vec3 forward;         // unit walking direction in the floor plane
  float stride = 0.0f;  // leg swing angle, radians
  vec3 head;            // world centre of the head
};
VisitorPose poseAt(const VisitorPlan& plan, float t);

// The visitors at time t, one mesh per visitor and material (skin, shirt, trousers, carried).
Model buildVisitors(const std::vector<VisitorPlan>& plans, float t);

}  // namespace holo::sim
