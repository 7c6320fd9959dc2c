#include "holo/capture/aravis_source.hpp"

#include <arv.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <functional>
#include <mutex>

#include "holo/core/error.hpp"
#include "holo/core/log.hpp"

namespace holo::capture {

namespace {

// Aravis keeps one global device list; discovery and opening go through it one caller at a time.
std::mutex& aravisMutex() {
  static std::mutex m;
  return m;
}

std::string takeError(GError*& error) {
  std::string message = error ? error->message : "unknown error";
  g_clear_error(&error);
  return message;
}

void check(GError*& error, const std::string& what) {
  if (error) throw Error(what + ": " + takeError(error));
}

struct Found {
  std::string id;
  std::string address;
};

// Must be called with aravisMutex() held.
Found findBySerial(const std::string& serial) {
  arv_update_device_list();
  std::string seen;
  for (unsigned i = 0; i < arv_get_n_devices(); ++i) {
    const char* s = arv_get_device_serial_nbr(i);
    if (s && serial == s)
      return {arv_get_device_id(i), arv_get_device_address(i) ? arv_get_device_address(i) : ""};
    seen += std::string(seen.empty() ? "" : ", ") + (s ? s : "?");
  }
  throw Error("aravis: no camera with serial " + serial + " (found: " + (seen.empty() ? "none" : seen) + ")");
}

ArvCamera* openCamera(const std::string& serial, std::string* address) {
  std::lock_guard lock(aravisMutex());
  const Found found = findBySerial(serial);
  if (address) *address = found.address;
  GError* error = nullptr;
  ArvCamera* camera = arv_camera_new(found.id.c_str(), &error);
  if (!camera) throw Error("aravis: cannot open camera " + serial + ": " + takeError(error));
  return camera;
}

std::vector<std::string> availableFormats(ArvCamera* camera) {
  guint n = 0;
  GError* error = nullptr;
  const char** names = arv_camera_dup_available_pixel_formats_as_strings(camera, &n, &error);
  std::vector<std::string> out;
  for (guint i = 0; i < n; ++i) out.emplace_back(names[i]);
  g_free(names);
  g_clear_error(&error);
  return out;
}

std::string join(const std::vector<std::string>& items) {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "" : ", ") + s;
  return out;
}

void onControlLost(ArvDevice*, gpointer flag) {
  static_cast<std::atomic<bool>*>(flag)->store(true);
}

}  // namespace

struct AravisDevice {
  AravisStreamConfig config;
  bool is_depth = false;
  ArvCamera* camera = nullptr;
  ArvStream* stream = nullptr;
  gulong lost_handler = 0;
  std::atomic<bool> control_lost{false};
  PixelFormat format = PixelFormat::Mono8;

  AravisDevice(AravisStreamConfig c, bool depth) : config(std::move(c)), is_depth(depth) {}
  ~AravisDevice() { close(); }

  void open() {
    std::string address;
    camera = openCamera(config.serial, &address);
    control_lost = false;
    lost_handler = g_signal_connect(arv_camera_get_device(camera), "control-lost", G_CALLBACK(onControlLost),
                                    &control_lost);
    GError* error = nullptr;
    const std::string who = "aravis camera " + config.serial;
    const auto offered = availableFormats(camera);
    if (!config.pixel_format.empty()) {
      if (std::find(offered.begin(), offered.end(), config.pixel_format) == offered.end())
        throw InputError(who, "pixel_format", "one the camera offers: " + join(offered), config.pixel_format);
      arv_camera_set_pixel_format_from_string(camera, config.pixel_format.c_str(), &error);
      check(error, who + ": setting PixelFormat " + config.pixel_format);
    }
    if (config.width > 0 && config.height > 0) {
      arv_camera_set_region(camera, 0, 0, config.width, config.height, &error);
      check(error,
            who + ": setting region " + std::to_string(config.width) + "x" + std::to_string(config.height));
    }
    if (config.frame_rate > 0) {
      arv_camera_set_frame_rate(camera, config.frame_rate, &error);
      check(error, who + ": setting AcquisitionFrameRate");
    }
    for (const auto& [feature, value] : config.features) {
      ArvGcNode* node = arv_device_get_feature(arv_camera_get_device(camera), feature.c_str());
      if (!node || !ARV_IS_GC_FEATURE_NODE(node))
        throw InputError(who, "features." + feature,
                         "a GenICam feature of this camera (see `holopyramid devices -v`)",
                         "no such feature");
      arv_gc_feature_node_set_value_from_string(ARV_GC_FEATURE_NODE(node), value.c_str(), &error);
      if (error)
        throw InputError(who, "features." + feature, "a value the camera accepts",
                         value + " (" + takeError(error) + ")");
    }
    // Read back last: a feature may have changed the format.
    const char* current = arv_camera_get_pixel_format_as_string(camera, &error);
    check(error, who + ": reading PixelFormat");
    try {
      format = pixelFormatFromName(current ? current : "");
    } catch (const InputError&) {
      throw InputError(who, "pixel_format",
                       "a format this program converts (" + join(pixelFormatNames()) +
                           "); the camera offers " + join(offered),
                       current ? current : "?");
    }
    if (is_depth && format != PixelFormat::Mono16 && format != PixelFormat::Coord3D_C16)
      throw InputError(who, "depth.pixel_format", "Mono16 or Coord3D_C16 for a depth stream",
                       toString(format));
    if (arv_camera_is_gv_device(camera)) {
      const bool loopback = address.rfind("127.", 0) == 0;
      const bool disable = config.packet_socket == AravisStreamConfig::PacketSocket::Off ||
                           (config.packet_socket == AravisStreamConfig::PacketSocket::Auto && loopback);
      arv_camera_gv_set_stream_options(
          camera, disable ? ARV_GV_STREAM_OPTION_PACKET_SOCKET_DISABLED : ARV_GV_STREAM_OPTION_NONE);
    }
    stream = arv_camera_create_stream(camera, nullptr, nullptr, &error);
    if (!stream) throw Error(who + ": cannot create stream: " + takeError(error));
    // A receive buffer as large as one frame: the default (~200 kB) loses packets of bigger frames.
    if (ARV_IS_GV_STREAM(stream))
      g_object_set(stream, "socket-buffer", ARV_GV_STREAM_SOCKET_BUFFER_AUTO, nullptr);
    const guint payload = arv_camera_get_payload(camera, &error);
    check(error, who + ": reading PayloadSize");
    // The camera announces its size; buffers are allocated from it, so a broken or hostile
    // device claiming 64k x 64k must be refused here, not by the allocator.
    gint x = 0, y = 0, width = 0, height = 0;
    arv_camera_get_region(camera, &x, &y, &width, &height, &error);
    check(error, who + ": reading the region");
    checkFrameSize(who, "width/height", width, height);
    if (payload == 0 || payload > kMaxFrameBytes)
      throw InputError(who, "PayloadSize", "1 to " + std::to_string(kMaxFrameBytes) + " bytes a frame",
                       std::to_string(payload));
    for (int i = 0; i < std::max(2, config.buffers); ++i)
      arv_stream_push_buffer(stream, arv_buffer_new(payload, nullptr));
    arv_camera_set_acquisition_mode(camera, ARV_ACQUISITION_MODE_CONTINUOUS, &error);
    check(error, who + ": setting AcquisitionMode");
  }

  void start() {
    GError* error = nullptr;
    arv_camera_start_acquisition(camera, &error);
    check(error, "aravis camera " + config.serial + ": AcquisitionStart");
  }

  std::int64_t resends() const {
    if (!stream || !ARV_IS_GV_STREAM(stream)) return 0;
    guint64 resent = 0, missing = 0;
    arv_gv_stream_get_statistics(ARV_GV_STREAM(stream), &resent, &missing);
    return static_cast<std::int64_t>(resent);
  }

  void close() {
    if (camera) {
      GError* error = nullptr;
      arv_camera_stop_acquisition(camera, &error);  // fails harmlessly when the camera is gone
      g_clear_error(&error);
      if (lost_handler) g_signal_handler_disconnect(arv_camera_get_device(camera), lost_handler);
      lost_handler = 0;
    }
    if (stream) g_object_unref(stream);  // joins the stream thread, frees the buffers
    stream = nullptr;
    if (camera) g_object_unref(camera);
    camera = nullptr;
  }
};

namespace {

struct Popped {
  GrabStatus status = GrabStatus::Timeout;
  cv::Mat image;
  Nanoseconds device_time{0};
  Nanoseconds host_time{0};  // arrival, on the host's clock (common to both devices)
  std::string message;
};

// Pops one buffer, converts it when complete, and always gives the buffer back to the pool.
template <class Convert>
Popped popOne(AravisDevice& d, Nanoseconds timeout, bool wait, Convert convert) {
  Popped out;
  const auto us = static_cast<guint64>(std::max<std::int64_t>(0, timeout.count() / 1000));
  ArvBuffer* buffer =
      wait ? arv_stream_timeout_pop_buffer(d.stream, us) : arv_stream_try_pop_buffer(d.stream);
  if (!buffer) {
    out.status = d.control_lost ? GrabStatus::Disconnected : GrabStatus::Timeout;
    out.message = d.control_lost ? "lost control of camera " + d.config.serial : "no buffer";
    return out;
  }
  const ArvBufferStatus status = arv_buffer_get_status(buffer);
  if (status == ARV_BUFFER_STATUS_SUCCESS) {
    size_t size = 0;
    const void* data = arv_buffer_get_image_data(buffer, &size);
    try {
      out.image = convert(
          RawImage{data, size, arv_buffer_get_image_width(buffer), arv_buffer_get_image_height(buffer), 0});
      out.status = GrabStatus::Ok;
      const guint64 t = arv_buffer_get_timestamp(buffer);
      // Arrival on the host's real-time clock; a stream that does not stamp it (0) gets the time
      // it is popped, on the same clock.
      const guint64 arrival = arv_buffer_get_system_timestamp(buffer);
      out.host_time =
          arrival
              ? Nanoseconds(static_cast<std::int64_t>(arrival))
              : std::chrono::duration_cast<Nanoseconds>(std::chrono::system_clock::now().time_since_epoch());
      out.device_time = t ? Nanoseconds(static_cast<std::int64_t>(t)) : out.host_time;
    } catch (const Error& e) {
      out.status = GrabStatus::Failed;
      out.message = e.what();
    }
  } else if (status == ARV_BUFFER_STATUS_MISSING_PACKETS || status == ARV_BUFFER_STATUS_TIMEOUT ||
             status == ARV_BUFFER_STATUS_ABORTED || status == ARV_BUFFER_STATUS_SIZE_MISMATCH) {
    out.status = GrabStatus::Incomplete;
    out.message = "incomplete buffer (status " + std::to_string(static_cast<int>(status)) + ")";
  } else {
    out.status = GrabStatus::Failed;
    out.message = "buffer error (status " + std::to_string(static_cast<int>(status)) + ")";
  }
  arv_stream_push_buffer(d.stream, buffer);  // re-queue: the pool never shrinks
  return out;
}

}  // namespace

AravisSource::AravisSource(AravisCameraConfig config) : config_(std::move(config)) {
  if (config_.colour.serial.empty() && config_.depth.serial.empty())
    throw InputError(config_.name, "serial", "a colour or a depth serial number");
}

AravisSource::~AravisSource() {
  stop();
}

std::string AravisSource::name() const {
  if (!config_.name.empty()) return config_.name;
  return "aravis:" + serial();
}

std::string AravisSource::serial() const {
  return config_.colour.serial.empty() ? config_.depth.serial : config_.colour.serial;
}

void AravisSource::open() {
  stop();
  try {
    if (!config_.colour.serial.empty()) {
      colour_ = std::make_unique<AravisDevice>(config_.colour, false);
      colour_->open();
    }
    if (!config_.depth.serial.empty()) {
      depth_ = std::make_unique<AravisDevice>(config_.depth, true);
      depth_->open();
    }
  } catch (...) {
    stop();  // a half-opened source reports Disconnected, never grabs from a dead handle
    throw;
  }
}

void AravisSource::start() {
  if (colour_) colour_->start();
  if (depth_) depth_->start();
}

void AravisSource::stop() {
  std::int64_t resends = 0;
  if (colour_) resends += colour_->resends();
  if (depth_) resends += depth_->resends();
  resends_before_ += resends;
  colour_.reset();
  depth_.reset();
  pairer_.clear();  // a reopened device's frames pair afresh
}

GrabResult AravisSource::grab(Nanoseconds timeout) {
  if (!colour_ && !depth_) return {GrabStatus::Disconnected, {}, "not open"};
  const double scale = config_.depth.depth_scale;
  auto toColour = [&](const RawImage& raw) { return convertToColour(colour_->format, raw); };
  auto toDepth = [&](const RawImage& raw) { return convertToDepth(depth_->format, raw, scale); };

  GrabResult result;
  const auto countResends = [&] {
    health().resends.store(
        resends_before_ + (colour_ ? colour_->resends() : 0) + (depth_ ? depth_->resends() : 0),
        std::memory_order_relaxed);
  };
  if (colour_ && depth_) {
    // Two devices: colour and depth paired by arrival time (frame_pairing.hpp).
    result = grabPair(pairer_, health(), [&](bool colour) {
      Popped popped =
          colour ? popOne(*colour_, timeout, true, toColour) : popOne(*depth_, timeout, true, toDepth);
      countResends();
      return StreamPop{popped.status,
                       {std::move(popped.image), popped.host_time, popped.device_time},
                       std::move(popped.message)};
    });
    if (result.status != GrabStatus::Ok) return result;
  } else {
    Popped main =
        colour_ ? popOne(*colour_, timeout, true, toColour) : popOne(*depth_, timeout, true, toDepth);
    countResends();
    if (main.status != GrabStatus::Ok) return {main.status, {}, main.message};
    (colour_ ? result.frame.colour : result.frame.depth) = main.image;
    result.frame.device_time = main.device_time;
  }
  result.status = GrabStatus::Ok;
  result.frame.sequence = sequence_++;
  result.frame.host_time = Clock::now();
  return result;
}

std::vector<AravisDeviceInfo> listAravisDevices() {
  std::lock_guard lock(aravisMutex());
  arv_update_device_list();
  std::vector<AravisDeviceInfo> out;
  auto text = [](const char* s) { return std::string(s ? s : ""); };
  for (unsigned i = 0; i < arv_get_n_devices(); ++i)
    out.push_back({text(arv_get_device_id(i)), text(arv_get_device_vendor(i)), text(arv_get_device_model(i)),
                   text(arv_get_device_serial_nbr(i)), text(arv_get_device_address(i)),
                   text(arv_get_device_protocol(i))});
  return out;
}

namespace {
void collectFeatures(ArvGc* genicam, const char* name, int level, std::vector<std::string>& out) {
  ArvGcNode* node = arv_gc_get_node(genicam, name);
  if (!node || level > 8) return;
  if (ARV_IS_GC_CATEGORY(node)) {
    for (const GSList* f = arv_gc_category_get_features(ARV_GC_CATEGORY(node)); f; f = f->next)
      collectFeatures(genicam, static_cast<const char*>(f->data), level + 1, out);
    return;
  }
  if (!ARV_IS_GC_FEATURE_NODE(node) || ARV_IS_GC_COMMAND(node)) return;
  GError* error = nullptr;
  ArvGcFeatureNode* feature = ARV_GC_FEATURE_NODE(node);
  if (!arv_gc_feature_node_is_implemented(feature, &error) ||
      !arv_gc_feature_node_is_available(feature, &error)) {
    g_clear_error(&error);
    return;
  }
  const char* value = arv_gc_feature_node_get_value_as_string(feature, &error);
  out.push_back(std::string(name) + " = " + (error ? "(unreadable)" : (value ? value : "")));
  g_clear_error(&error);
}
}  // namespace

AravisDeviceDetails describeAravisDevice(const std::string& serial, bool features) {
  ArvCamera* camera = openCamera(serial, nullptr);
  AravisDeviceDetails details;
  details.pixel_formats = availableFormats(camera);
  if (features) {
    ArvGc* genicam = arv_device_get_genicam(arv_camera_get_device(camera));
    if (genicam) collectFeatures(genicam, "Root", 0, details.features);
  }
  g_object_unref(camera);
  return details;
}

}  // namespace holo::capture
