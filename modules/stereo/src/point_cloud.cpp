#include "specht/stereo/point_cloud.h"

#include <mrpt/maps/CColouredPointsMap.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgproc.hpp>

#include "specht/core/error.h"
#include "specht/io/atomic_file.h"

namespace specht::stereo {

cv::Mat DepthFromDisparity(const cv::Mat& disparity, const RectifiedCamera& camera) {
  CV_Assert(disparity.type() == CV_32FC1);
  cv::Mat depth(disparity.size(), CV_32FC1, cv::Scalar(0));
  for (int v = 0; v < disparity.rows; ++v)
    for (int u = 0; u < disparity.cols; ++u) {
      const float d = disparity.at<float>(v, u);
      if (d > 0) depth.at<float>(v, u) = static_cast<float>(camera.DepthOf(d));
    }
  return depth;
}

std::vector<ColouredPoint> DisparityToPoints(const cv::Mat& disparity, const RectifiedCamera& camera,
                                             const cv::Mat& image, const CloudOptions& options) {
  CV_Assert(disparity.type() == CV_32FC1);
  if (!image.empty() && (image.size() != disparity.size() || image.depth() != CV_8U))
    throw InputError("point cloud: colour image must be 8-bit and of the disparity's size");
  std::vector<ColouredPoint> points;
  for (int v = 0; v < disparity.rows; ++v) {
    for (int u = 0; u < disparity.cols; ++u) {
      const float d = disparity.at<float>(v, u);
      if (!(d >= options.min_disparity_px)) continue;
      const double z = camera.DepthOf(d);
      if (z > options.max_depth_m) continue;
      ColouredPoint p;
      p.xyz = cv::Point3f(static_cast<float>((u - camera.cx_px) * z / camera.focal_px),
                          static_cast<float>((v - camera.cy_px) * z / camera.focal_px), static_cast<float>(z));
      if (image.empty())
        p.bgr = cv::Vec3b(128, 128, 128);
      else if (image.channels() == 1)
        p.bgr = cv::Vec3b::all(image.at<uint8_t>(v, u));
      else
        p.bgr = image.at<cv::Vec3b>(v, u);
      points.push_back(p);
    }
  }
  return points;
}

void TransformPoints(std::vector<ColouredPoint>& points, const mrpt::poses::CPose3D& target_from_camera) {
  for (auto& p : points) {
    double x, y, z;
    target_from_camera.composePoint(p.xyz.x, p.xyz.y, p.xyz.z, x, y, z);
    p.xyz = cv::Point3f(static_cast<float>(x), static_cast<float>(y), static_cast<float>(z));
  }
}

void WritePly(const std::vector<ColouredPoint>& points, const std::string& path) {
  mrpt::maps::CColouredPointsMap map;
  map.reserve(points.size());
  for (const auto& p : points)
    map.insertPointRGB(p.xyz.x, p.xyz.y, p.xyz.z, p.bgr[2] / 255.f, p.bgr[1] / 255.f, p.bgr[0] / 255.f);
  io::WriteAtomically(path, [&](const std::string& tmp) {
    if (!map.saveToPlyFile(tmp, true)) throw RuntimeError(path + ": cannot write PLY");
  });
}

void InsertIntoOctree(octomap::OcTree& tree, const std::vector<ColouredPoint>& points, const cv::Point3f& origin,
                      const CloudOptions& options) {
  octomap::Pointcloud cloud;
  cloud.reserve(points.size());
  for (const auto& p : points) cloud.push_back(p.xyz.x, p.xyz.y, p.xyz.z);
  // discretize: one ray per end voxel, not per point (dense stereo clouds put many
  // points in each voxel; the occupied and free voxels are the same).
  tree.insertPointCloud(cloud, octomap::point3d(origin.x, origin.y, origin.z), options.octree_max_range_m,
                        /*lazy_eval=*/false, /*discretize=*/true);
}

void WriteOctree(const octomap::OcTree& tree, const std::string& path) {
  io::WriteAtomically(path, [&](const std::string& tmp) {
    if (!const_cast<octomap::OcTree&>(tree).writeBinary(tmp)) throw RuntimeError(path + ": cannot write OctoMap");
  });
}

std::vector<cv::Vec4f> ReadVelodyne(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path + ": no such file");
  const auto bytes = std::filesystem::file_size(path);
  if (bytes % sizeof(cv::Vec4f) != 0)
    throw InputError(path + ": " + std::to_string(bytes) +
                     " bytes is not a whole number of 16-byte points "
                     "(float32 x, y, z, reflectance): truncated?");
  std::vector<cv::Vec4f> points(bytes / sizeof(cv::Vec4f));
  std::ifstream in(path, std::ios::binary);
  in.read(reinterpret_cast<char*>(points.data()), static_cast<std::streamsize>(bytes));
  if (!in) throw InputError(path + ": read failed");
  return points;
}

cv::Mat ProjectLidarToDisparity(const std::vector<cv::Vec4f>& points, const StereoCalibration& c, cv::Size size) {
  if (!c.velo_to_cam || !c.projection_left || !c.rectified)
    throw InputError(c.source + ": projecting LiDAR needs a rectified calibration with Tr_velo_to_cam (KITTI)");
  cv::Mat disparity(size, CV_32FC1, cv::Scalar(0));
  const cv::Matx34d p = *c.projection_left * *c.velo_to_cam;
  const double fb = c.camera.focal_px * c.camera.baseline_m;
  for (const auto& q : points) {
    const cv::Vec3d h = p * cv::Vec4d(q[0], q[1], q[2], 1.0);
    if (h[2] < 0.5) continue;  // behind or too close to the camera
    const int u = static_cast<int>(std::lround(h[0] / h[2])), v = static_cast<int>(std::lround(h[1] / h[2]));
    if (u < 0 || v < 0 || u >= size.width || v >= size.height) continue;
    const float d = static_cast<float>(fb / h[2]);
    float& cell = disparity.at<float>(v, u);
    if (d > cell) cell = d;  // nearest point wins
  }
  return WithoutOccludedHints(disparity);
}

// The LiDAR sits above and behind the camera, so it also sees surfaces the camera
// cannot: behind the edge of a nearer object, both project to the same image area.
// A hint is dropped when a nearer hint (by more than 1 px and 5 %) lies within
// ±kRadius pixels: the far point is then most likely hidden from the camera.
cv::Mat WithoutOccludedHints(const cv::Mat& sparse) {
  constexpr int kRadius = 3;
  cv::Mat nearest;
  cv::dilate(sparse, nearest, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * kRadius + 1, 2 * kRadius + 1)));
  cv::Mat kept = sparse.clone();
  for (int v = 0; v < sparse.rows; ++v)
    for (int u = 0; u < sparse.cols; ++u) {
      const float d = sparse.at<float>(v, u), near = nearest.at<float>(v, u);
      if (d > 0 && near - d > std::max(1.0f, 0.05f * d)) kept.at<float>(v, u) = 0;
    }
  return kept;
}

}  // namespace specht::stereo
