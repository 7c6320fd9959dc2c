#include "holo/display/frame_output.hpp"

#include <unistd.h>
#include <opencv2/imgcodecs.hpp>

#include "holo/core/error.hpp"
#include "holo/core/files.hpp"
#include "holo/core/log.hpp"

namespace holo::display {

namespace fs = std::filesystem;

void writePngAtomically(const fs::path& path, const cv::Mat& image) {
  std::vector<unsigned char> png;
  if (image.empty() || !cv::imencode(".png", image, png))
    throw Error("display: cannot encode a PNG for " + path.string());
  writeFileAtomically(path, std::string_view(reinterpret_cast<const char*>(png.data()), png.size()));
}

VideoFileWriter::VideoFileWriter(fs::path path, cv::Size frame_size, double fps)
    : path_(std::move(path)), size_(frame_size) {
  if (!path_.parent_path().empty()) fs::create_directories(path_.parent_path());
  temporary_ = path_;
  // FFmpeg picks the container from the extension, so the temporary keeps ".mp4".
  temporary_.replace_filename(path_.stem().string() + ".tmp-" + std::to_string(::getpid()) + ".mp4");
  for (const char* code : {"avc1", "mp4v"}) {
    if (writer_.open(temporary_.string(), cv::CAP_FFMPEG,
                     cv::VideoWriter::fourcc(code[0], code[1], code[2], code[3]), fps, size_, true)) {
      fourcc_ = code;
      break;
    }
  }
  if (!writer_.isOpened())
    throw Error("display: cannot open an MP4 writer for " + path_.string() + " (neither avc1 nor mp4v)");
  HOLO_LOG_DEBUG("display: writing {} with fourcc {}", path_.string(), fourcc_);
}

VideoFileWriter::~VideoFileWriter() {
  if (finished_) return;
  writer_.release();
  std::error_code ignored;
  fs::remove(temporary_, ignored);
}

void VideoFileWriter::write(const cv::Mat& frame) {
  if (finished_) throw Error("display: frame written to a finished video " + path_.string());
  if (frame.type() != CV_8UC3 || frame.size() != size_)
    throw Error("display: video frames of " + path_.string() + " must be CV_8UC3 of the first frame's size");
  writer_.write(frame);
  ++frames_;
}

void VideoFileWriter::finish() {
  if (finished_) return;
  writer_.release();
  // writeAtomically fsyncs and renames over the final path (its temporary name may be ours).
  writeAtomically(path_, [&](const fs::path& tmp) { fs::rename(temporary_, tmp); });
  finished_ = true;
}

}  // namespace holo::display
