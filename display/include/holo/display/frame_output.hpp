// Headless output of the quad view: PNG frames and an MP4 video, both written atomically (a
// reader never sees half a file; an interrupted recording leaves no MP4 behind).
#pragma once

#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/videoio.hpp>
#include <string>

namespace holo::display {

// Encodes `image` (CV_8UC3 BGR) as PNG and writes it atomically.
void writePngAtomically(const std::filesystem::path& path, const cv::Mat& image);

// An MP4 of CV_8UC3 BGR frames of one size. Frames go to a temporary file beside `path`
// ("NAME.tmp-PID.mp4"); finish() closes it and renames it over `path`. Destroying the writer
// without finish() deletes the temporary. Codec: H.264 ('avc1', through FFmpeg's libx264 in
// Debian's OpenCV) when it opens, else MPEG-4 Part 2 ('mp4v').
class VideoFileWriter {
 public:
  VideoFileWriter(std::filesystem::path path, cv::Size frame_size, double fps);
  ~VideoFileWriter();
  VideoFileWriter(const VideoFileWriter&) = delete;
  VideoFileWriter& operator=(const VideoFileWriter&) = delete;

  void write(const cv::Mat& frame);  // throws holo::Error on a wrong size or type
  void finish();
  const std::string& fourcc() const { return fourcc_; }
  long framesWritten() const { return frames_; }

 private:
  std::filesystem::path path_;
  std::filesystem::path temporary_;
  cv::Size size_;
  cv::VideoWriter writer_;
  std::string fourcc_;
  long frames_ = 0;
  bool finished_ = false;
};

}  // namespace holo::display
