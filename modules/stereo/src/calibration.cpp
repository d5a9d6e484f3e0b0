#include "specht/stereo/calibration.h"

#include <mrpt/config/CConfigFile.h>
#include <mrpt/img/TStereoCamera.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DQuat.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "specht/core/error.h"

namespace specht::stereo {
namespace {

std::string ReadText(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path + ": no such calibration file");
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// KITTI "key: v1 v2 ..." lines, with their line numbers.
struct KittiEntry {
  std::vector<double> values;
  int line = 0;
};
std::map<std::string, KittiEntry> ParseKitti(const std::string& path, const std::string& text) {
  std::map<std::string, KittiEntry> entries;
  std::istringstream lines(text);
  std::string line;
  for (int number = 1; std::getline(lines, line); ++number) {
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    KittiEntry e{{}, number};
    std::istringstream values(line.substr(colon + 1));
    std::string token;
    while (values >> token) {
      try {
        size_t used = 0;
        e.values.push_back(std::stod(token, &used));
        if (used != token.size()) throw std::invalid_argument(token);
      } catch (const std::exception&) {
        e.values.clear();  // a text field (calib_time) – not numeric
        break;
      }
    }
    entries[line.substr(0, colon)] = e;
  }
  return entries;
}

const std::vector<double>& Need(const std::map<std::string, KittiEntry>& entries, const std::string& path,
                                const std::string& key, size_t count) {
  const auto it = entries.find(key);
  if (it == entries.end()) throw InputError(path + ": missing '" + key + "'");
  if (it->second.values.size() != count)
    throw InputError(Where(path, it->second.line) + "'" + key + "' needs " + std::to_string(count) + " numbers, has " +
                     std::to_string(it->second.values.size()));
  return it->second.values;
}

template <int R, int C>
cv::Matx<double, R, C> ToMatx(const std::vector<double>& v) {
  cv::Matx<double, R, C> m;
  for (int i = 0; i < R * C; ++i) m.val[i] = v[static_cast<size_t>(i)];
  return m;
}

void CheckRectified(StereoCalibration& c) {
  const RectifiedCamera& cam = c.camera;
  if (!(cam.focal_px > 0)) throw InputError(c.source + ": focal length must be positive");
  if (!(cam.baseline_m > 0))
    throw InputError(c.source + ": the right camera must lie to the right of the left (baseline " +
                     std::to_string(cam.baseline_m) + " m)");
}

StereoCalibration KittiObject(const std::string& path, const std::map<std::string, KittiEntry>& e) {
  StereoCalibration c;
  c.source = path;
  c.rectified = true;
  const cv::Matx34d p2 = ToMatx<3, 4>(Need(e, path, "P2", 12)), p3 = ToMatx<3, 4>(Need(e, path, "P3", 12));
  c.camera.focal_px = p2(0, 0);
  c.camera.cx_px = p2(0, 2);
  c.camera.cy_px = p2(1, 2);
  c.camera.baseline_m = (p2(0, 3) - p3(0, 3)) / p2(0, 0);
  c.projection_left = p2;
  if (e.count("Tr_velo_to_cam") != 0) {
    const cv::Matx33d r0 = ToMatx<3, 3>(Need(e, path, "R0_rect", 9));
    const cv::Matx34d tr = ToMatx<3, 4>(Need(e, path, "Tr_velo_to_cam", 12));
    cv::Matx44d r0h = cv::Matx44d::eye(), trh = cv::Matx44d::eye();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 4; ++j) {
        if (j < 3) r0h(i, j) = r0(i, j);
        trh(i, j) = tr(i, j);
      }
    c.velo_to_cam = r0h * trh;
  }
  CheckRectified(c);
  return c;
}

StereoCalibration KittiCamToCam(const std::string& path, const std::map<std::string, KittiEntry>& e) {
  StereoCalibration c;
  c.source = path;
  const auto size = Need(e, path, "S_02", 2);
  c.size = cv::Size(static_cast<int>(size[0]), static_cast<int>(size[1]));
  c.k_left = ToMatx<3, 3>(Need(e, path, "K_02", 9));
  c.k_right = ToMatx<3, 3>(Need(e, path, "K_03", 9));
  c.d_left = cv::Mat(Need(e, path, "D_02", 5), true).reshape(1, 1);
  c.d_right = cv::Mat(Need(e, path, "D_03", 5), true).reshape(1, 1);
  // Each camera's pose relative to camera 0: X_i = R_i X_0 + T_i.
  const cv::Matx33d r2 = ToMatx<3, 3>(Need(e, path, "R_02", 9)), r3 = ToMatx<3, 3>(Need(e, path, "R_03", 9));
  const cv::Vec3d t2 = cv::Vec3d(Need(e, path, "T_02", 3).data()), t3 = cv::Vec3d(Need(e, path, "T_03", 3).data());
  c.r = r3 * r2.t();
  c.t = t3 - c.r * t2;
  return c;
}

cv::Mat NeedYamlMatrix(const std::string& path, const YAML::Node& root, const std::string& key, int rows, int cols) {
  const YAML::Node node = root[key];
  if (!node) throw InputError(path + ": missing '" + key + "'");
  const int line = node.Mark().line + 1;
  // OpenCV FileStorage (!!opencv-matrix) and ROS camera_info both write rows, cols, data.
  const YAML::Node data = node.IsMap() && node["data"] ? node["data"] : node;
  if (!data.IsSequence()) throw InputError(Where(path, line) + "'" + key + "' must be a matrix (rows, cols, data)");
  std::vector<double> values;
  try {
    for (const auto& v : data) values.push_back(v.as<double>());
  } catch (const YAML::Exception&) {
    throw InputError(Where(path, line) + "'" + key + "' holds something that is not a number");
  }
  if (rows > 0 && static_cast<int>(values.size()) != rows * cols)
    throw InputError(Where(path, line) + "'" + key + "' needs " + std::to_string(rows * cols) + " numbers, has " +
                     std::to_string(values.size()));
  return cv::Mat(values, true).reshape(1, rows > 0 ? rows : 1);
}

cv::Size YamlSize(const std::string& path, const YAML::Node& root) {
  if (!root["image_width"] || !root["image_height"]) return cv::Size();
  try {
    return cv::Size(root["image_width"].as<int>(), root["image_height"].as<int>());
  } catch (const YAML::Exception&) {
    throw InputError(Where(path, root["image_width"].Mark().line + 1) +
                     "image_width and image_height must be integers");
  }
}

YAML::Node LoadYaml(const std::string& path) {
  std::string text = ReadText(path);
  if (text.rfind("%YAML", 0) == 0) text = text.substr(text.find('\n') + 1);  // OpenCV's "%YAML:1.0" header
  // OpenCV tags matrices "!!opencv-matrix", which yaml-cpp keeps as a tag: harmless.
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(Where(path, e.mark.line + 1) + "not valid YAML: " + e.msg);
  }
}

StereoCalibration OpenCvYaml(const std::string& path, const YAML::Node& root) {
  StereoCalibration c;
  c.source = path;
  c.size = YamlSize(path, root);
  c.k_left = cv::Matx33d(NeedYamlMatrix(path, root, "M1", 3, 3));
  c.k_right = cv::Matx33d(NeedYamlMatrix(path, root, "M2", 3, 3));
  c.d_left = NeedYamlMatrix(path, root, "D1", -1, 0);
  c.d_right = NeedYamlMatrix(path, root, "D2", -1, 0);
  c.r = cv::Matx33d(NeedYamlMatrix(path, root, "R", 3, 3));
  c.t = cv::Vec3d(NeedYamlMatrix(path, root, "T", 3, 1));
  return c;
}

// ROS: both cameras already rectified by their rectification matrices; the
// projection matrices give the rectified pair.
StereoCalibration RosPair(const std::string& left_path, const std::string& right_path) {
  const YAML::Node left = LoadYaml(left_path), right = LoadYaml(right_path);
  const cv::Mat p_left = NeedYamlMatrix(left_path, left, "projection_matrix", 3, 4);
  const cv::Mat p_right = NeedYamlMatrix(right_path, right, "projection_matrix", 3, 4);
  StereoCalibration c;
  c.source = left_path + "," + right_path;
  c.size = YamlSize(left_path, left);
  if (YamlSize(right_path, right) != c.size) throw InputError(right_path + ": image size differs from " + left_path);
  // The raw images: K, D, and the rectifying rotations, turned into R, T.
  c.k_left = cv::Matx33d(NeedYamlMatrix(left_path, left, "camera_matrix", 3, 3));
  c.k_right = cv::Matx33d(NeedYamlMatrix(right_path, right, "camera_matrix", 3, 3));
  c.d_left = NeedYamlMatrix(left_path, left, "distortion_coefficients", -1, 0);
  c.d_right = NeedYamlMatrix(right_path, right, "distortion_coefficients", -1, 0);
  const cv::Matx33d r1(NeedYamlMatrix(left_path, left, "rectification_matrix", 3, 3));
  const cv::Matx33d r2(NeedYamlMatrix(right_path, right, "rectification_matrix", 3, 3));
  const double f = p_right.at<double>(0, 0), baseline = -p_right.at<double>(0, 3) / f;
  if (!(f > 0) || !(baseline > 0))
    throw InputError(right_path + ": projection_matrix must have f > 0 and P[0][3] = −f·B < 0");
  // Rectified frames coincide up to the baseline along x: X_r = R2ᵀ(R1 X_l − (B,0,0)).
  c.r = r2.t() * r1;
  c.t = r2.t() * cv::Vec3d(-baseline, 0, 0);
  if (p_left.at<double>(0, 0) != f)
    throw InputError(left_path + ": projection_matrix focal differs from the right camera's");
  return c;
}

StereoCalibration MrptIni(const std::string& path, const std::string& text) {
  std::string section;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    const auto a = line.find('['), b = line.find("_LEFT]");
    if (a != std::string::npos && b != std::string::npos && b > a) {
      section = line.substr(a + 1, b - a - 1);
      break;
    }
  }
  mrpt::img::TStereoCamera camera;
  try {
    mrpt::config::CConfigFile file(path);
    camera.loadFromConfigFile(section, file);
  } catch (const std::exception& e) {
    throw InputError(path + ": MRPT stereo camera section [" + section + "_...]: " + e.what());
  }
  StereoCalibration c;
  c.source = path;
  c.size = cv::Size(static_cast<int>(camera.leftCamera.ncols), static_cast<int>(camera.leftCamera.nrows));
  auto intrinsics = [](const mrpt::img::TCamera& cam, cv::Matx33d& k, cv::Mat& d) {
    k = cv::Matx33d(cam.fx(), 0, cam.cx(), 0, cam.fy(), cam.cy(), 0, 0, 1);
    d = cv::Mat(1, 5, CV_64F);
    for (int i = 0; i < 5; ++i) d.at<double>(i) = cam.dist[static_cast<size_t>(i)];
  };
  intrinsics(camera.leftCamera, c.k_left, c.d_left);
  intrinsics(camera.rightCamera, c.k_right, c.d_right);
  // MRPT gives the right camera's pose in the left frame: X_l = R_p X_r + t_p.
  const mrpt::poses::CPose3D pose(mrpt::poses::CPose3DQuat(camera.rightCameraPose));
  const auto rp = pose.getRotationMatrix();
  cv::Matx33d r_p;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r_p(i, j) = rp(i, j);
  c.r = r_p.t();
  c.t = -(r_p.t() * cv::Vec3d(pose.x(), pose.y(), pose.z()));
  return c;
}

}  // namespace

StereoCalibration LoadCalibration(const std::vector<std::string>& paths) {
  if (paths.size() == 2) return RosPair(paths[0], paths[1]);
  if (paths.size() != 1) throw InputError("calibration: give one file, or two (ROS left and right)");
  const std::string& path = paths[0];
  const std::string text = ReadText(path);
  if (text.find("_LEFT]") != std::string::npos) return MrptIni(path, text);
  if (text.find("P2:") != std::string::npos && text.find("P3:") != std::string::npos)
    return KittiObject(path, ParseKitti(path, text));
  if (text.find("K_02:") != std::string::npos) return KittiCamToCam(path, ParseKitti(path, text));
  const YAML::Node root = LoadYaml(path);
  if (root.IsMap() && root["M1"]) return OpenCvYaml(path, root);
  if (root.IsMap() && root["camera_matrix"])
    throw InputError(path + ": a ROS camera_info file describes one camera; give the left and the right file");
  throw InputError(path + ": not a calibration format specht knows (KITTI, OpenCV YAML, ROS camera_info, MRPT ini)");
}

void CheckImageSize(const StereoCalibration& c, cv::Size size) {
  const cv::Size expected = c.rectified ? c.camera.size : c.size;
  if (expected.area() > 0 && expected != size)
    throw InputError(c.source + ": calibrated for " + std::to_string(expected.width) + "×" +
                     std::to_string(expected.height) + " images, got " + std::to_string(size.width) + "×" +
                     std::to_string(size.height));
}

Rectifier::Rectifier(const StereoCalibration& c) {
  if (c.rectified) throw InputError(c.source + ": already rectified; nothing to rectify");
  if (c.size.area() == 0) throw InputError(c.source + ": image size missing (needed to rectify)");
  cv::Mat r1, r2, p1, p2, q;
  cv::stereoRectify(c.k_left, c.d_left, c.k_right, c.d_right, c.size, c.r, c.t, r1, r2, p1, p2, q,
                    cv::CALIB_ZERO_DISPARITY, 0);
  camera_.size = c.size;
  camera_.focal_px = p1.at<double>(0, 0);
  camera_.cx_px = p1.at<double>(0, 2);
  camera_.cy_px = p1.at<double>(1, 2);
  camera_.baseline_m = -p2.at<double>(0, 3) / p2.at<double>(0, 0);
  if (!(camera_.baseline_m > 0))
    throw InputError(c.source + ": the right camera must lie to the right of the left after rectification");
  cv::initUndistortRectifyMap(c.k_left, c.d_left, r1, p1, c.size, CV_32FC1, map_left_x_, map_left_y_);
  cv::initUndistortRectifyMap(c.k_right, c.d_right, r2, p2, c.size, CV_32FC1, map_right_x_, map_right_y_);
}

void Rectifier::Rectify(const cv::Mat& left, const cv::Mat& right, cv::Mat& left_out, cv::Mat& right_out) const {
  if (left.size() != camera_.size || right.size() != camera_.size)
    throw InputError("rectify: images must be " + std::to_string(camera_.size.width) + "×" +
                     std::to_string(camera_.size.height) + " as calibrated");
  cv::remap(left, left_out, map_left_x_, map_left_y_, cv::INTER_LINEAR);
  cv::remap(right, right_out, map_right_x_, map_right_y_, cv::INTER_LINEAR);
}

}  // namespace specht::stereo
