// specht/stereo/point_cloud.h: disparity → depth → 3D points, PLY, OctoMap; and the
// other direction, LiDAR points → sparse disparity hints.
//
// A left pixel (u, v) with disparity d lies at depth Z = f B / d and at
//   X = (u − c_x) Z / f,  Y = (v − c_y) Z / f     (camera frame: x right, y down, z forward).
#pragma once

#include <mrpt/poses/CPose3D.h>
#include <octomap/OcTree.h>

#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "specht/core/params.h"
#include "specht/stereo/calibration.h"

namespace specht::stereo {

struct ColouredPoint {
  cv::Point3f xyz;
  cv::Vec3b bgr;
};

// Section "stereo_cloud": which pixels become points and how they enter the OctoMap.
struct CloudOptions {
  double max_depth_m = 40;
  double min_disparity_px = 1;
  double octree_resolution_m = 0.2;
  double octree_max_range_m = 20;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Param("max_depth_m", max_depth_m, "drop points farther than this", Range::Of(1.0, 500.0));
    v.Param("min_disparity_px", min_disparity_px, "drop pixels with a smaller disparity (far, uncertain)",
            Range::Of(0.1, 16.0));
    v.Param("octree_resolution_m", octree_resolution_m, "OctoMap voxel size", Range::Of(0.01, 2.0).Log());
    v.Param("octree_max_range_m", octree_max_range_m, "OctoMap insertion range (free space is ray cast to it)",
            Range::Of(1.0, 500.0));
  }
};

// Depth in metres (CV_32F, 0 = none).
cv::Mat DepthFromDisparity(const cv::Mat& disparity, const RectifiedCamera& camera);

// One point per pixel with a usable disparity, in the camera frame, coloured from
// `image` (8-bit gray or BGR of the same size; empty = grey).
std::vector<ColouredPoint> DisparityToPoints(const cv::Mat& disparity, const RectifiedCamera& camera,
                                             const cv::Mat& image, const CloudOptions& options);

// Points into another frame: p' = target_from_camera · p (e.g. from the transform tree).
void TransformPoints(std::vector<ColouredPoint>& points, const mrpt::poses::CPose3D& target_from_camera);

// Binary PLY with colour (MRPT's exporter).
void WritePly(const std::vector<ColouredPoint>& points, const std::string& path);

// Inserts the points as one scan from `origin` (same frame): the voxels along each
// ray become free, the end voxels occupied (octomap::OcTree::insertPointCloud).
void InsertIntoOctree(octomap::OcTree& tree, const std::vector<ColouredPoint>& points, const cv::Point3f& origin,
                      const CloudOptions& options);
void WriteOctree(const octomap::OcTree& tree, const std::string& path);  // .bt

// A KITTI Velodyne scan (float32 x, y, z, reflectance per point).
std::vector<cv::Vec4f> ReadVelodyne(const std::string& path);
// LiDAR points projected into the rectified left image as sparse disparity (CV_32F,
// 0 = none; the nearest point wins a pixel; points hidden from the camera removed by
// WithoutOccludedHints). Needs velo_to_cam and projection_left.
cv::Mat ProjectLidarToDisparity(const std::vector<cv::Vec4f>& points, const StereoCalibration& calibration,
                                cv::Size size);
// Drops each hint that has a clearly nearer hint within 3 px (seen by the LiDAR,
// occluded for the camera).
cv::Mat WithoutOccludedHints(const cv::Mat& sparse);

}  // namespace specht::stereo
