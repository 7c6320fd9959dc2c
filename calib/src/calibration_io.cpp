#include "holo/calib/calibration_io.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <yaml-cpp/yaml.h>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <ctime>
#include <opencv2/core.hpp>

#include "holo/core/error.hpp"
#include "holo/core/files.hpp"

namespace holo::calib {

namespace fs = std::filesystem;

namespace {

// A hand-edited rotation typed with a few decimals still passes; a scaled or sheared one does not.
constexpr double kRotationTolerance = 1e-3;
// A camera whose colour needs more than a tenfold correction is misconfigured, not matched.
constexpr double kMinColourGain = 0.1;
constexpr double kMaxColourGain = 10.0;

std::string str(double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.9g", v);
  return buffer;
}

std::string quoted(const std::string& text) {
  std::string out = "\"";
  out.append(text).push_back('"');
  return out;
}

fs::path temporaryFor(const fs::path& path) {
  fs::path tmp = path;
  // Keeps the final extension: cv::FileStorage picks the format from it.
  tmp.replace_filename(path.stem().string() + ".tmp-" + std::to_string(::getpid()) +
                       path.extension().string());
  return tmp;
}

void syncPath(const fs::path& path, int flags) {
  const int fd = ::open(path.c_str(), flags);
  if (fd >= 0) {
    ::fsync(fd);
    ::close(fd);
  }
}

// The calibration files are read with yaml-cpp, not with OpenCV's FileStorage parser: that
// parser loops without end on some malformed files (fuzz_config found "%YAML:1.\n   - 0\n0\n"
// and files with a NUL byte), and a kiosk that reads a corrupt calibration at boot must fail with
// an error, not hang. yaml-cpp ignores OpenCV's non-standard "%YAML:1.0" directive, caps nesting
// depth, and reads the "!!opencv-matrix" maps as plain maps.
YAML::Node parseForReading(const fs::path& path) {
  if (!fs::exists(path)) throw InputError(path.string(), "", "an existing calibration file", "no such file");
  // A calibration file is a few kilobytes of text.
  constexpr std::uintmax_t kMaxCalibrationBytes = 1 << 20;
  if (fs::file_size(path) > kMaxCalibrationBytes)
    throw InputError(path.string(), "", "a calibration file of at most 1 MiB",
                     std::to_string(fs::file_size(path)) + " bytes");
  const std::string text = readFile(path);
  if (const auto nul = text.find('\0'); nul != std::string::npos)
    throw InputError(path.string(), "", "a text file", "a NUL byte at offset " + std::to_string(nul));
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(path.string(), "line " + std::to_string(e.mark.line + 1), "calibration YAML", e.msg);
  }
  if (!root.IsMap())
    throw InputError(path.string(), "", "a map of calibration fields", "no map at the top level");
  return root;
}

// Typed field readers: each names the file and the field in its error.
class Reader {
 public:
  Reader(const fs::path& path, YAML::Node node, std::string prefix = {})
      : path_(path.string()), node_(std::move(node)), prefix_(std::move(prefix)) {}

  YAML::Node required(const std::string& key) const {
    if (!node_.IsMap()) fail(key, "a value in a map", "the enclosing node is not a map");
    const YAML::Node n = node_[key];
    if (!n.IsDefined() || n.IsNull()) fail(key, "a value", "missing");
    return n;
  }

  double real(const std::string& key) const { return number(required(key), key); }

  // Optional fields of newer files: absent (or null) in older ones.
  bool has(const std::string& key) const {
    if (!node_.IsMap()) return false;
    const YAML::Node n = node_[key];
    return n.IsDefined() && !n.IsNull();
  }

  int integer(const std::string& key) const {
    const YAML::Node n = required(key);
    int v = 0;
    if (!n.IsScalar() || !YAML::convert<int>::decode(n, v))
      fail(key, "an integer", n.IsScalar() ? quoted(n.Scalar()) : "not an integer");
    return v;
  }

  std::string text(const std::string& key) const {
    const YAML::Node n = required(key);
    if (!n.IsScalar()) fail(key, "a string", "not a string");
    return n.Scalar();
  }

  // An opencv-matrix of exactly rows x cols (a 1x5 and a 5x1 vector are both accepted when
  // `either_way`), single-channel, every element finite; returned as CV_64F, rows x cols.
  cv::Mat matrix(const std::string& key, int rows, int cols, bool either_way = false) const {
    const YAML::Node n = required(key);
    const std::string want = std::to_string(rows) + "x" + std::to_string(cols) + " matrix";
    if (!n.IsMap()) fail(key, "an opencv-matrix (" + want + ")", "not a readable matrix");
    const int r = dimension(n, "rows"), c = dimension(n, "cols");
    const bool declared_ok = (r == rows && c == cols) || (either_way && r == cols && c == rows);
    if (!declared_ok)
      fail(key, "a " + want,
           "rows " + (r >= 0 ? std::to_string(r) : std::string("?")) + ", cols " +
               (c >= 0 ? std::to_string(c) : std::string("?")));
    const YAML::Node dt = n["dt"];
    const std::string type = dt.IsDefined() && dt.IsScalar() ? dt.Scalar() : std::string();
    if (type.size() != 1 || std::string("ucwsifd").find(type[0]) == std::string::npos)
      fail(key, "a single-channel matrix (dt one of u c w s i f d)", quoted(type));
    const YAML::Node data = n["data"];
    const std::size_t count = static_cast<std::size_t>(rows * cols);
    if (!data.IsDefined() || !data.IsSequence() || data.size() != count)
      fail(key, std::to_string(count) + " data values",
           std::to_string(data.IsDefined() && data.IsSequence() ? data.size() : 0));
    cv::Mat out(r, c, CV_64F);
    for (std::size_t i = 0; i < count; ++i) {
      const int row = static_cast<int>(i) / c, col = static_cast<int>(i) % c;
      double v = 0;
      if (!data[i].IsScalar() || !YAML::convert<double>::decode(data[i], v))
        fail(key, "numbers",
             "element (" + std::to_string(row) + "," + std::to_string(col) + ") is not a number");
      if (!std::isfinite(v))
        fail(key, "finite elements",
             "element (" + std::to_string(row) + "," + std::to_string(col) + ") = " + str(v));
      out.at<double>(row, col) = v;
    }
    return out.rows == rows ? out : out.t();
  }

  [[noreturn]] void fail(const std::string& key, const std::string& expected, const std::string& got) const {
    throw InputError(path_, prefix_ + key, expected, got);
  }

 private:
  // A matrix's declared rows or cols; -1 when absent or not an integer.
  static int dimension(const YAML::Node& matrix, const char* key) {
    const YAML::Node n = matrix[key];
    int v = -1;
    if (!n.IsDefined() || !n.IsScalar() || !YAML::convert<int>::decode(n, v)) return -1;
    return v;
  }

  double number(const YAML::Node& n, const std::string& key) const {
    double v = 0;
    if (!n.IsScalar() || !YAML::convert<double>::decode(n, v)) fail(key, "a number", "not a number");
    if (!std::isfinite(v)) fail(key, "a finite number", str(v));
    return v;
  }

  std::string path_;
  YAML::Node node_;
  std::string prefix_;
};

void validateIntrinsics(
    const Intrinsics& K,
    const std::function<void(const std::string&, const std::string&, const std::string&)>& fail) {
  if (K.width <= 0) fail("image_width", "a positive width in pixels", std::to_string(K.width));
  if (K.height <= 0) fail("image_height", "a positive height in pixels", std::to_string(K.height));
  if (!(K.fx > 0) || !std::isfinite(K.fx)) fail("camera_matrix", "fx > 0 (element 0,0)", str(K.fx));
  if (!(K.fy > 0) || !std::isfinite(K.fy)) fail("camera_matrix", "fy > 0 (element 1,1)", str(K.fy));
  if (!std::isfinite(K.cx) || !std::isfinite(K.cy))
    fail("camera_matrix", "a finite principal point", str(K.cx) + ", " + str(K.cy));
  for (float d : K.distortion)
    if (!std::isfinite(d)) fail("distortion_coefficients", "finite coefficients", str(d));
}

// Rigid: finite, last row 0 0 0 1, rotation orthonormal with determinant +1.
void validateRigid(
    const cv::Matx44d& T,
    const std::function<void(const std::string&, const std::string&, const std::string&)>& fail,
    const std::string& key) {
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      if (!std::isfinite(T(i, j))) fail(key, "finite elements", str(T(i, j)));
  if (std::abs(T(3, 0)) > 1e-9 || std::abs(T(3, 1)) > 1e-9 || std::abs(T(3, 2)) > 1e-9 ||
      std::abs(T(3, 3) - 1.0) > 1e-9)
    fail(key, "last row 0 0 0 1",
         str(T(3, 0)) + " " + str(T(3, 1)) + " " + str(T(3, 2)) + " " + str(T(3, 3)));
  const cv::Matx33d R = T.get_minor<3, 3>(0, 0);
  const double orth = cv::norm(R.t() * R - cv::Matx33d::eye(), cv::NORM_INF);
  if (orth > kRotationTolerance)
    fail(key, "a rotation (R^T R = I within " + str(kRotationTolerance) + ")", "deviation " + str(orth));
  const double det = cv::determinant(R);
  if (std::abs(det - 1.0) > kRotationTolerance)
    fail(key, "a rotation with determinant +1", "determinant " + str(det));
}

cv::Matx44d toCv(const mat4& T) {
  cv::Matx44d out;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out(r, c) = T[c][r];  // glm is column-major
  return out;
}

mat4 toGlm(const cv::Matx44d& T) {
  mat4 out(1.0f);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) out[c][r] = static_cast<float>(T(r, c));
  return out;
}

bool validSerial(const std::string& serial) {
  if (serial.empty() || serial == "." || serial == "..") return false;
  for (unsigned char ch : serial)
    if (!std::isalnum(ch) && ch != '-' && ch != '_' && ch != '.') return false;
  return true;
}

void validateCamera(const CameraCalibration& c, const std::string& file) {
  auto fail = [&](const std::string& field, const std::string& expected, const std::string& got) {
    throw InputError(file, field, expected, got);
  };
  if (!validSerial(c.serial))
    fail("camera_name", "a serial of letters, digits, '-', '_', '.'", quoted(c.serial));
  validateIntrinsics(c.intrinsics, fail);
  validateRigid(toCv(c.T_world_camera), fail, "T_world_camera");
  if (!(c.depth_scale > 0) || !std::isfinite(c.depth_scale))
    fail("depth_scale", "metres per depth unit > 0", str(c.depth_scale));
  if (c.depth_scale >= 1.0)
    fail("depth_scale", "metres per raw depth unit (0.001 = millimetres)",
         str(c.depth_scale) + " looks like units per metre (the inverse): write " + str(1.0 / c.depth_scale));
  if (!(c.rms >= 0) || !std::isfinite(c.rms)) fail("rms", "an RMS error >= 0 pixels", str(c.rms));
  if (c.depth_intrinsics) {
    validateIntrinsics(*c.depth_intrinsics, [&](const std::string& field, const std::string& e,
                                                const std::string& g) { fail("depth_" + field, e, g); });
    validateRigid(toCv(c.T_colour_depth), fail, "T_colour_depth");
  }
  for (int i = 0; i < 3; ++i)
    if (!(c.colour_gains[i] >= kMinColourGain && c.colour_gains[i] <= kMaxColourGain))
      fail("colour_gains", "linear gains in [" + str(kMinColourGain) + ", " + str(kMaxColourGain) + "]",
           str(c.colour_gains[i]) + " (element " + std::to_string(i) + ")");
}

void validatePyramid(const PyramidCalibration& p, const std::string& file) {
  for (int f = 0; f < kPyramidFaces; ++f) {
    const FaceAlignment& a = p.faces[static_cast<std::size_t>(f)];
    const std::string prefix = "faces[" + std::to_string(f) + "].";
    if (!std::isfinite(a.offset_px.x) || !std::isfinite(a.offset_px.y))
      throw InputError(file, prefix + "offset", "a finite offset in pixels");
    if (!(a.scale > 0) || !std::isfinite(a.scale))
      throw InputError(file, prefix + "scale", "a scale > 0", str(a.scale));
    if (!std::isfinite(a.rotation_deg))
      throw InputError(file, prefix + "rotation_deg", "a finite angle in degrees", str(a.rotation_deg));
  }
  if (!std::isfinite(p.panorama_yaw_rad))
    throw InputError(file, "panorama_yaw_rad", "a finite angle in radians", str(p.panorama_yaw_rad));
  if (!isFinite(p.panorama_position))
    throw InputError(file, "panorama_position", "a finite position in metres");
  if (p.face_view_width < 16 || p.face_view_width > 16384)
    throw InputError(file, "face_view_width", "16..16384 pixels", std::to_string(p.face_view_width));
  if (p.face_view_height < 16 || p.face_view_height > 16384)
    throw InputError(file, "face_view_height", "16..16384 pixels", std::to_string(p.face_view_height));
}

void writeCamera(const fs::path& tmp, const CameraCalibration& c) {
  cv::FileStorage out(tmp.string(), cv::FileStorage::WRITE | cv::FileStorage::FORMAT_YAML);
  if (!out.isOpened()) throw Error("could not write " + tmp.string());
  const Intrinsics& K = c.intrinsics;
  out << "image_width" << K.width << "image_height" << K.height << "camera_name" << c.serial;
  out << "camera_matrix" << cv::Mat(cv::Matx33d(K.fx, 0, K.cx, 0, K.fy, K.cy, 0, 0, 1));
  out << "distortion_model"
      << "plumb_bob";
  cv::Mat dist(1, 5, CV_64F);
  for (int i = 0; i < 5; ++i) dist.at<double>(0, i) = K.distortion[static_cast<std::size_t>(i)];
  out << "distortion_coefficients" << dist;
  out << "T_world_camera" << cv::Mat(toCv(c.T_world_camera));
  // The optional fields before the required ones: a file cut short loses a required field.
  if (c.depth_intrinsics) {
    const Intrinsics& D = *c.depth_intrinsics;
    out << "depth_image_width" << D.width << "depth_image_height" << D.height;
    out << "depth_camera_matrix" << cv::Mat(cv::Matx33d(D.fx, 0, D.cx, 0, D.fy, D.cy, 0, 0, 1));
    cv::Mat depth_dist(1, 5, CV_64F);
    for (int i = 0; i < 5; ++i) depth_dist.at<double>(0, i) = D.distortion[static_cast<std::size_t>(i)];
    out << "depth_distortion_coefficients" << depth_dist;
    out << "T_colour_depth" << cv::Mat(toCv(c.T_colour_depth));
  }
  out << "depth_scale_fitted" << static_cast<int>(c.depth_scale_fitted);
  out << "colour_gains" << cv::Mat(cv::Matx13d(c.colour_gains.r, c.colour_gains.g, c.colour_gains.b));
  out << "depth_scale" << c.depth_scale << "date" << c.date << "rms" << c.rms;
  out.release();
}

void writePyramid(const fs::path& tmp, const PyramidCalibration& p) {
  cv::FileStorage out(tmp.string(), cv::FileStorage::WRITE | cv::FileStorage::FORMAT_YAML);
  if (!out.isOpened()) throw Error("could not write " + tmp.string());
  out << "faces"
      << "[";
  for (const FaceAlignment& a : p.faces) {
    out << "{"
        << "offset_x" << a.offset_px.x << "offset_y" << a.offset_px.y << "scale" << a.scale << "rotation_deg"
        << a.rotation_deg << "mirror" << static_cast<int>(a.mirror) << "}";
  }
  out << "]";
  out << "face_view_width" << p.face_view_width << "face_view_height" << p.face_view_height;
  out << "panorama_yaw_rad" << p.panorama_yaw_rad;
  out << "panorama_position"
      << cv::Mat(cv::Matx31d(p.panorama_position.x, p.panorama_position.y, p.panorama_position.z));
  out << "date" << p.date;
  out.release();
}

}  // namespace

CameraModel toCameraModel(const CameraCalibration& calibration, const std::string& source) {
  validateCamera(calibration, source.empty() ? "camera " + calibration.serial : source);
  return CameraModel(calibration.intrinsics, calibration.T_world_camera);
}

CameraCalibration fromCameraModel(const CameraModel& camera, std::string serial, double rms,
                                  double depth_scale) {
  CameraCalibration c;
  c.serial = std::move(serial);
  c.intrinsics = camera.intrinsics();
  c.T_world_camera = camera.T_world_camera();
  c.rms = rms;
  c.depth_scale = depth_scale;
  return c;
}

fs::path cameraCalibrationPath(const fs::path& dir, const std::string& serial) {
  if (!validSerial(serial))
    throw InputError("", "camera serial", "letters, digits, '-', '_' or '.'", quoted(serial));
  return dir / ("camera_" + serial + ".yml");
}

fs::path pyramidCalibrationPath(const fs::path& dir) {
  return dir / "pyramid.yml";
}

fs::path backupPath(const fs::path& path) {
  return fs::path(path.string() + ".bak");
}

std::string utcTimestamp() {
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm tm{};
  gmtime_r(&now, &tm);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", &tm);
  return buffer;
}

void saveWithBackup(const fs::path& path, const std::function<void(const fs::path&)>& write,
                    const std::function<void(const fs::path&)>& validate,
                    const std::function<void(const fs::path&)>& before_commit) {
  if (path.has_parent_path()) fs::create_directories(path.parent_path());
  const fs::path tmp = temporaryFor(path);
  const fs::path bak = backupPath(path);
  const fs::path bak_tmp = temporaryFor(bak);
  try {
    write(tmp);
    syncPath(tmp, O_RDONLY);
    validate(tmp);
    if (before_commit) before_commit(tmp);
    if (fs::exists(path)) {
      // The backup is itself replaced atomically, so an old .bak survives a crash here too.
      fs::copy_file(path, bak_tmp, fs::copy_options::overwrite_existing);
      syncPath(bak_tmp, O_RDONLY);
      fs::rename(bak_tmp, bak);
    }
    fs::rename(tmp, path);
    syncPath(path.has_parent_path() ? path.parent_path() : fs::path("."), O_RDONLY | O_DIRECTORY);
  } catch (...) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    fs::remove(bak_tmp, ignored);
    throw;
  }
}

void saveCameraCalibration(const fs::path& path, CameraCalibration calibration) {
  if (calibration.date.empty()) calibration.date = utcTimestamp();
  validateCamera(calibration, path.string());
  saveWithBackup(
      path, [&](const fs::path& tmp) { writeCamera(tmp, calibration); },
      [](const fs::path& tmp) { (void)loadCameraCalibration(tmp); });
}

void savePyramidCalibration(const fs::path& path, PyramidCalibration calibration) {
  if (calibration.date.empty()) calibration.date = utcTimestamp();
  validatePyramid(calibration, path.string());
  saveWithBackup(
      path, [&](const fs::path& tmp) { writePyramid(tmp, calibration); },
      [](const fs::path& tmp) { (void)loadPyramidCalibration(tmp); });
}

CameraCalibration loadCameraCalibration(const fs::path& path) {
  const Reader in(path, parseForReading(path));
  CameraCalibration c;
  c.intrinsics.width = in.integer("image_width");
  c.intrinsics.height = in.integer("image_height");
  c.serial = in.text("camera_name");
  const cv::Mat K = in.matrix("camera_matrix", 3, 3);
  if (K.at<double>(2, 0) != 0 || K.at<double>(2, 1) != 0 || K.at<double>(2, 2) != 1 ||
      K.at<double>(1, 0) != 0)
    in.fail("camera_matrix", "[fx 0 cx; 0 fy cy; 0 0 1]", "a matrix of another form");
  if (K.at<double>(0, 1) != 0) in.fail("camera_matrix", "zero skew (element 0,1)", str(K.at<double>(0, 1)));
  c.intrinsics.fx = static_cast<float>(K.at<double>(0, 0));
  c.intrinsics.fy = static_cast<float>(K.at<double>(1, 1));
  c.intrinsics.cx = static_cast<float>(K.at<double>(0, 2));
  c.intrinsics.cy = static_cast<float>(K.at<double>(1, 2));
  const std::string model = in.text("distortion_model");
  if (model != "plumb_bob") in.fail("distortion_model", "\"plumb_bob\"", quoted(model));
  const cv::Mat dist = in.matrix("distortion_coefficients", 1, 5, true);
  for (int i = 0; i < 5; ++i)
    c.intrinsics.distortion[static_cast<std::size_t>(i)] = static_cast<float>(dist.at<double>(0, i));
  const cv::Mat T = in.matrix("T_world_camera", 4, 4);
  c.T_world_camera = toGlm(cv::Matx44d(T));
  c.depth_scale = in.real("depth_scale");
  c.date = in.text("date");
  c.rms = in.real("rms");
  if (in.has("depth_camera_matrix") || in.has("T_colour_depth")) {
    Intrinsics D;
    D.width = in.integer("depth_image_width");
    D.height = in.integer("depth_image_height");
    const cv::Mat DK = in.matrix("depth_camera_matrix", 3, 3);
    if (DK.at<double>(2, 0) != 0 || DK.at<double>(2, 1) != 0 || DK.at<double>(2, 2) != 1 ||
        DK.at<double>(1, 0) != 0 || DK.at<double>(0, 1) != 0)
      in.fail("depth_camera_matrix", "[fx 0 cx; 0 fy cy; 0 0 1]", "a matrix of another form");
    D.fx = static_cast<float>(DK.at<double>(0, 0));
    D.fy = static_cast<float>(DK.at<double>(1, 1));
    D.cx = static_cast<float>(DK.at<double>(0, 2));
    D.cy = static_cast<float>(DK.at<double>(1, 2));
    const cv::Mat depth_dist = in.matrix("depth_distortion_coefficients", 1, 5, true);
    for (int i = 0; i < 5; ++i)
      D.distortion[static_cast<std::size_t>(i)] = static_cast<float>(depth_dist.at<double>(0, i));
    c.depth_intrinsics = D;
    const cv::Mat TCD = in.matrix("T_colour_depth", 4, 4);
    auto fail_depth = [&](const std::string& f, const std::string& e, const std::string& g) {
      in.fail(f, e, g);
    };
    validateRigid(cv::Matx44d(TCD), fail_depth, "T_colour_depth");
    c.T_colour_depth = toGlm(cv::Matx44d(TCD));
  }
  if (in.has("depth_scale_fitted")) {
    const int fitted = in.integer("depth_scale_fitted");
    if (fitted != 0 && fitted != 1) in.fail("depth_scale_fitted", "0 or 1", std::to_string(fitted));
    c.depth_scale_fitted = fitted == 1;
  }
  if (in.has("colour_gains")) {
    const cv::Mat gains = in.matrix("colour_gains", 1, 3, true);
    c.colour_gains = {static_cast<float>(gains.at<double>(0)), static_cast<float>(gains.at<double>(1)),
                      static_cast<float>(gains.at<double>(2))};
  }
  // Validate against the double-precision matrix, not its float copy.
  auto fail = [&](const std::string& f, const std::string& e, const std::string& g) { in.fail(f, e, g); };
  validateRigid(cv::Matx44d(T), fail, "T_world_camera");
  validateCamera(c, path.string());
  return c;
}

PyramidCalibration loadPyramidCalibration(const fs::path& path) {
  const Reader in(path, parseForReading(path));
  PyramidCalibration p;
  const YAML::Node faces = in.required("faces");
  if (!faces.IsSequence() || faces.size() != kPyramidFaces)
    in.fail("faces", "a list of " + std::to_string(kPyramidFaces) + " faces",
            faces.IsSequence() ? std::to_string(faces.size()) + " entries" : "not a list");
  for (int f = 0; f < kPyramidFaces; ++f) {
    const YAML::Node node = faces[static_cast<std::size_t>(f)];
    const std::string prefix = "faces[" + std::to_string(f) + "].";
    if (!node.IsMap()) in.fail(prefix.substr(0, prefix.size() - 1), "a map", "not a map");
    const Reader face(path, node, prefix);
    FaceAlignment& a = p.faces[static_cast<std::size_t>(f)];
    a.offset_px = {static_cast<float>(face.real("offset_x")), static_cast<float>(face.real("offset_y"))};
    a.scale = static_cast<float>(face.real("scale"));
    if (!(a.scale > 0)) face.fail("scale", "a scale > 0", str(a.scale));
    a.rotation_deg = static_cast<float>(face.real("rotation_deg"));
    const int mirror = face.integer("mirror");
    if (mirror != 0 && mirror != 1) face.fail("mirror", "0 or 1", std::to_string(mirror));
    a.mirror = mirror == 1;
  }
  p.panorama_yaw_rad = static_cast<float>(in.real("panorama_yaw_rad"));
  const cv::Mat pos = in.matrix("panorama_position", 3, 1, true);
  p.panorama_position = {static_cast<float>(pos.at<double>(0)), static_cast<float>(pos.at<double>(1)),
                         static_cast<float>(pos.at<double>(2))};
  if (in.has("face_view_width")) p.face_view_width = in.integer("face_view_width");
  if (in.has("face_view_height")) p.face_view_height = in.integer("face_view_height");
  p.date = in.text("date");
  validatePyramid(p, path.string());
  return p;
}

}  // namespace holo::calib
