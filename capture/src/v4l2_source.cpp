#include "holo/capture/v4l2_source.hpp"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <poll.h>
#include <sys/ioctl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

#include "holo/core/error.hpp"
#include "holo/core/log.hpp"

namespace holo::capture {

namespace {

namespace fs = std::filesystem;

// ioctl that retries when a signal interrupted it.
int xioctl(int fd, unsigned long request, void* arg) {
  int rc;
  do rc = ::ioctl(fd, request, arg);
  while (rc == -1 && errno == EINTR);
  return rc;
}

std::string errnoText(int err) {
  return std::system_category().message(err);
}

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

std::string cString(const __u8* text, std::size_t size) {
  const auto* chars = reinterpret_cast<const char*>(text);
  return std::string(chars, strnlen(chars, size));
}

// Opens a node and checks it is a streaming capture device; throws Error naming the path.
int openCaptureNode(const std::string& path, v4l2_capability& cap) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    const int err = errno;
    throw Error(path + ": cannot open: " + errnoText(err) +
                (err == ENOENT ? " (no such V4L2 device; see `holopyramid devices`)" : ""));
  }
  std::memset(&cap, 0, sizeof cap);
  if (xioctl(fd, VIDIOC_QUERYCAP, &cap) != 0) {
    const int err = errno;
    ::close(fd);
    throw Error(path + ": not a V4L2 device (VIDIOC_QUERYCAP: " + errnoText(err) + ")");
  }
  const std::uint32_t caps = (cap.capabilities & V4L2_CAP_DEVICE_CAPS) ? cap.device_caps : cap.capabilities;
  if (!(caps & V4L2_CAP_VIDEO_CAPTURE) || !(caps & V4L2_CAP_STREAMING)) {
    ::close(fd);
    throw Error(path + ": not a video capture node with streaming I/O (a metadata or output node?)");
  }
  return fd;
}

// "YUYV 640x480 1280x720" for every format the node offers.
std::vector<std::string> offeredFormats(int fd) {
  std::vector<std::string> out;
  v4l2_fmtdesc desc{};
  desc.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
  for (desc.index = 0; xioctl(fd, VIDIOC_ENUM_FMT, &desc) == 0; ++desc.index) {
    std::string entry = fourccToString(desc.pixelformat);
    v4l2_frmsizeenum size{};
    size.pixel_format = desc.pixelformat;
    for (size.index = 0; xioctl(fd, VIDIOC_ENUM_FRAMESIZES, &size) == 0; ++size.index) {
      // Appended piece by piece: GCC 12 warns (-Wrestrict, falsely) on chained operator+ here.
      const bool discrete = size.type == V4L2_FRMSIZE_TYPE_DISCRETE;
      entry += discrete ? " " : " up to ";
      entry += std::to_string(discrete ? size.discrete.width : size.stepwise.max_width);
      entry += 'x';
      entry += std::to_string(discrete ? size.discrete.height : size.stepwise.max_height);
      if (size.type != V4L2_FRMSIZE_TYPE_DISCRETE) break;
    }
    out.push_back(entry);
  }
  return out;
}

// The USB serial of a node: sysfs puts the interface under class/video4linux/videoN/device and
// the serial file on the USB device one level up.
std::string sysfsSerial(const std::string& node_name) {
  std::error_code ec;
  fs::path dir = fs::canonical(fs::path("/sys/class/video4linux") / node_name / "device", ec);
  for (int up = 0; !ec && up < 3 && !dir.empty(); ++up, dir = dir.parent_path()) {
    std::ifstream in(dir / "serial");
    std::string serial;
    if (in && std::getline(in, serial)) return serial;
  }
  return {};
}

}  // namespace

std::uint32_t fourccFromName(const std::string& name) {
  if (name.size() != 4)
    throw InputError("", "pixel_format", "a V4L2 FourCC of four characters (YUYV, MJPG, Z16 )", name);
  return v4l2_fourcc(name[0], name[1], name[2], name[3]);
}

std::string fourccToString(std::uint32_t fourcc) {
  std::string out;
  for (int i = 0; i < 4; ++i) out += static_cast<char>((fourcc >> (8 * i)) & 0xff);
  while (!out.empty() && out.back() == ' ') out.pop_back();  // "Z16 " -> "Z16"
  return out;
}

std::vector<V4l2DeviceInfo> listV4l2Devices(const fs::path& dev_dir) {
  std::vector<std::string> nodes;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dev_dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("video", 0) == 0) nodes.push_back(entry.path().string());
  }
  std::sort(nodes.begin(), nodes.end());
  std::vector<V4l2DeviceInfo> out;
  for (const auto& path : nodes) {
    v4l2_capability cap{};
    int fd = -1;
    try {
      fd = openCaptureNode(path, cap);
    } catch (const Error& e) {
      HOLO_LOG_DEBUG("v4l2: skipping {}", e.what());
      continue;
    }
    V4l2DeviceInfo info;
    info.path = path;
    info.card = cString(cap.card, sizeof cap.card);
    info.driver = cString(cap.driver, sizeof cap.driver);
    info.bus_info = cString(cap.bus_info, sizeof cap.bus_info);
    info.serial = sysfsSerial(fs::path(path).filename().string());
    info.formats = offeredFormats(fd);
    ::close(fd);
    out.push_back(std::move(info));
  }
  return out;
}

std::string resolveV4l2Device(const std::string& spec, const fs::path& dev_dir) {
  const bool by_bus = spec.rfind("bus:", 0) == 0;
  const bool by_serial = spec.rfind("serial:", 0) == 0;
  if (!by_bus && !by_serial) return spec;
  const std::string wanted = spec.substr(by_bus ? 4 : 7);
  std::vector<std::string> seen;
  for (const auto& d : listV4l2Devices(dev_dir)) {
    const std::string& key = by_bus ? d.bus_info : d.serial;
    if (key == wanted) return d.path;
    seen.push_back(d.path + " (" + (key.empty() ? "?" : key) + ")");
  }
  throw Error("v4l2: no capture device in " + dev_dir.string() + " with " +
              (by_bus ? "bus info " : "serial ") + wanted +
              " (found: " + (seen.empty() ? "none" : join(seen)) + ")");
}

struct V4l2Stream {
  struct Mapped {
    void* start = MAP_FAILED;
    std::size_t length = 0;
  };

  V4l2StreamConfig config;
  bool is_depth = false;
  std::string path;
  int fd = -1;
  bool streaming = false;
  PixelFormat format = PixelFormat::YUYV;
  int width = 0, height = 0;
  std::size_t stride = 0;
  std::vector<Mapped> buffers;

  V4l2Stream(V4l2StreamConfig c, bool depth) : config(std::move(c)), is_depth(depth) {}
  ~V4l2Stream() { close(); }

  void open(const fs::path& dev_dir) {
    path = resolveV4l2Device(config.device, dev_dir);
    v4l2_capability cap{};
    fd = openCaptureNode(path, cap);
    const std::vector<std::string> offered = offeredFormats(fd);

    v4l2_format fmt{};
    fmt.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (xioctl(fd, VIDIOC_G_FMT, &fmt) != 0) throw Error(path + ": VIDIOC_G_FMT: " + errnoText(errno));
    if (!config.pixel_format.empty()) {
      const std::uint32_t wanted =
          fourccFromName(config.pixel_format.size() == 3 ? config.pixel_format + " " : config.pixel_format);
      const bool has = std::any_of(offered.begin(), offered.end(), [&](const std::string& f) {
        return f.rfind(fourccToString(wanted), 0) == 0;
      });
      if (!has)
        throw InputError(path, "pixel_format", "one the device offers: " + join(offered),
                         config.pixel_format);
      fmt.fmt.pix.pixelformat = wanted;
    }
    if (config.width > 0 && config.height > 0) {
      fmt.fmt.pix.width = static_cast<__u32>(config.width);
      fmt.fmt.pix.height = static_cast<__u32>(config.height);
    }
    fmt.fmt.pix.field = V4L2_FIELD_ANY;
    if (xioctl(fd, VIDIOC_S_FMT, &fmt) != 0) {
      const int err = errno;
      throw Error(path + ": cannot set format: " + errnoText(err) +
                  (err == EBUSY ? " (the device is in use by another program)" : ""));
    }
    if (config.width > 0 && (fmt.fmt.pix.width != static_cast<__u32>(config.width) ||
                             fmt.fmt.pix.height != static_cast<__u32>(config.height)))
      throw InputError(path, "width/height", "a size the device offers: " + join(offered),
                       std::to_string(config.width) + "x" + std::to_string(config.height));
    const std::string fourcc = fourccToString(fmt.fmt.pix.pixelformat);
    try {
      format = pixelFormatFromName(fourcc);
    } catch (const InputError&) {
      throw InputError(path, "pixel_format", "YUYV, MJPG or Z16 (the device offers " + join(offered) + ")",
                       fourcc);
    }
    if (is_depth != isDepthFormat(format))
      throw InputError(path, is_depth ? "depth.pixel_format" : "color.pixel_format",
                       is_depth ? "Z16 for a depth stream" : "YUYV or MJPG for a colour stream", fourcc);
    checkFrameSize(path, "width/height", fmt.fmt.pix.width, fmt.fmt.pix.height);
    width = static_cast<int>(fmt.fmt.pix.width);
    height = static_cast<int>(fmt.fmt.pix.height);
    stride = format == PixelFormat::MJPEG ? 0 : fmt.fmt.pix.bytesperline;

    if (config.frame_rate > 0) {
      v4l2_streamparm parm{};
      parm.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      parm.parm.capture.timeperframe.numerator = 1000;
      parm.parm.capture.timeperframe.denominator = static_cast<__u32>(config.frame_rate * 1000.0 + 0.5);
      if (xioctl(fd, VIDIOC_S_PARM, &parm) != 0)
        HOLO_LOG_WARN("{}: cannot set {} fps: {}", path, config.frame_rate, errnoText(errno));
    }

    v4l2_requestbuffers req{};
    req.count = static_cast<__u32>(std::max(2, config.buffers));
    req.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    req.memory = V4L2_MEMORY_MMAP;
    if (xioctl(fd, VIDIOC_REQBUFS, &req) != 0) {
      const int err = errno;
      throw Error(path + ": cannot allocate mmap buffers: " + errnoText(err) +
                  (err == EBUSY ? " (the device is in use by another program)" : ""));
    }
    if (req.count < 2)
      throw Error(path + ": the driver granted " + std::to_string(req.count) + " buffer(s), need 2");
    for (__u32 i = 0; i < req.count; ++i) {
      v4l2_buffer buf{};
      buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      buf.memory = V4L2_MEMORY_MMAP;
      buf.index = i;
      if (xioctl(fd, VIDIOC_QUERYBUF, &buf) != 0)
        throw Error(path + ": VIDIOC_QUERYBUF: " + errnoText(errno));
      Mapped m;
      m.length = buf.length;
      m.start = ::mmap(nullptr, buf.length, PROT_READ | PROT_WRITE, MAP_SHARED, fd, buf.m.offset);
      if (m.start == MAP_FAILED) throw Error(path + ": mmap: " + errnoText(errno));
      buffers.push_back(m);
      if (xioctl(fd, VIDIOC_QBUF, &buf) != 0) throw Error(path + ": VIDIOC_QBUF: " + errnoText(errno));
    }
  }

  void start() {
    v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    if (xioctl(fd, VIDIOC_STREAMON, &type) != 0) throw Error(path + ": VIDIOC_STREAMON: " + errnoText(errno));
    streaming = true;
  }

  void close() {
    if (fd >= 0 && streaming) {
      v4l2_buf_type type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
      xioctl(fd, VIDIOC_STREAMOFF, &type);  // fails harmlessly when the device is gone
    }
    streaming = false;
    for (auto& m : buffers)
      if (m.start != MAP_FAILED) ::munmap(m.start, m.length);
    buffers.clear();
    if (fd >= 0) ::close(fd);
    fd = -1;
  }

  struct Popped {
    GrabStatus status = GrabStatus::Timeout;
    cv::Mat image;
    Nanoseconds device_time{0};
    Nanoseconds pairing_time{0};  // CLOCK_MONOTONIC: the kernel's stamp, else the dequeue time
    std::string message;
  };

  // Waits for one buffer, converts it when good, and always queues it again.
  Popped pop(Nanoseconds timeout) {
    Popped out;
    pollfd p{fd, POLLIN, 0};
    const int ms = static_cast<int>(std::max<std::int64_t>(0, timeout.count() / 1000000));
    const int ready = ::poll(&p, 1, ms);
    if (ready == 0 || (ready < 0 && errno == EINTR)) return out;
    if (ready < 0 || (p.revents & (POLLERR | POLLHUP | POLLNVAL))) {
      out.status = GrabStatus::Disconnected;
      out.message = path + ": device gone (poll)";
      return out;
    }
    v4l2_buffer buf{};
    buf.type = V4L2_BUF_TYPE_VIDEO_CAPTURE;
    buf.memory = V4L2_MEMORY_MMAP;
    if (xioctl(fd, VIDIOC_DQBUF, &buf) != 0) {
      const int err = errno;
      if (err == EAGAIN) return out;
      out.status = err == ENODEV || err == EIO ? GrabStatus::Disconnected : GrabStatus::Failed;
      out.message = path + ": VIDIOC_DQBUF: " + errnoText(err);
      return out;
    }
    if (buf.flags & V4L2_BUF_FLAG_ERROR) {
      out.status = GrabStatus::Incomplete;
      out.message = path + ": driver flagged the buffer as corrupt";
    } else {
      const RawImage raw{buffers[buf.index].start, buf.bytesused, width, height, stride};
      try {
        out.image = is_depth ? convertToDepth(format, raw, config.depth_scale) : convertToColour(format, raw);
        out.status = GrabStatus::Ok;
        out.device_time = Nanoseconds(static_cast<std::int64_t>(buf.timestamp.tv_sec) * 1000000000LL +
                                      static_cast<std::int64_t>(buf.timestamp.tv_usec) * 1000LL);
        const bool monotonic =
            (buf.flags & V4L2_BUF_FLAG_TIMESTAMP_MASK) == V4L2_BUF_FLAG_TIMESTAMP_MONOTONIC;
        out.pairing_time = monotonic ? out.device_time : Clock::now().time_since_epoch();
      } catch (const Error& e) {
        out.status = GrabStatus::Failed;
        out.message = path + ": " + e.what();
      }
    }
    if (xioctl(fd, VIDIOC_QBUF, &buf) != 0 && out.status == GrabStatus::Ok) {
      out.status = GrabStatus::Disconnected;
      out.message = path + ": VIDIOC_QBUF: " + errnoText(errno);
    }
    return out;
  }
};

namespace {
void checkFormat(const V4l2StreamConfig& s, bool depth, const std::string& who) {
  if (s.device.empty() || s.pixel_format.empty()) return;
  const char* field = depth ? "depth.pixel_format" : "color.pixel_format";
  PixelFormat f{};
  try {
    f = pixelFormatFromName(s.pixel_format);
  } catch (const InputError&) {
    throw InputError(who, field, depth ? "Z16" : "YUYV or MJPG", s.pixel_format);
  }
  if (depth ? f != PixelFormat::Z16 : (f != PixelFormat::YUYV && f != PixelFormat::MJPEG))
    throw InputError(who, field, depth ? "Z16" : "YUYV or MJPG", s.pixel_format);
  if (depth && !(s.depth_scale > 0))
    throw InputError(who, "depth.depth_scale", "a positive number of metres per raw unit");
}
}  // namespace

V4l2Source::V4l2Source(V4l2CameraConfig config, fs::path dev_dir)
    : config_(std::move(config)), dev_dir_(std::move(dev_dir)) {
  if (config_.colour.device.empty() && config_.depth.device.empty())
    throw InputError(name(), "device", "a colour or a depth device (/dev/videoN, bus:..., serial:...)");
  checkFormat(config_.colour, false, name());
  checkFormat(config_.depth, true, name());
}

V4l2Source::~V4l2Source() {
  stop();
}

std::string V4l2Source::name() const {
  return config_.name.empty() ? "v4l2:" + serial() : config_.name;
}

std::string V4l2Source::serial() const {
  return config_.colour.device.empty() ? config_.depth.device : config_.colour.device;
}

void V4l2Source::open() {
  stop();
  try {
    if (!config_.colour.device.empty()) {
      colour_ = std::make_unique<V4l2Stream>(config_.colour, false);
      colour_->open(dev_dir_);
    }
    if (!config_.depth.device.empty()) {
      depth_ = std::make_unique<V4l2Stream>(config_.depth, true);
      depth_->open(dev_dir_);
    }
  } catch (...) {
    stop();  // a half-opened source reports Disconnected, never grabs from a dead handle
    throw;
  }
}

void V4l2Source::start() {
  if (colour_) colour_->start();
  if (depth_) depth_->start();
}

void V4l2Source::stop() {
  colour_.reset();
  depth_.reset();
  pairer_.clear();  // a reopened device's frames pair afresh
}

GrabResult V4l2Source::grab(Nanoseconds timeout) {
  if (!colour_ && !depth_) return {GrabStatus::Disconnected, {}, "not open"};
  GrabResult result;
  if (colour_ && depth_) {
    result = grabPair(pairer_, health(), [&](bool colour) {
      V4l2Stream::Popped popped = (colour ? *colour_ : *depth_).pop(timeout);
      return StreamPop{popped.status,
                       {std::move(popped.image), popped.pairing_time, popped.device_time},
                       std::move(popped.message)};
    });
    if (result.status != GrabStatus::Ok) return result;
  } else {
    V4l2Stream::Popped main = (colour_ ? *colour_ : *depth_).pop(timeout);
    if (main.status != GrabStatus::Ok) return {main.status, {}, main.message};
    (colour_ ? result.frame.colour : result.frame.depth) = main.image;
    result.frame.device_time = main.device_time;
  }
  result.status = GrabStatus::Ok;
  result.frame.sequence = sequence_++;
  result.frame.host_time = Clock::now();
  return result;
}

}  // namespace holo::capture
