// A presenter that records what another presenter shows: MP4 and PNG frames of the canvas.
#include <fmt/format.h>

#include "holo/core/error.hpp"
#include "holo/core/log.hpp"
#include "holo/display/frame_output.hpp"
#include "holo/display/quad_view_presenter.hpp"

namespace holo::display {

namespace {

class RecordingPresenter final : public QuadViewPresenter {
 public:
  RecordingPresenter(std::unique_ptr<QuadViewPresenter> inner, RecordingSettings settings)
      : inner_(std::move(inner)), settings_(std::move(settings)) {
    if (!inner_) throw Error("display: recording presenter needs a presenter to record");
    if (settings_.png_every < 0) throw Error("display: png_every must be >= 0");
    std::filesystem::create_directories(settings_.out_dir);
  }

  void present(const FaceImages& face_images, const FaceImages* coverage) override {
    inner_->present(face_images, coverage);
    const cv::Mat canvas = inner_->readBack();
    if (!settings_.video_name.empty()) {
      if (!video_)
        video_ = std::make_unique<VideoFileWriter>(settings_.out_dir / settings_.video_name, canvas.size(),
                                                   settings_.fps);
      video_->write(canvas);
    }
    if (settings_.png_every > 0 && frame_ % settings_.png_every == 0)
      writePngAtomically(settings_.out_dir / fmt::format("frame_{:05d}.png", frame_), canvas);
    ++frame_;
  }
  cv::Mat readBack() override { return inner_->readBack(); }
  bool isOpen() override { return inner_->isOpen(); }
  const DisplayConfig& config() const override { return inner_->config(); }
  const std::array<cv::Rect2f, kFaceCount>& lastCrops() const override { return inner_->lastCrops(); }
  void finish() override {
    inner_->finish();
    if (!video_) return;
    video_->finish();
    HOLO_LOG_INFO("display: wrote {} ({} frames, {})", (settings_.out_dir / settings_.video_name).string(),
                  video_->framesWritten(), video_->fourcc());
  }

 private:
  std::unique_ptr<QuadViewPresenter> inner_;
  RecordingSettings settings_;
  std::unique_ptr<VideoFileWriter> video_;
  long frame_ = 0;
};

}  // namespace

std::unique_ptr<QuadViewPresenter> makeRecordingPresenter(std::unique_ptr<QuadViewPresenter> inner,
                                                          const RecordingSettings& settings) {
  return std::make_unique<RecordingPresenter>(std::move(inner), settings);
}

}  // namespace holo::display
