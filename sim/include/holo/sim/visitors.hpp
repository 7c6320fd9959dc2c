// Visitors walk seeded paths around the pyramid, some carrying a book or a bag in a saturated
// colour. Two models of them (VisitorModel) share the lanes, the close visitors' places and the
// palettes of shirts, trousers and carried things:
//
// bodies (the default): articulated human bodies, 18 smooth closed parts (head, hair, neck, torso,
// pelvis, upper and lower arms, hands, thighs, shins, feet; ~5k triangles) posed rigidly by a joint
// hierarchy: hips and knees from the gait, the spine leaning and twisting, shoulders and elbows
// swinging against the legs, holding what is carried or reaching out. Height, build, skin, hair and
// clothes come from the seed. A walker cruises (0.6-1.2 m/s; 0.35-0.7 m/s on average), slows down
// to a standstill of 1.5-3.7 s once per pace cycle, during which it turns to face the pyramid and
// leans towards it, and speeds up again; legs and arms swing with the distance walked, their swing
// fading as the visitor slows.
//
// figures: articulated figures built from primitives (legs, torso, arms, neck, head) with a slowly
// varying speed (0.4 to 0.9 m/s on average, slowing down and speeding up, never stopping), a radial
// sway inside the lane and a leg/arm swing tied to the distance walked.
//
// Each visitor walks its own lane (a ring between the hall's inner and outer radius, so visitors
// never walk through each other). A pose is a closed-form function of time, so any frame can be
// rendered on its own. Every surface is an emitter with baked radiance, like the hall (see
// museum.hpp).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "holo/core/mesh.hpp"

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

// `count` visitors for a hall (room, gallery, atrium, none), from the seed.
std::vector<VisitorPlan> planVisitors(int count, std::uint64_t seed, const std::string& hall,
                                      VisitorModel model = VisitorModel::bodies);

// `count` visitors who stand close to the pyramid looking at it (feet 0.45-0.6 m from the base's
// side, i.e. 0.75-0.9 m from the axis, leaning in and out by 5 cm), one arm reaching out towards
// it (the hand ~0.25 m from the glass), the first one carrying a bag in the other hand. Each
// stands in front of its own face, away from the hall's furniture near the pyramid; at most 4.
// Their random stream is apart from planVisitors', so adding them changes no walking visitor.
std::vector<VisitorPlan> planCloseVisitors(int count, std::uint64_t seed, const std::string& hall,
                                           VisitorModel model = VisitorModel::bodies);

struct VisitorPose {
  vec3 feet;                    // world position of the point between the feet (on the floor)
  vec3 forward;                 // unit direction the body faces, in the floor plane
  float gait_phase = 0.0f;      // radians, pi per step: pi x distance walked / step length
  float swing = 0.0f;           // amplitude of the thighs' swing, radians (0 when standing)
  float lean = 0.0f;            // forward tilt of the spine at the hips, radians (0 for figures)
  float facing_pyramid = 0.0f;  // 0 walking along the lane .. 1 turned to face the pyramid's axis
  vec3 head;                    // world centre of the head
};
VisitorPose poseAt(const VisitorPlan& plan, float t);

// The visitors at time t, one mesh per visitor and material: figures (trousers, shirt, skin,
// carried); bodies (skin, hair, shirt, trousers, shoes, carried), every part a closed surface.
Model buildVisitors(const std::vector<VisitorPlan>& plans, float t);

}  // namespace holo::sim
