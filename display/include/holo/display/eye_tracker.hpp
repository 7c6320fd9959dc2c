// Eye positions E_f of the four pyramid faces: where each face's view of the relic is rendered
// from. A face shows the relic as seen by a default standing visitor until a visitor stands at
// it; then the eye follows the visitor's head, found in the foreground point cloud.
//
// Frames and units: world = pyramid frame (docs/architecture.md): origin at the centre of the base's top
// plane, +Y up, metres; the floor is at settings.floor_y. Face f (0..3) faces +Z, +X, -Z, -X
// (layout.hpp), and its sector is the quarter of the room within 45 degrees of that direction.
//
// Detection, per face and frame (detectEye): the foreground points in the face's sector, at a
// horizontal distance from the pyramid's axis in [min_distance, max_distance] and at heights
// where a head can be ([min_head_top, max_head_top] above the floor). The head is the highest
// such point that has at least min_top_support points within head_radius horizontally and
// top_band below it, and min_support within head_depth below it (flying pixels above a head are
// sparse and are not its top), and whose slice between width_band_top and width_band_bottom
// below the top, as one piece with no gap wider than max_surface_gap, is at least min_head_width
// wide across the line of sight from the axis, with the top over its middle half (a raised arm's
// forearm and hand, the highest points of a visitor waving, are thinner than a head, and apart
// from it; the width is measured across, not along, the base cameras' rays, so depth noise and
// flying pixels, which spread along the rays, do not widen an arm into a head). The centroid
// below uses that piece only. The eye is at the horizontal
// centroid of those points (the cameras on the base see the visitor's face side, so the centroid of the
// visible head lies near the eyes) and eye_below_top under that top. (The cameras look up at the
// head and see little of its crown; a percentile of the heights would put the eye too low.)
//
// Smoothing: an alpha-beta (constant-velocity) filter on the 3D eye, per face. Why not the
// paper's KCF: OpenCV's KCF tracks an appearance patch in one 2D image, while the head here is
// a 3D cluster of the fused, already segmented foreground cloud of four cameras (a visitor walking
// around the pyramid passes from one camera to the next), and the reflections need the 3D point.
// Detection in the cloud is cheap and needs no initial box; the alpha-beta filter removes the
// frame-to-frame jitter of the depth with no appearance model. The default gains (0.35, 0.05)
// leave about half the rms jitter of white detection noise ((2a^2 + b(2 - 3a)) / (a(4 - b - 2a))
// = 0.26 of its variance), settle in a few frames and, being constant-velocity, do not lag a
// visitor walking at a steady pace (about 1.5 cm behind one turning around the pyramid at 1 m).
// Updated less often than every reference_interval_s (a busy kiosk, a test at 10 Hz), the gains
// grow with the step (alpha linearly, beta with its square, both at most 1), which keeps the
// filter's bandwidth and damping in seconds: fixed gains at 10 Hz would lag a visitor walking
// round the pyramid (1 m/s^2 centripetal) by 0.2 m.
// A detection farther than `gate` from the prediction starts a new track (another visitor);
// with a track, the highest head within the gate is preferred over a taller visitor elsewhere.
// After lost_timeout_s without a detection the face goes back to its default eye.
#pragma once

#include <array>
#include <optional>

#include "holo/core/math.hpp"
#include "holo/depthfilter/foreground_cloud.hpp"
#include "holo/display/layout.hpp"

namespace holo::display {

struct EyeTrackerSettings {
  float floor_y = -1.0f;                     // world height of the floor (the simulated museum's)
  float default_eye_height = 1.6f;           // above the floor: an adult standing visitor's eyes
  float default_distance = 1.0f;             // from the pyramid's axis, along the face's normal
  float min_head_top = 1.0f;                 // above the floor: a child
  float max_head_top = 2.2f;                 // above the floor: a tall adult
  float min_distance = 0.25f;                // horizontal, from the axis: closer is the pyramid itself
  float max_distance = 3.0f;                 // farther away is not "standing at the face"
  float head_radius = 0.15f;                 // metres, horizontal
  float head_depth = 0.25f;                  // metres below the top that count as head
  int min_support = 15;                      // points the head needs
  float top_band = 0.05f;                    // metres: the top of a head is a dense surface, so...
  int min_top_support = 5;                   // ...this many points lie within top_band below it
  float eye_below_top = 0.10f;               // metres from the top of the head down to the eyes
  float width_band_top = 0.04f;              // metres below the top: the slice whose width is measured...
  float width_band_bottom = 0.12f;           // ...down to here (a head's widest part, around the eyes)
  float min_head_width = 0.11f;              // metres across the slice: a head is 0.14-0.19, a raised
                                             // forearm or hand 0.06-0.09
  float max_surface_gap = 0.02f;             // metres across: a wider gap in the slice separates two parts
  float alpha = 0.35f;                       // position gain of the alpha-beta filter, (0, 1]
  float beta = 0.05f;                        // velocity gain, [0, 2)
  double reference_interval_s = 1.0 / 30.0;  // the update interval alpha and beta are for; a
                                             // longer one scales them (alpha x, beta x^2, <= 1)
  float max_speed = 3.0f;                    // m/s: a faster filtered velocity is clamped
  float gate = 0.5f;                         // metres: a detection farther from the prediction restarts
  double lost_timeout_s = 1.0;               // seconds without a detection before the default eye
};

struct FaceEye {
  vec3 position{0.0f};       // world, metres: the eye the face renders from
  bool tracked = false;      // true while it follows a visitor (else the default eye)
  vec3 velocity{0.0f};       // m/s, the filter's estimate (0 when not tracked)
  double last_seen_s = 0.0;  // time of the last detection used
};

// Outward horizontal unit normal of face f: +Z, +X, -Z, -X for f = 0..3.
vec3 faceNormal(int face);
// The default standing visitor's eye of face f.
vec3 defaultEye(int face, const EyeTrackerSettings& settings);

// One frame's eye of face f found in `cloud`, without smoothing. Non-finite points are ignored.
// With `near`, the highest supported head within settings.gate of it (horizontally) wins if any;
// otherwise the highest supported head of the sector. Nothing found gives nullopt.
std::optional<vec3> detectEye(const depthfilter::ForegroundCloud& cloud, int face,
                              const EyeTrackerSettings& settings,
                              const std::optional<vec3>& near = std::nullopt);

class EyeTracker {
 public:
  explicit EyeTracker(EyeTrackerSettings settings = {});

  // Detects and filters the four eyes in the cloud of one frame (time cloud.time_s, seconds,
  // increasing; a time that does not advance counts as a new frame 1/30 s later).
  const std::array<FaceEye, kFaceCount>& update(const depthfilter::ForegroundCloud& cloud);
  const std::array<FaceEye, kFaceCount>& eyes() const { return eyes_; }
  const EyeTrackerSettings& settings() const { return settings_; }

 private:
  void updateFace(int face, const std::optional<vec3>& detection, double now);

  EyeTrackerSettings settings_;
  std::array<FaceEye, kFaceCount> eyes_{};
  std::optional<double> last_time_s_;
};

}  // namespace holo::display
