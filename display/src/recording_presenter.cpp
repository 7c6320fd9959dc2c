// A presenter that records what another presenter shows: MP4 and PNG frames of the canvas.
// The canvas is read back on the caller's thread (the GL context lives there); encoding and
// writing happen on a writer thread, so the frame loop goes on with the next frame meanwhile.
// At most kQueued frames wait for the writer; present() waits when it is that far behind, so
// every frame is recorded and memory stays bounded.
#include <fmt/format.h>

#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <thread>

#include "holo/core/error.hpp"
#include "holo/core/log.hpp"
#include "holo/display/frame_output.hpp"
#include "holo/display/quad_view_presenter.hpp"

namespace holo::display {

namespace {

class RecordingPresenter final : public QuadViewPresenter {
 public:
  static constexpr std::size_t kQueued = 2;

  RecordingPresenter(std::unique_ptr<QuadViewPresenter> inner, RecordingSettings settings)
      : inner_(std::move(inner)), settings_(std::move(settings)) {
    if (!inner_) throw Error("display: recording presenter needs a presenter to record");
    if (settings_.png_every < 0) throw Error("display: png_every must be >= 0");
    std::filesystem::create_directories(settings_.out_dir);
    writer_ = std::thread([this] { writeLoop(); });
  }
  ~RecordingPresenter() override { stopWriter(); }
  RecordingPresenter(const RecordingPresenter&) = delete;
  RecordingPresenter& operator=(const RecordingPresenter&) = delete;

  void present(const FaceImages& face_images, const FaceImages* coverage) override {
    inner_->present(face_images, coverage);
    cv::Mat canvas = inner_->readBack();
    std::unique_lock lock(mutex_);
    space_.wait(lock, [this] { return queue_.size() < kQueued || failure_; });
    rethrowFailure();
    queue_.push_back({frame_++, std::move(canvas)});
    work_.notify_one();
  }
  cv::Mat readBack() override { return inner_->readBack(); }
  bool isOpen() override { return inner_->isOpen(); }
  const DisplayConfig& config() const override { return inner_->config(); }
  cv::Size outputSize(int output) const override { return inner_->outputSize(output); }
  const std::array<cv::Rect2f, kFaceCount>& lastCrops() const override { return inner_->lastCrops(); }
  void finish() override {
    inner_->finish();
    stopWriter();
    {
      std::lock_guard lock(mutex_);
      rethrowFailure();
    }
    if (!video_) return;
    video_->finish();
    HOLO_LOG_INFO("display: wrote {} ({} frames, {})", (settings_.out_dir / settings_.video_name).string(),
                  video_->framesWritten(), video_->fourcc());
  }

 private:
  struct Pending {
    long index;
    cv::Mat canvas;
  };

  void write(const Pending& p) {
    if (!settings_.video_name.empty()) {
      if (!video_)
        video_ = std::make_unique<VideoFileWriter>(settings_.out_dir / settings_.video_name, p.canvas.size(),
                                                   settings_.fps);
      video_->write(p.canvas);
    }
    if (settings_.png_every > 0 && p.index % settings_.png_every == 0)
      writePngAtomically(settings_.out_dir / fmt::format("frame_{:05d}.png", p.index), p.canvas);
  }

  void writeLoop() {
    std::unique_lock lock(mutex_);
    for (;;) {
      work_.wait(lock, [this] { return !queue_.empty() || stopping_; });
      if (queue_.empty()) return;  // stopping, everything written
      Pending p = std::move(queue_.front());
      lock.unlock();
      std::exception_ptr error;
      try {
        if (!failure_) write(p);
      } catch (...) {
        error = std::current_exception();
      }
      lock.lock();
      queue_.pop_front();
      if (error && !failure_) failure_ = error;
      space_.notify_all();
    }
  }

  void stopWriter() {
    if (!writer_.joinable()) return;
    {
      std::lock_guard lock(mutex_);
      stopping_ = true;
    }
    work_.notify_all();
    writer_.join();
  }

  void rethrowFailure() {
    if (failure_) std::rethrow_exception(failure_);
  }

  std::unique_ptr<QuadViewPresenter> inner_;
  RecordingSettings settings_;
  std::unique_ptr<VideoFileWriter> video_;  // the writer thread's, until it is joined
  long frame_ = 0;
  std::mutex mutex_;
  std::condition_variable work_, space_;
  std::deque<Pending> queue_;  // the front is being written while it is still in the queue
  bool stopping_ = false;
  std::exception_ptr failure_;
  std::thread writer_;
};

}  // namespace

std::unique_ptr<QuadViewPresenter> makeRecordingPresenter(std::unique_ptr<QuadViewPresenter> inner,
                                                          const RecordingSettings& settings) {
  return std::make_unique<RecordingPresenter>(std::move(inner), settings);
}

}  // namespace holo::display
