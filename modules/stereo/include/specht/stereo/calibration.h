// specht/stereo/calibration.h: stereo calibration from the files users have, and
// rectification of unrectified pairs.
//
// Formats (recognised by content):
//   KITTI object calib.txt   P0..P3, R0_rect, Tr_velo_to_cam: rectified; the pair is
//                            cameras 2 (left) and 3 (right), baseline (P2₀₃ − P3₀₃)/f.
//   KITTI calib_cam_to_cam   K_02, D_02, R_02, T_02, S_02 (and _03): unrectified.
//   OpenCV YAML              M1, D1, M2, D2, R, T (stereo_calib's intrinsics +
//                            extrinsics in one file), image_width/image_height.
//   ROS camera_info pair     two files (left, right) with camera_matrix,
//                            distortion_coefficients, rectification_matrix,
//                            projection_matrix; right P[0][3] = −f·B.
//   MRPT TStereoCamera ini   [<S>_LEFT], [<S>_RIGHT], [<S>_LEFT2RIGHT_POSE].
// Unrectified calibrations carry (K, D) per camera and the right camera's pose
// (X_right = R · X_left + T, as OpenCV); Rectifier computes the rectified pair
// (cv::stereoRectify, zero disparity at infinity).
#pragma once

#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

namespace specht::stereo {

// A rectified pinhole pair: what disparity → depth needs.
struct RectifiedCamera {
  cv::Size size;
  double focal_px = 0, cx_px = 0, cy_px = 0;
  double baseline_m = 0;
  double DepthOf(double disparity_px) const { return focal_px * baseline_m / disparity_px; }
};

struct StereoCalibration {
  std::string source;  // file(s) it came from
  cv::Size size;       // image size (0×0 when the file does not say)
  bool rectified = false;
  // Rectified pairs:
  RectifiedCamera camera;
  // Unrectified pairs:
  cv::Matx33d k_left, k_right;
  cv::Mat d_left, d_right;  // distortion (OpenCV order), 1×N
  cv::Matx33d r;
  cv::Vec3d t;
  // Optional: LiDAR (Velodyne) to rectified left camera, X_cam = velo_to_cam · X_velo
  // (KITTI: P-independent part R0_rect · Tr_velo_to_cam) and the left projection P2.
  std::optional<cv::Matx44d> velo_to_cam;
  std::optional<cv::Matx34d> projection_left;
};

// One path (KITTI, OpenCV YAML, MRPT ini) or two (ROS left and right). Throws
// InputError naming the file, the key and the reason.
StereoCalibration LoadCalibration(const std::vector<std::string>& paths);

// Throws InputError when `calibration` does not fit images of `size`.
void CheckImageSize(const StereoCalibration& calibration, cv::Size size);

class Rectifier {
 public:
  explicit Rectifier(const StereoCalibration& calibration);  // needs an unrectified calibration with a size
  void Rectify(const cv::Mat& left, const cv::Mat& right, cv::Mat& left_out, cv::Mat& right_out) const;
  const RectifiedCamera& camera() const { return camera_; }

 private:
  RectifiedCamera camera_;
  cv::Mat map_left_x_, map_left_y_, map_right_x_, map_right_y_;
};

}  // namespace specht::stereo
