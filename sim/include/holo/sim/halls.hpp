// The static halls around the pyramid. Every surface is a diffuse emitter whose
// Material::emission is its (baked) radiance, so cameras, the panorama and the path tracer agree
// (see museum.hpp). Floor at y = -kBaseHeight; the pyramid base is a dark box of half width
// kBaseHalfWidth from the floor to y = 0. Lamps, windows and skylights have radiance well above 1,
// so the hall's panorama is truly HDR.
//   room    : small living room 5 x 5 x 2.8 m, coloured walls, sofa, bookcase, window, lamps
//   gallery : long gallery 16 x 5.6 x 4.5 m, paintings, benches, a row of ceiling lamps
//   atrium  : tall atrium 12 x 12 x 12 m, columns, balcony, banners, a skylight
//   window  : plain room 6 x 5.2 x 3 m lit mostly by one tall bright window 2.2 m from the axis on
//             its +Z side (a close visitor at face 0 stands between it and the relic)
//   none    : nothing at all (the relic alone, for tests under a panorama)
// Each hall but window has strongly coloured objects within 1 m of the pyramid axis. The gilt frames,
// bollard tops and poles are metallic and the bollards glossy (metallic/roughness), which only
// the depth sensor model reads (sensor_noise.hpp: metal and highlight holes).
#pragma once

#include <string>
#include <vector>

#include "holo/core/mesh.hpp"

namespace holo::sim {

inline constexpr float kBaseHeight = 1.0f;  // floor to base top, metres
inline constexpr int kFaceCount = 4;
inline constexpr float kBaseHalfWidth = 0.3f;  // metres, the square base is 0.6 m wide

std::vector<std::string> hallNames();  // room, gallery, atrium, window, none
// Throws InputError(origin, "hall", ...) for an unknown name.
Model makeHall(const std::string& name, const std::string& origin = "built-in");

}  // namespace holo::sim
