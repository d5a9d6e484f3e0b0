#include "specht/io/video.h"

#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "specht/core/error.h"
#include "specht/core/log.h"

namespace specht::io {
namespace fs = std::filesystem;

struct VideoSink::Writer {
  cv::VideoWriter video;
  std::string tmp_path;
};

namespace {

std::string FramesDir(const std::string& path) {
  const fs::path p(path);
  return (p.parent_path() / (p.stem().string() + "_frames")).string();
}

}  // namespace

VideoSink::VideoSink(std::string path, double fps, Format format)
    : path_(std::move(path)), fps_(fps), format_(format) {}

VideoSink::~VideoSink() {
  try {
    Close();
  } catch (const std::exception& e) {
    spdlog::error("{}: {}", path_, e.what());
  }
}

void VideoSink::Write(const cv::Mat& bgr) {
  if (closed_) throw RuntimeError(path_ + ": frame written after the video was closed");
  if (frames_ == 0) {
    size_ = cv::Size(bgr.cols & ~1, bgr.rows & ~1);  // H.264 wants even sizes
    writer_ = std::make_unique<Writer>();
    if (format_ == Format::kMp4) {
      const fs::path p(path_);
      writer_->tmp_path = (p.parent_path() / (p.stem().string() + ".tmp.mp4")).string();
      for (const char* codec : {"mp4v", "avc1"}) {
        const int fourcc = cv::VideoWriter::fourcc(codec[0], codec[1], codec[2], codec[3]);
        if (writer_->video.open(writer_->tmp_path, cv::CAP_FFMPEG, fourcc, fps_, size_)) break;
      }
      if (!writer_->video.isOpened()) {
        spdlog::warn("{}: no MP4 encoder opens here; writing PNG frames into {}/", path_, FramesDir(path_));
        format_ = Format::kPng;
      }
    }
    if (format_ == Format::kPng) fs::create_directories(FramesDir(path_));
  }
  cv::Mat frame = bgr;
  if (frame.size() != size_) cv::resize(bgr, frame, size_);
  if (format_ == Format::kMp4) {
    writer_->video.write(frame);
  } else {
    char name[32];
    std::snprintf(name, sizeof(name), "/%06ld.png", frames_);
    if (!cv::imwrite(FramesDir(path_) + name, frame)) throw RuntimeError(FramesDir(path_) + name + ": cannot write");
  }
  ++frames_;
}

std::string VideoSink::Close() {
  if (frames_ == 0) return "";
  const std::string written = format_ == Format::kMp4 ? fs::path(path_).filename().string()
                                                      : fs::path(FramesDir(path_)).filename().string() + "/";
  if (closed_) return written;
  closed_ = true;
  if (format_ == Format::kMp4) {
    writer_->video.release();
    std::error_code ec;
    fs::rename(writer_->tmp_path, path_, ec);
    if (ec) throw RuntimeError(path_ + ": cannot rename " + writer_->tmp_path + ": " + ec.message());
  }
  return written;
}

}  // namespace specht::io
