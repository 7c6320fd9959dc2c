#include "holo/calib/calibration_wizard.hpp"

#define GL_GLEXT_PROTOTYPES 1
#include <GL/gl.h>
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>

#include <algorithm>
#include <chrono>
#include <future>
#include <mutex>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>
#include <vector>

#include "holo/core/error.hpp"

namespace holo::calib {

namespace fs = std::filesystem;

namespace {

std::string& lastGlfwError() {
  static std::string message;
  return message;
}

void onGlfwError(int code, const char* description) {
  lastGlfwError() =
      std::string(description ? description : "") + " (GLFW error " + std::to_string(code) + ")";
}

const ImVec4 kPass{0.35f, 0.85f, 0.35f, 1.0f};
const ImVec4 kFail{1.0f, 0.4f, 0.3f, 1.0f};
const ImVec4 kPending{0.6f, 0.6f, 0.6f, 1.0f};
const ImVec4 kHint{1.0f, 0.75f, 0.3f, 1.0f};

// One picture on the GPU. Pictures larger than the window are shrunk first: the preview never
// shows them bigger, and uploading less keeps the frame rate up on software OpenGL.
struct Texture {
  GLuint id = 0;
  int width = 0;
  int height = 0;
  std::string label;

  void upload(const cv::Mat& bgr, int max_width) {
    cv::Mat picture = bgr;
    if (picture.cols > max_width)
      cv::resize(picture, picture, cv::Size(max_width, std::max(1, picture.rows * max_width / picture.cols)),
                 0, 0, cv::INTER_AREA);
    cv::Mat rgba;
    cv::cvtColor(picture, rgba, picture.channels() == 1 ? cv::COLOR_GRAY2RGBA : cv::COLOR_BGR2RGBA);
    if (id == 0) glGenTextures(1, &id);
    glBindTexture(GL_TEXTURE_2D, id);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA, rgba.cols, rgba.rows, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data);
    width = rgba.cols;
    height = rgba.rows;
  }
  void release() {
    if (id != 0) glDeleteTextures(1, &id);
    id = 0;
  }
};

// Pictures the measuring thread delivers, picked up by the next frame.
struct LivePictures {
  std::mutex mutex;
  std::vector<std::pair<std::string, cv::Mat>> pictures;  // by preview index
  bool changed = false;

  void put(int index, const std::string& label, const cv::Mat& picture) {
    std::lock_guard lock(mutex);
    if (static_cast<int>(pictures.size()) <= index) pictures.resize(static_cast<std::size_t>(index) + 1);
    pictures[static_cast<std::size_t>(index)] = {label, picture.clone()};
    changed = true;
  }
};

void verdictTable(const std::vector<calib::StepVerdict>& verdicts) {
  constexpr ImGuiTableFlags flags =
      ImGuiTableFlags_Borders | ImGuiTableFlags_RowBg | ImGuiTableFlags_SizingStretchProp;
  if (!ImGui::BeginTable("verdicts", 5, flags)) return;
  ImGui::TableSetupColumn("check", ImGuiTableColumnFlags_WidthStretch, 1.2f);
  ImGui::TableSetupColumn("quality figure", ImGuiTableColumnFlags_WidthStretch, 2.0f);
  ImGui::TableSetupColumn("measured", ImGuiTableColumnFlags_WidthStretch, 0.6f);
  ImGui::TableSetupColumn("must be", ImGuiTableColumnFlags_WidthStretch, 0.6f);
  ImGui::TableSetupColumn("verdict", ImGuiTableColumnFlags_WidthStretch, 0.5f);
  ImGui::TableHeadersRow();
  for (const calib::StepVerdict& v : verdicts) {
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(v.step.c_str());
    ImGui::TableNextColumn();
    ImGui::TextUnformatted(v.figure.c_str());
    ImGui::TableNextColumn();
    ImGui::Text("%.3g", v.value);
    ImGui::TableNextColumn();
    // Correlation must reach its threshold; every other figure must stay below it.
    ImGui::Text("%s %.3g", v.figure.find("correlation") != std::string::npos ? ">=" : "<", v.threshold);
    ImGui::TableNextColumn();
    ImGui::TextColored(v.pass ? kPass : kFail, "%s", v.pass ? "PASS" : "FAIL");
  }
  ImGui::EndTable();
}

}  // namespace

struct CalibrationWizard::Impl {
  calib::CalibrationSession& session;
  WizardWindowOptions options;
  GLFWwindow* window = nullptr;
  int step = 0;
  std::future<void> measuring;
  std::ostringstream log;  // the steps' log; the measuring thread writes it only while busy()
  LivePictures live;
  std::vector<Texture> textures;
  int generation = 0;         // counts measurements: a new one changes what the textures show
  int shown_step = -1;        // the step whose pictures the textures hold
  int shown_generation = -1;  // -1 while they hold live pictures
  std::optional<Button> pending;
  bool closed = false;
  std::vector<fs::path> saved_files;
  std::string save_error;

  Impl(calib::CalibrationSession& s, WizardWindowOptions o) : session(s), options(std::move(o)) {}

  CalibrationStep current() const { return static_cast<CalibrationStep>(step); }
  bool busy() const {
    return measuring.valid() && measuring.wait_for(std::chrono::seconds(0)) != std::future_status::ready;
  }
  bool stepPassed(int s) const {
    const auto& outcome = session.outcome(static_cast<CalibrationStep>(s));
    return outcome && outcome->passed();
  }

  bool enabled(Button button) const {
    if (busy()) return button == Button::Close;
    const bool save_step = current() == CalibrationStep::Save;
    switch (button) {
      case Button::Back:
        return step > 0;
      case Button::Retry:
        return !save_step;
      case Button::Next:
        return !save_step && stepPassed(step);
      case Button::Save:
        return save_step && saved_files.empty() && session.report().allPassed();
      case Button::Close:
        return true;
    }
    return false;
  }

  void startMeasuring() {
    {
      std::lock_guard lock(live.mutex);
      live.pictures.clear();
      live.changed = true;
    }
    ++generation;
    saved_files.clear();
    const CalibrationStep s = current();
    measuring = std::async(std::launch::async, [this, s] {
      session.measure(s, log, true, [this](int index, const std::string& label, const cv::Mat& picture) {
        live.put(index, label, picture);
      });
    });
  }

  // Finishes a measurement that has ended: errors other than the step's own (those are in its
  // outcome) end the wizard.
  void collect() {
    if (measuring.valid() && !busy()) measuring.get();
  }

  void apply(Button button) {
    switch (button) {
      case Button::Back:
        --step;
        break;
      case Button::Retry:
        startMeasuring();
        break;
      case Button::Next:
        ++step;
        // A step measured before, with nothing before it changed since, keeps its outcome.
        if (current() != CalibrationStep::Save && !session.measured(current())) startMeasuring();
        break;
      case Button::Save:
        save_error.clear();
        try {
          saved_files = session.save(options.out_dir, log);
        } catch (const std::exception& e) {
          save_error = e.what();
        }
        break;
      case Button::Close:
        closed = true;
        break;
    }
  }

  // The pictures to show: live ones while measuring, else the step's outcome.
  void refreshTextures() {
    std::vector<std::pair<std::string, cv::Mat>> pictures;
    if (busy()) {
      std::lock_guard lock(live.mutex);
      if (!live.changed && shown_step == step) return;
      pictures = live.pictures;
      live.changed = false;
      shown_generation = -1;
    } else {
      if (shown_step == step && shown_generation == generation) return;
      if (const auto& outcome = session.outcome(current())) pictures = outcome->previews;
      shown_generation = generation;
    }
    shown_step = step;
    const int max_width = options.width / 2;
    textures.resize(std::max(textures.size(), pictures.size()));
    for (std::size_t i = 0; i < textures.size(); ++i) {
      if (i >= pictures.size() || pictures[i].second.empty()) {
        textures[i].release();
        textures[i].label.clear();
        continue;
      }
      textures[i].upload(pictures[i].second, max_width);
      textures[i].label = pictures[i].first;
    }
  }

  // While busy() the measuring thread owns the step being measured and the ones after it (it
  // resets them); they show as pending. Earlier steps are only read by both.
  void drawStepList(bool is_busy) {
    for (int s = 0; s < calib::kCalibrationSteps; ++s) {
      if (s > 0) ImGui::SameLine(0.0f, 14.0f);
      ImVec4 colour = kPending;
      if (s == calib::kCalibrationSteps - 1) {
        colour = saved_files.empty() ? kPending : kPass;
      } else if (!is_busy || s < step) {
        if (const auto& outcome = session.outcome(static_cast<CalibrationStep>(s)))
          colour = outcome->passed() ? kPass : kFail;
      }
      const std::string text =
          std::to_string(s + 1) + " " + calib::stepTitle(static_cast<CalibrationStep>(s));
      ImGui::TextColored(colour, s == step ? "[%s]" : " %s ", text.c_str());
    }
  }

  void drawPreviews() {
    const float avail = ImGui::GetContentRegionAvail().x;
    const float spacing = ImGui::GetStyle().ItemSpacing.x;
    constexpr int kColumns = 4;
    const float cell = (avail - spacing * (kColumns - 1)) / kColumns;
    int column = 0;
    for (const Texture& t : textures) {
      if (t.id == 0) continue;
      // Wide pictures (the panorama) get a row of their own, as wide as two cells.
      const bool wide = t.width > 3 * t.height;
      if (column > 0 && (wide || column == kColumns)) column = 0;
      if (column > 0) ImGui::SameLine();
      const float w = wide ? 2 * cell + spacing : cell;
      const float h = std::min(w * static_cast<float>(t.height) / static_cast<float>(t.width), 0.62f * cell);
      const float shown_w = h * static_cast<float>(t.width) / static_cast<float>(t.height);
      ImGui::BeginGroup();
      ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<std::intptr_t>(t.id)), ImVec2(shown_w, h));
      ImGui::TextUnformatted(t.label.c_str());
      ImGui::EndGroup();
      column = wide ? kColumns : column + 1;
    }
  }

  void drawHints(const calib::StepOutcome& outcome) {
    if (!outcome.error.empty()) {
      ImGui::TextColored(kFail, "Could not measure this step:");
      ImGui::PushStyleColor(ImGuiCol_Text, kHint);
      ImGui::TextWrapped("%s", outcome.error.c_str());
      ImGui::PopStyleColor();
    }
    for (const calib::StepVerdict& v : outcome.verdicts)
      if (!v.pass && !v.hint.empty()) {
        ImGui::PushStyleColor(ImGuiCol_Text, kHint);
        ImGui::TextWrapped("%s: %s", v.step.c_str(), v.hint.c_str());
        ImGui::PopStyleColor();
      }
  }

  void drawSaveStep() {
    ImGui::TextUnformatted("Every step's result:");
    verdictTable(session.report().verdicts);
    ImGui::Spacing();
    ImGui::Text("Output folder: %s", options.out_dir.string().c_str());
    if (!saved_files.empty())
      ImGui::TextColored(kPass,
                         "Saved %zu files. The calibration is in use from the next start; the previous one "
                         "is kept as .bak.",
                         saved_files.size());
    if (!save_error.empty()) {
      ImGui::TextColored(kFail, "Saving failed; the previous calibration is untouched:");
      ImGui::TextWrapped("%s", save_error.c_str());
    }
  }

  // One button; the scripted press of the same button runs the same branch.
  bool button(Button which, const char* label) {
    ImGui::BeginDisabled(!enabled(which));
    bool clicked = ImGui::Button(label, ImVec2(120.0f, 0.0f));
    ImGui::EndDisabled();
    if (pending == which) {
      clicked = true;
      pending.reset();
    }
    return clicked;
  }

  void draw() {
    const ImGuiViewport* viewport = ImGui::GetMainViewport();
    ImGui::SetNextWindowPos(viewport->WorkPos);
    ImGui::SetNextWindowSize(viewport->WorkSize);
    ImGui::Begin("wizard", nullptr,
                 ImGuiWindowFlags_NoDecoration | ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoSavedSettings);
    const bool is_busy = busy();
    ImGui::Text("Holopyramid calibration - %s", options.source.c_str());
    drawStepList(is_busy);
    ImGui::Separator();
    ImGui::Text("Step %d of %d: %s", step + 1, calib::kCalibrationSteps, calib::stepTitle(current()));
    ImGui::TextWrapped("%s", calib::stepInstructions(current()));
    ImGui::Separator();

    if (current() == CalibrationStep::Save) {
      drawSaveStep();
    } else {
      drawPreviews();
      ImGui::Separator();
      if (is_busy) {
        ImGui::TextColored(kHint, "Measuring... the pictures above are the cameras' as they arrive.");
      } else if (const auto& outcome = session.outcome(current())) {
        verdictTable(outcome->verdicts);
        drawHints(*outcome);
        if (outcome->passed()) ImGui::TextColored(kPass, "This step passed: press Next.");
      }
    }

    ImGui::SetCursorPosY(ImGui::GetWindowHeight() - ImGui::GetFrameHeightWithSpacing() - 8.0f);
    ImGui::Separator();
    std::optional<Button> clicked;
    if (button(Button::Back, "< Back")) clicked = Button::Back;
    ImGui::SameLine();
    if (button(Button::Retry, "Retry")) clicked = Button::Retry;
    ImGui::SameLine();
    if (current() == CalibrationStep::Save) {
      if (button(Button::Save, "Save")) clicked = Button::Save;
    } else if (button(Button::Next, "Next >")) {
      clicked = Button::Next;
    }
    ImGui::SameLine();
    if (button(Button::Close, "Close")) clicked = Button::Close;
    ImGui::End();
    if (clicked) apply(*clicked);
  }
};

CalibrationWizard::CalibrationWizard(calib::CalibrationSession& session, WizardWindowOptions options)
    : impl_(std::make_unique<Impl>(session, std::move(options))) {
  glfwSetErrorCallback(onGlfwError);
  if (!glfwInit())
    throw Error("calibration wizard: cannot open a window (" + lastGlfwError() +
                "); is DISPLAY set? Use `holopyramid calibrate --auto` on a machine without a screen");
  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_FALSE);
  impl_->window = glfwCreateWindow(impl_->options.width, impl_->options.height, "Holopyramid calibration",
                                   nullptr, nullptr);
  if (!impl_->window) {
    glfwTerminate();
    throw Error("calibration wizard: cannot create an OpenGL 3.3 window (" + lastGlfwError() + ")");
  }
  glfwMakeContextCurrent(impl_->window);
  glfwSwapInterval(1);
  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini beside the technician's files
  ImGui::StyleColorsDark();
  ImGui_ImplGlfw_InitForOpenGL(impl_->window, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");
  impl_->startMeasuring();
}

CalibrationWizard::~CalibrationWizard() {
  // The measuring thread uses the session and the log: let it finish before they go.
  if (impl_->measuring.valid()) impl_->measuring.wait();
  for (Texture& t : impl_->textures) t.release();
  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(impl_->window);
  glfwTerminate();
}

bool CalibrationWizard::frame(const fs::path& screenshot) {
  if (impl_->closed) return false;
  // Waiting for input (at most a frame at 30 Hz) rather than polling leaves the CPU to the
  // measuring thread; there is no vsync to pace the loop under Xvfb.
  glfwWaitEventsTimeout(1.0 / 30.0);
  if (glfwWindowShouldClose(impl_->window) || glfwGetKey(impl_->window, GLFW_KEY_ESCAPE) == GLFW_PRESS)
    impl_->closed = true;
  impl_->collect();
  impl_->refreshTextures();
  ImGui_ImplOpenGL3_NewFrame();
  ImGui_ImplGlfw_NewFrame();
  ImGui::NewFrame();
  impl_->draw();
  ImGui::Render();
  int width = 0, height = 0;
  glfwGetFramebufferSize(impl_->window, &width, &height);
  glViewport(0, 0, width, height);
  glClearColor(0.08f, 0.08f, 0.1f, 1.0f);
  glClear(GL_COLOR_BUFFER_BIT);
  ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
  if (!screenshot.empty()) {
    cv::Mat rgb(height, width, CV_8UC3);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadBuffer(GL_BACK);
    glReadPixels(0, 0, width, height, GL_RGB, GL_UNSIGNED_BYTE, rgb.data);
    cv::Mat bgr;
    cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
    cv::flip(bgr, bgr, 0);  // OpenGL's rows run bottom-up
    if (!screenshot.parent_path().empty()) fs::create_directories(screenshot.parent_path());
    if (!cv::imwrite(screenshot.string(), bgr, {cv::IMWRITE_PNG_COMPRESSION, 9}))
      throw Error("could not write " + screenshot.string());
  }
  glfwSwapBuffers(impl_->window);
  return !impl_->closed;
}

void CalibrationWizard::press(Button button, const std::string& source) {
  if (!enabled(button)) {
    std::string why = busy() ? "the step is still being measured" : "the button is disabled";
    if (button == Button::Next && !busy()) why = "the step has not passed";
    throw InputError(source, buttonName(button),
                     std::string("an enabled button at step ") + calib::stepTitle(step()), why);
  }
  impl_->pending = button;
}

bool CalibrationWizard::enabled(Button button) const {
  return impl_->enabled(button);
}
bool CalibrationWizard::busy() const {
  return impl_->busy();
}
CalibrationStep CalibrationWizard::step() const {
  return impl_->current();
}
std::string CalibrationWizard::log() const {
  return busy() ? std::string() : impl_->log.str();
}
int CalibrationWizard::livePictureCount() const {
  std::lock_guard lock(impl_->live.mutex);
  return static_cast<int>(std::count_if(impl_->live.pictures.begin(), impl_->live.pictures.end(),
                                        [](const auto& picture) { return !picture.second.empty(); }));
}
bool CalibrationWizard::saved() const {
  return !impl_->saved_files.empty();
}

const char* buttonName(CalibrationWizard::Button button) {
  switch (button) {
    case CalibrationWizard::Button::Back:
      return "back";
    case CalibrationWizard::Button::Retry:
      return "retry";
    case CalibrationWizard::Button::Next:
      return "next";
    case CalibrationWizard::Button::Save:
      return "save";
    case CalibrationWizard::Button::Close:
      return "close";
  }
  return "?";
}

}  // namespace holo::calib
