// `holopyramid display-test`: the alignment test pattern (a letter F per face, in the face's
// colour, with its name) through the real presenter. On the appliance the technician runs it,
// looks into each face of the pyramid and adjusts display.faces[N] (mirror, rotation, offset,
// scale) until every viewer reads an upright, unmirrored F in the middle of the glass. With
// --headless it writes the quad view as a PNG instead (what the monitors would show).
#include <fmt/format.h>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <memory>
#include <thread>

#include "command.hpp"
#include "holo/core/stopwatch.hpp"
#include "holo/display/display_config.hpp"
#include "holo/display/frame_output.hpp"
#include "holo/display/quad_view_presenter.hpp"
#include "holo/display/test_pattern.hpp"

namespace holo::app {
namespace {

struct DisplayTestOptions {
  std::string config_file;
  std::string layout;
  bool headless = false;
  bool windowed = false;
  std::string out = "out/display-test";
  int face_size = 512;
  double seconds = 0.0;
};

void describeLayout(const display::DisplayConfig& config, std::ostream& out) {
  out << "layout: " << display::layoutName(config.layout) << " (settings from " << config.source << ")\n";
  for (int f = 0; f < display::kFaceCount; ++f) {
    const display::FaceSettings& face = config.faces[static_cast<std::size_t>(f)];
    const cv::Rect2f view = display::viewRect(config, f, config.output_size);
    out << fmt::format(
        "face {} ({}): output {}, view {}x{} at ({}, {}), rotation {} deg, mirror {}, offset ({}, {}), "
        "scale {}\n",
        f, display::faceName(f), config.layout == display::LayoutKind::Monitors ? f : 0, view.width,
        view.height, view.x, view.y, display::layoutRotationDeg(config.layout, f) + face.rotation_deg,
        face.mirror ? "yes" : "no", face.offset.x, face.offset.y, face.scale);
  }
}

int runDisplayTest(const DisplayTestOptions& options) {
  display::DisplayConfig config = options.config_file.empty()
                                      ? display::DisplayConfig{}
                                      : display::loadDisplayConfig(options.config_file);
  if (!options.layout.empty()) config.layout = display::parseLayoutKind(options.layout, "command line");
  if (options.windowed) config.fullscreen = false;
  describeLayout(config, std::cout);

  display::FaceImages faces;
  for (int f = 0; f < display::kFaceCount; ++f)
    faces[static_cast<std::size_t>(f)] = display::testPatternFace(f, {options.face_size, options.face_size});

  if (options.headless) {
    auto presenter = display::makeHeadlessPresenter(config);
    presenter->present(faces);
    const std::filesystem::path path = std::filesystem::path(options.out) /
                                       fmt::format("display-test-{}.png", display::layoutName(config.layout));
    std::filesystem::create_directories(path.parent_path());
    display::writePngAtomically(path, presenter->readBack());
    std::cout << "wrote " << path.string() << "\n";
    return 0;
  }
  auto presenter = display::makeWindowPresenter(config);
  std::cout << "showing the test pattern; Escape or closing a window ends it\n";
  const Stopwatch shown;
  while (presenter->isOpen()) {
    presenter->present(faces);
    if (options.seconds > 0.0 && shown.seconds() >= options.seconds) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));  // a still picture needs no 60 fps
  }
  return 0;
}

}  // namespace

HOLO_REGISTER_COMMAND(Command{
    "display-test",
    [](CLI::App& sub) {
      auto options = std::make_shared<DisplayTestOptions>();
      sub.add_option("--config", options->config_file, "YAML file with a display: section");
      sub.add_option("--layout", options->layout, "monitors or cross (overrides the config)");
      sub.add_flag("--headless", options->headless, "Render through EGL and write a PNG instead of windows");
      sub.add_option("--out", options->out, "Folder for the headless PNG")->capture_default_str();
      sub.add_flag("--windowed", options->windowed, "Plain windows instead of fullscreen monitors");
      sub.add_option("--face-size", options->face_size, "Side of each face's pattern, pixels")
          ->check(CLI::Range(16, 8192))
          ->capture_default_str();
      sub.add_option("--seconds", options->seconds, "Windows: close after this long (0: until Escape)")
          ->check(CLI::NonNegativeNumber);
      return [options] { return runDisplayTest(*options); };
    },
    "Show the monitor alignment test pattern (or write it with --headless)"});

}  // namespace holo::app
