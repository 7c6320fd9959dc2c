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
#include "holo/sim/visitor_plan.hpp"

namespace holo::sim {

// `count` visitors for a hall (room, gallery, atrium, none), from the seed.
std::vector<VisitorPlan> planVisitors(int count, std::uint64_t seed, const std::string& hall,
                                      VisitorModel model = VisitorModel::bodies);

// `count` visitors who stand close to the pyramid looking at it (feet 0.45-0.6 m from the base's
// side, i.e. 0.75-0.9 m from the axis, leaning in and out by 5 cm), one arm reaching out towards
// it (the hand ~0.25 m from the glass), the first one carrying a bag in the other hand. Each
// stands in front of its own face, away from the hall's furniture near the pyramid; at most 4 (in
// the window hall one, at face 0, between the window and the relic).
// Their random stream is apart from planVisitors', so adding them changes no walking visitor.
std::vector<VisitorPlan> planCloseVisitors(int count, std::uint64_t seed, const std::string& hall,
                                           VisitorModel model = VisitorModel::bodies);

VisitorPose poseAt(const VisitorPlan& plan, float t);

// The visitors at time t, one mesh per visitor and material: figures (trousers, shirt, skin,
// carried); bodies (skin, hair, shirt, trousers, shoes, carried), every part a closed surface.
Model buildVisitors(const std::vector<VisitorPlan>& plans, float t);

}  // namespace holo::sim
