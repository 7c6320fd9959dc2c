// `holopyramid devices [-v]`: every camera this machine can see, one line each: backend, model,
// serial, address or port, pixel formats, and whether a calibration file exists for it
// (DIR/camera_SERIAL.yml, the calib module's naming). -v adds the GenICam features of Aravis
// cameras, indented under their line.
#include <filesystem>
#include <iostream>

#include "command.hpp"
#include "holo/capture/aravis_source.hpp"
#include "holo/capture/v4l2_source.hpp"
#include "holo/core/error.hpp"

namespace holo::app {
namespace {

namespace fs = std::filesystem;

std::string join(const std::vector<std::string>& items, const char* separator) {
  std::string out;
  for (const auto& s : items) out += (out.empty() ? "" : separator) + s;
  return out;
}

// "yes (PATH)" or "no (PATH)": the path tells the user where calibrate will put it.
std::string calibrationState(const fs::path& dir, const std::string& serial) {
  if (serial.empty()) return "no (the device has no serial)";
  for (char c : serial)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.')
      return "no (serial not usable as a file name)";
  const fs::path path = dir / ("camera_" + serial + ".yml");
  std::error_code ec;
  return (fs::is_regular_file(path, ec) ? "yes (" : "no (") + path.string() + ")";
}

int listDevices(bool verbose, const fs::path& calibration_dir, const fs::path& dev_dir) {
  int count = 0;
  for (const auto& d : capture::listAravisDevices()) {
    std::string formats = "?";
    std::vector<std::string> features;
    try {
      const auto details = capture::describeAravisDevice(d.serial, verbose);
      formats = join(details.pixel_formats, ",");
      features = details.features;
    } catch (const Error& e) {
      formats = std::string("(cannot open: ") + e.what() + ")";
    }
    std::cout << "aravis\t" << d.vendor << " " << d.model << "\tserial " << d.serial << "\t" << d.protocol
              << " " << d.address << "\tformats " << formats << "\tcalibration "
              << calibrationState(calibration_dir, d.serial) << "\n";
    for (const auto& f : features) std::cout << "    " << f << "\n";
    ++count;
  }
  for (const auto& d : capture::listV4l2Devices(dev_dir)) {
    std::cout << "v4l2\t" << d.card << " (" << d.driver << ")\tserial " << (d.serial.empty() ? "-" : d.serial)
              << "\t" << d.path << " " << d.bus_info << "\tformats " << join(d.formats, ",")
              << "\tcalibration " << calibrationState(calibration_dir, d.serial) << "\n";
    ++count;
  }
  if (count == 0)
    std::cout << "no cameras found (Aravis: no GigE Vision or USB3 Vision device answered; V4L2: no capture "
                 "node in "
              << dev_dir.string() << ")\n";
  return 0;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "devices",
    [](CLI::App& sub) {
      struct Options {
        bool verbose = false;
        std::string calibration_dir = "calibration";
        std::string dev_dir = "/dev";
      };
      auto o = std::make_shared<Options>();
      sub.add_flag("-v,--verbose", o->verbose, "List the GenICam features of each camera");
      sub.add_option("--calib-dir", o->calibration_dir, "Folder of calibration files (camera_SERIAL.yml)")
          ->capture_default_str();
      sub.add_option("--dev-dir", o->dev_dir, "Where to look for V4L2 nodes (video*)")->capture_default_str();
      return [o] { return listDevices(o->verbose, o->calibration_dir, o->dev_dir); };
    },
    "List cameras (Aravis GigE/USB3 Vision and V4L2) with serials and formats"});

}  // namespace holo::app
