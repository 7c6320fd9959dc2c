// Calibration files: OpenCV FileStorage YAML that stock OpenCV (and ROS camera_calibration users)
// can read, one file per camera keyed by its serial number and one file for the pyramid.
//
// Camera file (camera_SERIAL.yml), ROS camera_calibration key names plus the appliance's own:
//   image_width, image_height        int, pixels, > 0
//   camera_name                      string, the camera's serial number
//   camera_matrix                    3x3 double [fx 0 cx; 0 fy cy; 0 0 1], pixels, fx, fy > 0
//   distortion_model                 "plumb_bob" (OpenCV k1 k2 p1 p2 k3)
//   distortion_coefficients          1x5 double
//   T_world_camera                   4x4 double, camera -> world (pyramid frame), metres; a rigid
//                                    transform (rotation orthonormal with det +1, last row 0 0 0 1)
//   depth_scale                      double > 0: metres per raw depth unit (0.001 for millimetres)
//   date                             string, ISO 8601 UTC time of the calibration
//   rms                              double >= 0: RMS reprojection error of the intrinsics, pixels
//   depth_scale_fitted               optional int 0/1: depth_scale was measured against the board
//                                    (depth_registration.hpp) and the live loop uses it; 0 or
//                                    absent: the nominal value, the capture configuration's rules
//   depth_image_width, depth_image_height, depth_camera_matrix, depth_distortion_coefficients,
//   T_colour_depth                   optional, together: a camera whose depth comes from a second
//                                    device - that device's intrinsics (as the colour ones) and
//                                    its pose in the colour camera's frame (4x4 rigid, metres;
//                                    depth_registration.hpp); the live loop reprojects its depth
//                                    into the colour image
//   colour_gains                     optional 1x3 double, linear R G B multipliers in [0.1, 10]
//                                    (colour_gains.hpp); absent in older files: 1 1 1
// Pyramid file (pyramid.yml): the four faces' display alignment and the panorama's alignment.
//
// Saving is atomic and keeps the previous file: the new content goes to a temporary file in the
// same folder, is read back and validated, the old file is copied to PATH.bak, then the temporary
// is renamed over PATH. A crash at any moment leaves PATH either the old or the new calibration.
// Loading validates every field and throws holo::InputError naming the file and the field.
#pragma once

#include <array>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>

#include "holo/core/camera_model.hpp"

namespace holo::calib {

struct CameraCalibration {
  std::string serial;               // stored as camera_name; names the file
  Intrinsics intrinsics;            // image size, focal lengths, principal point, distortion
  mat4 T_world_camera{1.0f};        // camera -> world (pyramid frame), metres
  double depth_scale = 0.001;       // metres per raw depth unit
  bool depth_scale_fitted = false;  // measured (used by the live loop) rather than nominal
  std::string date;                 // ISO 8601 UTC; filled in by saveCameraCalibration when empty
  double rms = 0.0;                 // RMS reprojection error of the intrinsics, pixels
  vec3 colour_gains{1.0f};          // linear RGB multipliers matching this camera to the others
  // Two-device cameras: the depth device's intrinsics and depth camera -> colour camera.
  std::optional<Intrinsics> depth_intrinsics;
  mat4 T_colour_depth{1.0f};
};

// Display alignment of one pyramid face: the face view is optionally mirrored left-right, scaled
// about its centre, rotated (counter-clockwise on screen, degrees), then shifted by offset
// (pixels, +x right, +y down) inside its quarter of the monitor (display_alignment.hpp).
struct FaceAlignment {
  vec2 offset_px{0.0f};
  float scale = 1.0f;         // > 0
  float rotation_deg = 0.0f;  // finite
  bool mirror = false;
};

inline constexpr int kPyramidFaces = 4;

struct PyramidCalibration {
  std::array<FaceAlignment, kPyramidFaces> faces{};  // face f faces azimuth f * 90 degrees
  float panorama_yaw_rad = 0.0f;  // rotation about world +Y taking panorama directions to world
  vec3 panorama_position{0.0f};   // where the panorama was captured, world metres
  // The face view the alignment was measured in (offsets are its pixels); optional in the file
  // (face_view_width, face_view_height), older files: 960 x 540.
  int face_view_width = 960;
  int face_view_height = 540;
  std::string date;  // ISO 8601 UTC; filled in on save when empty
};

// Conversions to and from the camera model the pipeline uses. toCameraModel throws InputError
// (naming `source`) when the calibration is not a valid camera.
CameraModel toCameraModel(const CameraCalibration& calibration, const std::string& source = {});
CameraCalibration fromCameraModel(const CameraModel& camera, std::string serial, double rms = 0.0,
                                  double depth_scale = 0.001);

// File of one camera inside a calibration folder: DIR/camera_SERIAL.yml. The serial may hold only
// letters, digits, '-', '_' and '.' (it becomes a file name); otherwise InputError.
std::filesystem::path cameraCalibrationPath(const std::filesystem::path& dir, const std::string& serial);
std::filesystem::path pyramidCalibrationPath(const std::filesystem::path& dir);
// The backup a save keeps of the previous file: PATH.bak.
std::filesystem::path backupPath(const std::filesystem::path& path);

// Save atomically (see above). Throws InputError when the calibration itself is invalid (nothing
// is written then) and holo::Error when the file cannot be written (the old file is untouched).
void saveCameraCalibration(const std::filesystem::path& path, CameraCalibration calibration);
void savePyramidCalibration(const std::filesystem::path& path, PyramidCalibration calibration);

// Load and validate; InputError names the file and the field that is missing or wrong.
CameraCalibration loadCameraCalibration(const std::filesystem::path& path);
PyramidCalibration loadPyramidCalibration(const std::filesystem::path& path);

// The save mechanism on its own, for any writer that needs a file name: `write` fills the
// temporary file, `validate` reads it back (throwing when it is wrong), then the previous file
// is copied to PATH.bak and the temporary renamed over PATH. `before_commit` (tests) runs just
// before the backup and rename, the moment a crash would hurt most.
void saveWithBackup(const std::filesystem::path& path,
                    const std::function<void(const std::filesystem::path& tmp)>& write,
                    const std::function<void(const std::filesystem::path& tmp)>& validate,
                    const std::function<void(const std::filesystem::path& tmp)>& before_commit = {});

// The current UTC time as ISO 8601 ("2026-11-23T09:15:00Z").
std::string utcTimestamp();

}  // namespace holo::calib
