// What a visitor of the simulated museum is (visitors.hpp plans, poses and builds them): the
// visitor model, the seeded plan of one visitor's lane, pace and looks, and its pose at a time.
// Units: metres, seconds, radians; colours are baked linear radiance.
#pragma once

#include <string>
#include <vector>

#include "holo/core/math.hpp"

namespace holo::sim {

enum class Carried { nothing, book, bag };

// How visitors look and move; see the top of this file.
enum class VisitorModel { figures, bodies };
// "figures", "bodies", in VisitorModel's order.
std::vector<std::string> visitorModelNames();
// Throws InputError(origin, field, ...) naming both models for another name.
VisitorModel visitorModelFromName(const std::string& name, const std::string& origin = "",
                                  const std::string& field = "visitor_model");

struct VisitorPlan {
  VisitorModel model = VisitorModel::bodies;
  float lane_radius = 1.5f;    // metres from the pyramid axis
  float sway = 0.05f;          // radial sway amplitude, metres
  float sway_hz = 0.1f;        // Hz; bodies: per second walked at the mean pace (pausing with them)
  float start_angle = 0.0f;    // radians, azimuth at t = 0 (0 = +Z, pi/2 = +X)
  float angular_speed = 0.4f;  // mean, radians per second; the sign gives the direction
  float pace_hz = 0.08f;       // how often the visitor slows down and speeds up
  float pace_phase = 0.0f;
  float height = 1.75f;  // metres, feet to the top of the head
  // build, hair, hair_length, short_sleeves and shoes: the bodies model only.
  float build = 1.0f;        // width of shoulders, hips and torso relative to the mean, 0.9-1.15
  float hair_length = 0.3f;  // 0: cropped to the crown, 1: down to the neck
  bool short_sleeves = false;
  vec3 skin{0.6f}, hair{0.05f}, shirt{0.5f}, trousers{0.1f}, shoes{0.05f};
  Carried carried = Carried::nothing;
  vec3 carried_colour{0.0f};
  // A close visitor (planCloseVisitors) stands facing the pyramid's axis instead of walking: the
  // azimuth shuffles by +-drift radians around start_angle (angular_speed 0) and the free arm is
  // raised forward by `reach` radians (0: it swings as usual). A figure's legs stay still and it
  // sways radially by +-sway metres; a body's feet stay at lane_radius and its spine leans in and
  // out so the head moves by +-sway metres.
  bool faces_pyramid = false;
  float drift = 0.0f;  // radians
  float drift_hz = 0.0f;
  float reach = 0.0f;  // radians from hanging down, towards the pyramid, in the floor's frame
};

struct VisitorPose {
  vec3 feet;                    // world position of the point between the feet (on the floor)
  vec3 forward;                 // unit direction the body faces, in the floor plane
  float gait_phase = 0.0f;      // radians, pi per step: pi x distance walked / step length
  float swing = 0.0f;           // amplitude of the thighs' swing, radians (0 when standing)
  float lean = 0.0f;            // forward tilt of the spine at the hips, radians (0 for figures)
  float facing_pyramid = 0.0f;  // 0 walking along the lane .. 1 turned to face the pyramid's axis
  vec3 head;                    // world centre of the head
};

}  // namespace holo::sim
