#include "specht/stereo/images.h"

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "specht/core/error.h"
#include "specht/io/map_io.h"

namespace specht::stereo {
namespace {

cv::Mat ReadUnchanged(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path + ": no such file");
  cv::Mat image = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (image.empty()) throw InputError(path + ": not a readable image (empty or corrupt)");
  return image;
}

cv::Mat Colorize(const cv::Mat& values, double lo, double hi, bool reverse) {
  cv::Mat scaled;
  values.convertTo(scaled, CV_8U, 255.0 / (hi - lo), -lo * 255.0 / (hi - lo));
  if (reverse) scaled = 255 - scaled;
  cv::Mat colour;
  cv::applyColorMap(scaled, colour, cv::COLORMAP_TURBO);
  colour.setTo(cv::Scalar::all(0), values <= 0);
  return colour;
}

}  // namespace

cv::Mat ReadGray8(const std::string& path) {
  cv::Mat image = ReadUnchanged(path);
  if (image.depth() != CV_8U)
    throw InputError(path + ": expected an 8-bit image, got " + cv::typeToString(image.type()));
  if (image.channels() == 1) return image;
  cv::Mat gray;
  cv::cvtColor(image, gray, image.channels() == 4 ? cv::COLOR_BGRA2GRAY : cv::COLOR_BGR2GRAY);
  return gray;
}

cv::Mat ReadDisparityPng(const std::string& path, double scale_8bit) {
  cv::Mat raw = ReadUnchanged(path);
  if (raw.channels() != 1) throw InputError(path + ": a disparity image must have one channel");
  cv::Mat disparity;
  if (raw.depth() == CV_16U)
    raw.convertTo(disparity, CV_32F, 1.0 / 256);
  else if (raw.depth() == CV_8U)
    raw.convertTo(disparity, CV_32F, scale_8bit);
  else
    throw InputError(path + ": disparity must be uint16 (KITTI) or uint8 (Middlebury), got " +
                     cv::typeToString(raw.type()));
  return disparity;
}

void WriteDisparityKitti(const cv::Mat& disparity, const std::string& path) {
  CV_Assert(disparity.type() == CV_32FC1);
  cv::Mat encoded;
  disparity.convertTo(encoded, CV_16U, 256.0);  // saturates; 0 stays "no estimate"
  encoded.setTo(0, disparity <= 0);
  io::WritePng(encoded, path);
}

cv::Mat ColorizeDisparity(const cv::Mat& disparity, double max_disparity) {
  return Colorize(disparity, 0, max_disparity, false);
}

cv::Mat ColorizeDepth(const cv::Mat& depth_m, double max_depth_m) { return Colorize(depth_m, 0, max_depth_m, true); }

}  // namespace specht::stereo
