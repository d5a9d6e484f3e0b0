// specht/stereo/images.h: stereo images and disparity maps in the formats users have.
//   KITTI disparity PNG: uint16, value / 256 = disparity in pixels, 0 = no estimate.
//   Middlebury 2001–2006 GT PNG: uint8, value = disparity (× scale), 0 = invalid.
// PNGs are written with io::WritePng (atomically).
// Every reader throws InputError naming the file and the reason.
#pragma once

#include <opencv2/core.hpp>
#include <string>

namespace specht::stereo {

// An 8-bit image as grayscale (colour is converted; 16-bit, missing or unreadable
// files are errors).
cv::Mat ReadGray8(const std::string& path);

// A disparity PNG as CV_32F pixels (0 = none): uint16 files are KITTI (/256), uint8
// files are Middlebury (× scale_8bit).
cv::Mat ReadDisparityPng(const std::string& path, double scale_8bit = 1.0);
void WriteDisparityKitti(const cv::Mat& disparity, const std::string& path);

// Colour pictures (BGR, black = no value): disparity on a fixed scale 0..max_disparity,
// depth in metres 0..max_depth_m (near = warm).
cv::Mat ColorizeDisparity(const cv::Mat& disparity, double max_disparity);
cv::Mat ColorizeDepth(const cv::Mat& depth_m, double max_depth_m);

}  // namespace specht::stereo
