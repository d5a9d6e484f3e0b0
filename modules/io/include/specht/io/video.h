// specht/io/video.h: a video written frame by frame — an MP4 through OpenCV's
// VideoWriter (FFmpeg: MPEG-4 part 2, which VLC, mpv and FFmpeg play; H.264 only
// where that encoder is missing, as libx264's own threads slow the pipeline), or,
// where no encoder opens, PNG frames numbered from 000000 in a directory beside it
// (<stem>_frames/). The MP4 is written under a temporary name and renamed when
// closed, so a run that stops early leaves a playable video of the frames so far,
// never a half-written file under the final name.
#pragma once

#include <memory>
#include <opencv2/core.hpp>
#include <string>

namespace specht::io {

class VideoSink {
 public:
  enum class Format { kMp4, kPng };

  // `path` ends in .mp4. Nothing is opened until the first frame.
  VideoSink(std::string path, double fps, Format format = Format::kMp4);
  ~VideoSink();  // closes
  VideoSink(const VideoSink&) = delete;
  VideoSink& operator=(const VideoSink&) = delete;

  // A BGR frame (CV_8UC3); every frame is resized to the first one's size.
  void Write(const cv::Mat& bgr);
  // Finishes the file; returns what was written, relative to the path's directory:
  // the MP4's file name, "<stem>_frames/" or "" when no frame came. Idempotent.
  std::string Close();

  long frames() const { return frames_; }
  Format format() const { return format_; }

 private:
  struct Writer;
  std::string path_;
  double fps_;
  Format format_;
  cv::Size size_;
  long frames_ = 0;
  bool closed_ = false;
  std::unique_ptr<Writer> writer_;
};

}  // namespace specht::io
