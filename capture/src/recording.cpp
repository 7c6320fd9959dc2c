#include "holo/capture/recording.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string_view>
#include <unordered_map>
#include <unordered_set>

#include "holo/core/config.hpp"
#include "holo/core/error.hpp"
#include "holo/core/files.hpp"

namespace holo::capture {

namespace fs = std::filesystem;

namespace {

// Paths a recording names (a camera's `folder:`, the frame files of an index) must stay inside the
// folder that names them: a recording copied from elsewhere must not make the appliance read
// files outside it. Absolute paths, '..' leading out and symlinks leading out are refused. Each
// frame's parent folder is resolved and listed once (frames share rgb/ and depth/), a file itself
// only when the listing shows it is a symlink.
class Confinement {
 public:
  explicit Confinement(const fs::path& folder)
      : folder_(fs::weakly_canonical(folder)), folder_text_(folder_.string() + "/") {}

  // True when `named`, relative to the folder, stays inside it once symlinks are followed.
  bool holds(const std::string& named) {
    if (named.empty() || named.front() == '/') return false;
    const std::size_t slash = named.rfind('/');
    const std::string parent = slash == std::string::npos ? std::string() : named.substr(0, slash);
    const std::string_view name =
        slash == std::string::npos ? std::string_view(named) : std::string_view(named).substr(slash + 1);
    if (name.empty() || name == "." || name == "..") return inside(resolve(folder_ / named));
    auto known = parents_.find(parent);
    if (known == parents_.end()) known = parents_.emplace(parent, look(parent)).first;
    const Parent& folder = known->second;
    if (!folder.inside) return false;
    return folder.symlinks.count(std::string(name)) == 0 || inside(resolve(folder_text_ + named));
  }

 private:
  struct Parent {
    bool inside = false;                       // the folder, symlinks followed, is inside
    std::unordered_set<std::string> symlinks;  // names in it that are symlinks
  };

  // One directory listing per parent folder: its entries' types come with the listing, so a
  // frame costs a hash lookup, not a system call.
  Parent look(const std::string& parent) const {
    Parent out;
    out.inside = inside(resolve(folder_ / parent));
    std::error_code error;
    if (!out.inside) return out;
    for (fs::directory_iterator it(folder_ / parent, error), end; !error && it != end; it.increment(error))
      if (it->is_symlink(error)) out.symlinks.insert(it->path().filename().string());
    return out;
  }

  static fs::path resolve(const fs::path& p) {
    std::error_code error;
    const fs::path resolved = fs::weakly_canonical(p, error);
    return error ? fs::path() : resolved;
  }
  bool inside(const fs::path& p) const {
    const fs::path relative = p.lexically_relative(folder_);
    return !p.empty() && !relative.empty() && *relative.begin() != "..";
  }

  fs::path folder_;
  std::string folder_text_;                          // folder_ and a slash, to which a name is appended
  std::unordered_map<std::string, Parent> parents_;  // by the parent folder as written
};

constexpr const char* kStaysInside =
    "a relative path inside the recording's folder (no absolute path, no '..' or symlink leading out)";

void checkIndexSize(const fs::path& file) {
  std::error_code error;
  const auto bytes = fs::file_size(file, error);
  if (!error && bytes > kMaxRecordingIndexBytes)
    throw InputError(
        file.string(), "",
        "an index of at most " + std::to_string(kMaxRecordingIndexBytes >> 20) + " MiB (~1M frames)",
        std::to_string(bytes >> 20) + " MiB");
}

// TUM index file: "timestamp path" per line, '#' starts a comment.
std::vector<std::pair<double, std::string>> readIndex(const fs::path& file) {
  checkIndexSize(file);
  Confinement folder(file.parent_path());
  std::ifstream in(file);
  if (!in) throw InputError(file.string(), "", "a readable TUM index file", "cannot open");
  std::vector<std::pair<double, std::string>> entries;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    double t = 0;
    std::string path;
    if (!(fields >> t >> path) || !std::isfinite(t))
      throw InputError(file.string(), "line " + std::to_string(line_number), "'timestamp file'", line);
    if (!folder.holds(path))
      throw InputError(file.string(), "line " + std::to_string(line_number), kStaysInside, path);
    entries.emplace_back(t, path);
  }
  return entries;
}

// associations.txt: "t_rgb rgb_file t_depth depth_file".
std::vector<RecordedFrame> readAssociations(const fs::path& dir) {
  const fs::path file = dir / "associations.txt";
  checkIndexSize(file);
  std::ifstream in(file);
  if (!in) throw InputError(file.string(), "", "a readable associations file", "cannot open");
  Confinement folder(dir);
  std::vector<RecordedFrame> frames;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    double t_rgb = 0, t_depth = 0;
    std::string rgb, depth;
    if (!(fields >> t_rgb >> rgb >> t_depth >> depth))
      throw InputError(file.string(), "line " + std::to_string(line_number),
                       "'t_rgb rgb_file t_depth depth_file'", line);
    for (const std::string& named : {rgb, depth})
      if (!folder.holds(named))
        throw InputError(file.string(), "line " + std::to_string(line_number), kStaysInside, named);
    frames.push_back({t_rgb, dir / rgb, dir / depth, t_depth});
  }
  return frames;
}

// Pairs each colour frame with the nearest depth frame within 20 ms (TUM's associate.py).
std::vector<RecordedFrame> associate(const fs::path& dir) {
  const auto rgb = readIndex(dir / "rgb.txt");
  const auto depth = readIndex(dir / "depth.txt");
  std::vector<RecordedFrame> frames;
  std::size_t j = 0;
  for (const auto& [t, file] : rgb) {
    while (j + 1 < depth.size() && std::abs(depth[j + 1].first - t) <= std::abs(depth[j].first - t)) ++j;
    if (j < depth.size() && std::abs(depth[j].first - t) <= 0.02)
      frames.push_back({t, dir / file, dir / depth[j].second, depth[j].first});
  }
  return frames;
}

// Open3D PinholeCameraIntrinsic JSON: width, height, intrinsic_matrix (3x3, column-major).
std::optional<CameraModel> readOpen3dIntrinsics(const fs::path& dir) {
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".json") continue;
    const std::string text = readFile(entry.path());
    const auto json = nlohmann::json::parse(text, nullptr, false);
    if (json.is_discarded() || !json.contains("intrinsic_matrix")) continue;
    const auto& m = json["intrinsic_matrix"];
    if (!m.is_array() || m.size() != 9 || !json.contains("width") || !json.contains("height"))
      throw InputError(entry.path().string(), "intrinsic_matrix",
                       "9 numbers (column-major 3x3) with width and height");
    Intrinsics K;
    K.width = json["width"].get<int>();
    K.height = json["height"].get<int>();
    K.fx = m[0].get<float>();
    K.fy = m[4].get<float>();
    K.cx = m[6].get<float>();
    K.cy = m[7].get<float>();
    if (K.width <= 0 || K.height <= 0 || K.fx <= 0 || K.fy <= 0)
      throw InputError(entry.path().string(), "intrinsic_matrix", "positive size and focal lengths");
    return CameraModel(K, mat4(1.0f));
  }
  return std::nullopt;
}

fs::path firstExisting(const fs::path& dir, std::initializer_list<const char*> names) {
  for (const char* n : names)
    if (fs::exists(dir / n)) return dir / n;
  return {};
}

CameraModel readCameraModel(const ConfigNode& camera) {
  const ConfigNode k = camera["intrinsics"];
  Intrinsics K;
  K.width = k["width"].as<int>();
  K.height = k["height"].as<int>();
  K.fx = k["fx"].as<float>();
  K.fy = k["fy"].as<float>();
  K.cx = k["cx"].as<float>();
  K.cy = k["cy"].as<float>();
  if (k.has("distortion")) {
    const ConfigNode d = k["distortion"];
    if (d.size() != 5) d.fail("5 numbers k1 k2 p1 p2 k3", std::to_string(d.size()) + " values");
    for (std::size_t i = 0; i < 5; ++i) K.distortion[i] = d[i].as<float>();
  }
  if (K.width <= 0 || K.height <= 0 || K.fx <= 0 || K.fy <= 0) k.fail("positive width, height, fx and fy");
  mat4 T(1.0f);
  if (camera.has("T_world_camera")) {
    const ConfigNode t = camera["T_world_camera"];
    if (t.size() != 16) t.fail("16 numbers (4x4 row-major)", std::to_string(t.size()) + " values");
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) T[c][r] = t[static_cast<std::size_t>(r * 4 + c)].as<float>();
  }
  return CameraModel(K, T);
}

Recording readHolopyramid(const fs::path& root) {
  const ConfigNode doc = ConfigNode::loadFile(root / kRecordingFile);
  const std::string format = doc["format"].as<std::string>();
  if (format != "holopyramid-recording") doc["format"].fail("holopyramid-recording", format);
  Recording rec{root, "holopyramid", {}};
  const double scale = doc["depth_scale"].as<double>();
  if (!(scale > 0)) doc["depth_scale"].fail("a positive number of units per metre");
  const ConfigNode cameras = doc["cameras"];
  Confinement recording(root);
  for (std::size_t i = 0; i < cameras.size(); ++i) {
    const ConfigNode c = cameras[i];
    RecordedCamera cam;
    cam.id = c.get<int>("id", static_cast<int>(i));
    cam.name = c.get<std::string>("name", "cam" + std::to_string(i));
    cam.serial = c.get<std::string>("serial", "");
    cam.depth_scale = scale;
    if (c.has("intrinsics")) cam.model = readCameraModel(c);
    const std::string folder = c["folder"].as<std::string>();
    if (!recording.holds(folder)) c["folder"].fail(kStaysInside, folder);
    const fs::path dir = root / folder;
    cam.frames = readAssociations(dir);
    rec.cameras.push_back(std::move(cam));
  }
  return rec;
}

}  // namespace

bool isRecordingFolder(const fs::path& folder) {
  if (!fs::is_directory(folder)) return false;
  if (fs::exists(folder / kRecordingFile)) return true;
  if (fs::exists(folder / "rgb.txt") && fs::exists(folder / "depth.txt")) return true;
  return fs::exists(folder / "depth.png") && !firstExisting(folder, {"color.png", "rgb.png"}).empty();
}

Recording readRecording(const fs::path& folder) {
  if (!fs::is_directory(folder)) throw InputError(folder.string(), "", "a recording folder", "not a folder");
  if (fs::exists(folder / kRecordingFile)) return readHolopyramid(folder);

  RecordedCamera cam;
  cam.name = folder.filename().string();
  cam.depth_scale = kTumDepthScale;
  cam.model = readOpen3dIntrinsics(folder);
  Recording rec{folder, "", {}};
  if (fs::exists(folder / "rgb.txt") && fs::exists(folder / "depth.txt")) {
    rec.layout = "tum-sequence";
    cam.frames = fs::exists(folder / "associations.txt") ? readAssociations(folder) : associate(folder);
  } else if (const fs::path colour = firstExisting(folder, {"color.png", "rgb.png"});
             !colour.empty() && fs::exists(folder / "depth.png")) {
    rec.layout = "single-frame";
    cam.frames.push_back({0.0, colour, folder / "depth.png", 0.0});
  } else {
    throw InputError(
        folder.string(), "",
        std::string("a recording: ") + kRecordingFile + ", TUM rgb.txt + depth.txt, or color.png + depth.png",
        "none of these");
  }
  if (cam.frames.empty()) throw InputError(folder.string(), "", "at least one frame", "none");
  rec.cameras.push_back(std::move(cam));
  return rec;
}

cv::Mat depthToU16(const cv::Mat& depth_m, double depth_scale, std::int64_t* clipped) {
  HOLO_ASSERT(depth_m.type() == CV_32FC1 && depth_scale > 0);
  cv::Mat out(depth_m.size(), CV_16UC1);
  std::int64_t too_far = 0;
  for (int y = 0; y < depth_m.rows; ++y) {
    const float* src = depth_m.ptr<float>(y);
    auto* dst = out.ptr<std::uint16_t>(y);
    for (int x = 0; x < depth_m.cols; ++x) {
      const float d = src[x];
      if (!(d > 0) || !std::isfinite(d)) {
        dst[x] = 0;
      } else if (d * depth_scale >= 65535.5) {
        dst[x] = 0;
        ++too_far;
      } else {
        dst[x] = static_cast<std::uint16_t>(std::lround(d * depth_scale));
      }
    }
  }
  if (clipped) *clipped += too_far;
  return out;
}

cv::Mat depthFromU16(const cv::Mat& depth_u16, double depth_scale) {
  HOLO_ASSERT(depth_u16.type() == CV_16UC1 && depth_scale > 0);
  cv::Mat out;
  depth_u16.convertTo(out, CV_32FC1, 1.0 / depth_scale);
  return out;
}

}  // namespace holo::capture
