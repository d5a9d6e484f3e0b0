#include "specht/sim/camera.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <opencv2/core/utility.hpp>

namespace specht::sim {
namespace {

// Deterministic value noise: a hash of the lattice corner, bilinear with smoothstep.
double Hash(int64_t x, int64_t y, uint32_t salt) {
  uint64_t h = static_cast<uint64_t>(x) * 0x9E3779B97F4A7C15ULL ^ static_cast<uint64_t>(y) * 0xC2B2AE3D27D4EB4FULL ^
               (static_cast<uint64_t>(salt) << 17);
  h ^= h >> 33, h *= 0xFF51AFD7ED558CCDULL, h ^= h >> 33, h *= 0xC4CEB9FE1A85EC53ULL, h ^= h >> 33;
  return static_cast<double>(h & 0xFFFFFF) / static_cast<double>(0xFFFFFF);
}

double ValueNoise(double x, double y, uint32_t salt) {
  const double fx = std::floor(x), fy = std::floor(y);
  const int64_t ix = static_cast<int64_t>(fx), iy = static_cast<int64_t>(fy);
  double tx = x - fx, ty = y - fy;
  tx = tx * tx * (3 - 2 * tx), ty = ty * ty * (3 - 2 * ty);
  const double a = Hash(ix, iy, salt), b = Hash(ix + 1, iy, salt), c = Hash(ix, iy + 1, salt),
               d = Hash(ix + 1, iy + 1, salt);
  return (a * (1 - tx) + b * tx) * (1 - ty) + (c * (1 - tx) + d * tx) * ty;
}

// Octaves from 0.8 m down to 5 cm features.
double Fractal(double x, double y, uint32_t salt) {
  double sum = 0, amp = 0.5, freq = 1.25;
  for (int o = 0; o < 5; ++o) {
    sum += amp * ValueNoise(x * freq, y * freq, salt + o);
    amp *= 0.55, freq *= 2.0;
  }
  return sum / 0.95;
}

double Texture(const std::string& kind, double s, double z, uint32_t salt) {
  const double n = Fractal(s, z, salt);
  if (kind == "bricks") {
    const double row = std::floor(z / 0.25), offset = std::fmod(row, 2.0) * 0.25;
    const double bs = std::fmod(s + offset, 0.5), bz = std::fmod(z, 0.25);
    const bool mortar = bs < 0.03 || bz < 0.03;
    return mortar ? 0.85 : 0.35 + 0.4 * n * Hash(static_cast<int64_t>((s + offset) / 0.5), static_cast<int64_t>(row), salt);
  }
  if (kind == "stripes") return 0.3 + 0.4 * (std::fmod(std::floor(s / 0.3), 2.0)) + 0.3 * (n - 0.5);
  if (kind == "checker") {
    const bool dark = static_cast<int64_t>(std::floor(s / 0.4) + std::floor(z / 0.4)) % 2 == 0;
    return (dark ? 0.25 : 0.7) + 0.3 * (n - 0.5);
  }
  if (kind == "plain") return 0.55 + 0.15 * (n - 0.5);
  return 0.15 + 0.8 * n;  // noise
}

}  // namespace

struct StereoRenderer::Hit {
  double t = std::numeric_limits<double>::infinity();
  double shade = 0;  // texture × lighting, [0, 1]
};

StereoRenderer::StereoRenderer(const Scenario& scenario, const World& world, StereoSpec spec)
    : scenario_(scenario), world_(world), spec_(spec) {}

StereoRenderer::Hit StereoRenderer::Cast(const cv::Vec3d& o, const cv::Vec3d& d,
                                        const std::vector<Box3>& boxes) const {
  Hit best;
  const cv::Vec3d sun(0.4, 0.3, 0.87);
  // Ground plane z = 0.
  if (d[2] < -1e-9) {
    const double t = -o[2] / d[2];
    const double x = o[0] + t * d[0], y = o[1] + t * d[1];
    best.t = t;
    best.shade = 0.2 + 0.6 * Fractal(x * 1.3, y * 1.3, 7);
  }
  // A vertical face from a to b up to height h: the ray's horizontal part against the
  // segment, then the height of the hit.
  auto face = [&](Vec2 a, Vec2 b, double h, const std::string& texture, uint32_t salt, double s0) {
    const double ex = b.x - a.x, ey = b.y - a.y;
    const double den = d[0] * ey - d[1] * ex;
    if (std::abs(den) < 1e-12) return;
    const double apx = a.x - o[0], apy = a.y - o[1];
    const double t = (apx * ey - apy * ex) / den, u = (apx * d[1] - apy * d[0]) / den;
    if (t <= 1e-6 || u < 0 || u > 1 || t >= best.t) return;
    const double z = o[2] + t * d[2];
    if (z < 0 || z > h) return;
    const double len = std::hypot(ex, ey);
    const cv::Vec3d normal(ey / len, -ex / len, 0);
    const double light = 0.45 + 0.55 * std::abs(normal.dot(sun));
    best.t = t;
    best.shade = light * Texture(texture, s0 + u * len, z, salt);
  };
  uint32_t salt = 100;
  for (const auto& obj : scenario_.objects) {
    const size_t n = obj.polygon.size(), edges = obj.closed ? n : n - 1;
    double s0 = 0;
    for (size_t i = 0; i < edges; ++i, ++salt) {
      const Vec2 a = obj.polygon[i], b = obj.polygon[(i + 1) % n];
      face(a, b, obj.height_m, obj.texture, salt, s0);
      s0 += std::hypot(b.x - a.x, b.y - a.y);
    }
  }
  for (const auto& box : boxes) {
    const auto outline = BoxOutline(box.pose, box.length_m, box.width_m);
    double s0 = 0;
    for (size_t i = 0; i < outline.size(); ++i) {
      face(outline[i].a, outline[i].b, box.height_m, box.cls == "Car" ? "checker" : "noise",
           5000 + static_cast<uint32_t>(box.id), s0);
      s0 += std::hypot(outline[i].b.x - outline[i].a.x, outline[i].b.y - outline[i].a.y);
    }
  }
  return best;
}

cv::Mat StereoRenderer::RenderView(const cv::Vec3d& origin, const cv::Matx33d& world_from_cam,
                                   const std::vector<Box3>& boxes, cv::Mat* depth) const {
  const StereoSpec& s = spec_;
  cv::Mat image(s.height, s.width, CV_8U);
  if (depth != nullptr) *depth = cv::Mat(s.height, s.width, CV_32F, cv::Scalar(0));
  const double cx = (s.width - 1) / 2.0, cy = (s.height - 1) / 2.0;
  // Rows render in parallel; every pixel depends on nothing but its own ray.
  cv::parallel_for_(cv::Range(0, s.height), [&](const cv::Range& rows) {
  for (int v = rows.start; v < rows.end; ++v) {
    for (int u = 0; u < s.width; ++u) {
      const cv::Vec3d ray_cam((u - cx) / s.focal_px, (v - cy) / s.focal_px, 1.0);
      const cv::Vec3d ray = world_from_cam * ray_cam;
      const Hit hit = Cast(origin, ray, boxes);
      if (std::isfinite(hit.t)) {
        image.at<uint8_t>(v, u) = static_cast<uint8_t>(std::lround(255.0 * std::clamp(hit.shade, 0.0, 1.0)));
        // ray_cam has z = 1, so the ray parameter is the depth along the optical axis.
        if (depth != nullptr) depth->at<float>(v, u) = static_cast<float>(hit.t);
      } else {
        image.at<uint8_t>(v, u) = static_cast<uint8_t>(200 + 40.0 * v / s.height);  // sky
      }
    }
  }
  });
  return image;
}

StereoFrame StereoRenderer::Render(const Pose2& ego, const std::vector<Box3>& boxes) const {
  const StereoSpec& s = spec_;
  const double c = std::cos(ego.yaw_rad), sn = std::sin(ego.yaw_rad);
  const cv::Vec3d left_origin(ego.x + c * s.x_m - sn * s.y_m, ego.y + sn * s.x_m + c * s.y_m, s.z_m);
  // Camera axes in the world: forward along the heading (pitched down by pitch),
  // right, and down.
  const double yaw = ego.yaw_rad + s.yaw_rad, cp = std::cos(s.pitch_rad), sp = std::sin(s.pitch_rad);
  const cv::Vec3d forward(std::cos(yaw) * cp, std::sin(yaw) * cp, -sp);
  const cv::Vec3d right(std::sin(yaw), -std::cos(yaw), 0);
  const cv::Vec3d down = forward.cross(right);
  const cv::Matx33d world_from_cam(right[0], down[0], forward[0], right[1], down[1], forward[1], right[2], down[2],
                                   forward[2]);
  const cv::Vec3d right_origin = left_origin + s.baseline_m * right;
  StereoFrame f;
  f.left = RenderView(left_origin, world_from_cam, boxes, &f.depth);
  f.right = RenderView(right_origin, world_from_cam, boxes, &f.depth_right);
  f.disparity = cv::Mat(s.height, s.width, CV_32F, cv::Scalar(0));
  for (int v = 0; v < s.height; ++v) {
    for (int u = 0; u < s.width; ++u) {
      const float z = f.depth.at<float>(v, u);
      if (z > 0) f.disparity.at<float>(v, u) = static_cast<float>(s.focal_px * s.baseline_m / z);
    }
  }
  // KITTI object labels: type truncated occluded alpha bbox(4) dims(h w l) location(x y z) rotation_y
  const double cxp = (s.width - 1) / 2.0, cyp = (s.height - 1) / 2.0;
  for (const auto& box : boxes) {
    const cv::Vec3d centre(box.pose.x, box.pose.y, box.height_m / 2);
    double umin = 1e9, umax = -1e9, vmin = 1e9, vmax = -1e9;
    bool behind = false;
    const auto outline = BoxOutline(box.pose, box.length_m, box.width_m);
    for (const auto& seg : outline) {
      for (double z : {0.0, box.height_m}) {
        const cv::Vec3d p = cv::Vec3d(seg.a.x, seg.a.y, z) - left_origin;
        const cv::Vec3d pc = world_from_cam.t() * p;
        if (pc[2] <= 0.1) {
          behind = true;
          continue;
        }
        const double u = cxp + s.focal_px * pc[0] / pc[2], v = cyp + s.focal_px * pc[1] / pc[2];
        umin = std::min(umin, u), umax = std::max(umax, u), vmin = std::min(vmin, v), vmax = std::max(vmax, v);
      }
    }
    if (behind || umax < 0 || umin >= s.width || vmax < 0 || vmin >= s.height) continue;
    const cv::Vec3d c_cam = world_from_cam.t() * (centre - left_origin);
    if (c_cam[2] > 60) continue;
    const double area = (umax - umin) * (vmax - vmin);
    const double cu0 = std::max(0.0, umin), cu1 = std::min(s.width - 1.0, umax);
    const double cv0 = std::max(0.0, vmin), cv1 = std::min(s.height - 1.0, vmax);
    const double truncated = area > 0 ? 1.0 - (cu1 - cu0) * (cv1 - cv0) / area : 0.0;
    // Occlusion: the share of the box's pixels where the depth is clearly nearer.
    long seen = 0, total = 0;
    for (int v = static_cast<int>(cv0); v <= static_cast<int>(cv1); v += 2) {
      for (int u = static_cast<int>(cu0); u <= static_cast<int>(cu1); u += 2) {
        ++total;
        const float z = f.depth.at<float>(v, u);
        seen += z > 0 && z >= c_cam[2] - std::max(box.length_m, box.width_m);
      }
    }
    const double visible = total > 0 ? static_cast<double>(seen) / total : 0.0;
    if (visible < 0.05) continue;
    const int occluded = visible > 0.8 ? 0 : visible > 0.4 ? 1 : 2;
    const double rotation_y = -(box.pose.yaw_rad - yaw);  // about the camera's y (down) axis
    const double alpha = rotation_y - std::atan2(c_cam[0], c_cam[2]);
    char line[320];
    std::snprintf(line, sizeof(line), "%s %.2f %d %.2f %.2f %.2f %.2f %.2f %.2f %.2f %.2f %.2f %.2f %.2f %.2f",
                  box.cls.c_str(), truncated, occluded, std::atan2(std::sin(alpha), std::cos(alpha)), cu0, cv0, cu1,
                  cv1, box.height_m, box.width_m, box.length_m, c_cam[0], c_cam[1] + box.height_m / 2, c_cam[2],
                  std::atan2(std::sin(rotation_y), std::cos(rotation_y)));
    f.kitti_labels.push_back(line);
  }
  return f;
}

}  // namespace specht::sim
