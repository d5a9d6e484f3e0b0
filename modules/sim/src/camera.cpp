#include "specht/sim/camera.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <opencv2/imgproc.hpp>

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
    return mortar ? 0.85
                  : 0.35 + 0.4 * n * Hash(static_cast<int64_t>((s + offset) / 0.5), static_cast<int64_t>(row), salt);
  }
  if (kind == "stripes") return 0.3 + 0.4 * (std::fmod(std::floor(s / 0.3), 2.0)) + 0.3 * (n - 0.5);
  if (kind == "checker") {
    const bool dark = static_cast<int64_t>(std::floor(s / 0.4) + std::floor(z / 0.4)) % 2 == 0;
    return (dark ? 0.25 : 0.7) + 0.3 * (n - 0.5);
  }
  if (kind == "plain") return 0.55 + 0.15 * (n - 0.5);
  return 0.15 + 0.8 * n;  // noise
}

// Textures sampled once into tiles of kTexelM: faces 12 m along × 8 m up (every
// pattern's period divides both), the ground 12 m × 12 m. A face starts at its own
// offset into its tile, so neighbouring faces differ.
constexpr double kTexelM = 0.01;
constexpr int kTileS = 1200, kTileZ = 800, kTileGround = 1200;

struct Tiles {
  std::map<std::string, cv::Mat> faces;  // CV_8U
  cv::Mat ground;
};

const Tiles& TextureTiles() {
  static const Tiles tiles = [] {
    Tiles t;
    for (const char* kind : {"noise", "bricks", "stripes", "checker", "plain"}) {
      cv::Mat m(kTileZ, kTileS, CV_8U);
      for (int r = 0; r < kTileZ; ++r)
        for (int c = 0; c < kTileS; ++c)
          m.at<uint8_t>(r, c) = cv::saturate_cast<uint8_t>(
              255.0 * std::clamp(Texture(kind, (c + 0.5) * kTexelM, (r + 0.5) * kTexelM, 100), 0.0, 1.0));
      t.faces[kind] = m;
    }
    t.ground = cv::Mat(kTileGround, kTileGround, CV_8U);
    for (int r = 0; r < kTileGround; ++r)
      for (int c = 0; c < kTileGround; ++c)
        t.ground.at<uint8_t>(r, c) = cv::saturate_cast<uint8_t>(
            255.0 * (0.2 + 0.6 * Fractal((c + 0.5) * kTexelM * 1.3, (r + 0.5) * kTexelM * 1.3, 7)));
    return t;
  }();
  return tiles;
}

int Wrap(double metres, int period) {
  const int i = static_cast<int>(std::floor(metres / kTexelM)) % period;
  return i < 0 ? i + period : i;
}

// Colour of a texture kind (BGR factors): brick walls reddish, cars bluish, …
cv::Vec3d Tint(const std::string& kind) {
  if (kind == "bricks") return {0.55, 0.62, 0.92};
  if (kind == "checker") return {0.92, 0.72, 0.55};
  if (kind == "stripes") return {0.35, 0.85, 0.95};
  if (kind == "noise") return {0.62, 0.80, 0.66};
  return {0.85, 0.85, 0.85};
}

// a·r for the camera ray r(u, v) = ((u − cx)/f, (v − cy)/f, 1): affine in u and v.
struct Affine {
  double du = 0, dv = 0, c = 0;
  double At(double u, double v) const { return du * u + dv * v + c; }
};

// A planar patch: the points c + s·e + z·ẑ (s ∈ [s0, s1], z ∈ [0, height]) of a
// vertical plane with normal n.
struct Patch {
  cv::Vec3d c, e, n;
  double s0 = 0, s1 = 0, height = 0;
};

}  // namespace

struct StereoRenderer::View {
  cv::Vec3d o;    // camera centre in the world
  cv::Matx33d R;  // world_from_cam
  double f = 0, cx = 0, cy = 0;
  int w = 0, h = 0;
  cv::Mat3b image;
  cv::Mat1f depth;
  cv::Mat1i agent;  // left view: index + 1 of the agent drawn there, 0 none

  Affine Form(const cv::Vec3d& world_vector) const {
    const cv::Vec3d a = R.t() * world_vector;  // in the camera frame
    return {a[0] / f, a[1] / f, a[2] - a[0] * cx / f - a[1] * cy / f};
  }

  // The patch's screen box: its corners clipped to the half-space in front of the
  // camera (z_cam ≥ 5 cm, Sutherland–Hodgman) and projected.
  std::optional<cv::Rect> ScreenBox(const Patch& p) const {
    std::vector<cv::Vec3d> poly;
    for (const auto& [s, z] : {std::pair{p.s0, 0.0}, {p.s1, 0.0}, {p.s1, p.height}, {p.s0, p.height}})
      poly.push_back(R.t() * (p.c + s * p.e + cv::Vec3d(0, 0, z) - o));
    constexpr double kNear = 0.05;
    std::vector<cv::Vec3d> clipped;
    for (size_t i = 0; i < poly.size(); ++i) {
      const cv::Vec3d& a = poly[i];
      const cv::Vec3d& b = poly[(i + 1) % poly.size()];
      if (a[2] >= kNear) clipped.push_back(a);
      if ((a[2] >= kNear) != (b[2] >= kNear)) clipped.push_back(a + (b - a) * ((kNear - a[2]) / (b[2] - a[2])));
    }
    if (clipped.empty()) return std::nullopt;
    double u0 = 1e18, u1 = -1e18, v0 = 1e18, v1 = -1e18;
    for (const auto& q : clipped) {
      const double u = cx + f * q[0] / q[2], v = cy + f * q[1] / q[2];
      u0 = std::min(u0, u), u1 = std::max(u1, u), v0 = std::min(v0, v), v1 = std::max(v1, v);
    }
    const cv::Rect box = cv::Rect(cv::Point(static_cast<int>(std::floor(u0)) - 1, static_cast<int>(std::floor(v0)) - 1),
                                  cv::Point(static_cast<int>(std::ceil(u1)) + 2, static_cast<int>(std::ceil(v1)) + 2)) &
                         cv::Rect(0, 0, w, h);
    if (box.empty()) return std::nullopt;
    return box;
  }

  // Every pixel of the patch nearer than what is there: `shade(u, v, s, z, bgr)`
  // returns false where the patch is transparent; `on_pixel(u, v, t)` is told of every
  // pixel the patch covers, drawn or hidden.
  template <class Shade, class OnPixel>
  void Draw(const Patch& p, Shade&& shade, OnPixel&& on_pixel) {
    const auto box = ScreenBox(p);
    if (!box) return;
    const Affine den = Form(p.n), along = Form(p.e), up = Form(cv::Vec3d(0, 0, 1));
    const double num = p.n.dot(p.c - o), s_origin = p.e.dot(o - p.c), z_origin = o[2];
    cv::Vec3b bgr;
    for (int v = box->y; v < box->br().y; ++v) {
      float* depth_row = depth.ptr<float>(v);
      for (int u = box->x; u < box->br().x; ++u) {
        const double d = den.At(u, v);
        if (std::abs(d) < 1e-12) continue;
        const double t = num / d;
        if (t <= 0.05) continue;
        const double s = s_origin + t * along.At(u, v), z = z_origin + t * up.At(u, v);
        if (s < p.s0 || s > p.s1 || z < 0 || z > p.height) continue;
        if (!shade(s, z, bgr)) continue;
        const bool nearer = t < depth_row[u] || depth_row[u] <= 0;
        on_pixel(u, v, nearer);
        if (!nearer) continue;
        depth_row[u] = static_cast<float>(t);
        image(v, u) = bgr;
      }
    }
  }
};

std::string DrivingClassOf(const std::string& kitti) {
  return kitti == "Car" ? "car" : kitti == "Cyclist" ? "cyclist" : "pedestrian";
}

StereoRenderer::StereoRenderer(const Scenario& scenario, const World& world, StereoSpec spec,
                               const SpriteLibrary* sprites)
    : scenario_(scenario), world_(world), spec_(std::move(spec)), sprites_(sprites) {
  if (sprites_) set_ = ParseSpriteSet(spec_.sprites, scenario.path + ": stereo.sprites");
  TextureTiles();
}

const Sprite* StereoRenderer::SpriteFor(const Box3& box, const cv::Vec3d& camera) const {
  if (!sprites_) return nullptr;
  if (!box.sprite.empty()) return &sprites_->Named(box.sprite);
  const auto candidates = sprites_->Of(DrivingClassOf(box.cls), set_);
  if (candidates.empty()) return nullptr;
  // The width the box shows the camera: its footprint's extent across the view.
  const double bx = box.pose.x - camera[0], by = box.pose.y - camera[1], r = std::hypot(bx, by);
  const double across_x = -by / r, across_y = bx / r;
  const double c = std::cos(box.pose.yaw_rad), s = std::sin(box.pose.yaw_rad);
  const double shown =
      std::abs(box.length_m * (c * across_x + s * across_y)) + std::abs(box.width_m * (-s * across_x + c * across_y));
  const double want = std::log(shown / box.height_m);
  const Sprite* best = nullptr;
  double best_cost = 1e18;
  for (size_t i = 0; i < candidates.size(); ++i) {
    // Ties (equal aspects) go to the sprite the agent's id picks.
    const size_t k = (i + static_cast<size_t>(box.id) * 7919) % candidates.size();
    const double cost = std::abs(std::log(candidates[k]->Aspect()) - want);
    if (cost < best_cost - 1e-9) best_cost = cost, best = candidates[k];
  }
  return best;
}

StereoFrame StereoRenderer::Render(const Pose2& ego, const std::vector<Box3>& boxes) const {
  const StereoSpec& s = spec_;
  const Tiles& tiles = TextureTiles();
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
  const cv::Vec3d sun(0.4, 0.3, 0.87);

  View views[2];
  for (int k = 0; k < 2; ++k) {
    View& v = views[k];
    v.o = left_origin + (k == 0 ? 0.0 : s.baseline_m) * right;
    v.R = world_from_cam;
    v.f = s.focal_px, v.cx = (s.width - 1) / 2.0, v.cy = (s.height - 1) / 2.0;
    v.w = s.width, v.h = s.height;
    v.image.create(s.height, s.width);
    v.depth.create(s.height, s.width);
    if (k == 0) v.agent = cv::Mat1i(s.height, s.width, 0);
  }

  // Ground and sky, every pixel: the ray's world z decides.
  for (View& v : views) {
    const Affine dx = v.Form({1, 0, 0}), dy = v.Form({0, 1, 0}), dz = v.Form({0, 0, 1});
    for (int row = 0; row < v.h; ++row) {
      for (int u = 0; u < v.w; ++u) {
        const double z = dz.At(u, row);
        if (z < -1e-9) {
          const double t = -v.o[2] / z;
          const double x = v.o[0] + t * dx.At(u, row), y = v.o[1] + t * dy.At(u, row);
          const uint8_t g = tiles.ground.at<uint8_t>(Wrap(y, kTileGround), Wrap(x, kTileGround));
          v.image(row, u) = cv::Vec3b(cv::saturate_cast<uint8_t>(0.93 * g), cv::saturate_cast<uint8_t>(0.95 * g), g);
          v.depth(row, u) = static_cast<float>(t);
        } else {
          const double sky = static_cast<double>(row) / v.h;
          v.image(row, u) =
              cv::Vec3b(cv::saturate_cast<uint8_t>(235 - 20 * sky), cv::saturate_cast<uint8_t>(200 + 20 * sky),
                        cv::saturate_cast<uint8_t>(160 + 50 * sky));
          v.depth(row, u) = 0;
        }
      }
    }
  }

  // A vertical face from a to b up to height h, textured from `offset` into the tile
  // of `kind`, coloured by `colour` and lit by the sun; `on_pixel` as in View::Draw.
  const auto face = [&](View& v, Vec2 a, Vec2 b, double height, const std::string& kind, const cv::Vec3d& colour,
                        double offset, auto&& on_pixel) {
    const double len = std::hypot(b.x - a.x, b.y - a.y);
    if (len < 1e-9) return;
    Patch p;
    p.c = {a.x, a.y, 0};
    p.e = {(b.x - a.x) / len, (b.y - a.y) / len, 0};
    p.n = {p.e[1], -p.e[0], 0};
    p.s1 = len, p.height = height;
    const cv::Vec3d tint = colour * (0.45 + 0.55 * std::abs(p.n.dot(sun)));
    const cv::Mat& tile = tiles.faces.count(kind) ? tiles.faces.at(kind) : tiles.faces.at("noise");
    v.Draw(
        p,
        [&](double ss, double z, cv::Vec3b& bgr) {
          const double g = tile.at<uint8_t>(Wrap(z, kTileZ), Wrap(ss + offset, kTileS));
          bgr = cv::Vec3b(cv::saturate_cast<uint8_t>(tint[0] * g), cv::saturate_cast<uint8_t>(tint[1] * g),
                          cv::saturate_cast<uint8_t>(tint[2] * g));
          return true;
        },
        on_pixel);
  };
  for (View& v : views) {
    uint32_t salt = 100;
    for (const auto& obj : scenario_.objects) {
      const size_t n = obj.polygon.size(), edges = obj.closed ? n : n - 1;
      double s0 = 0;
      for (size_t i = 0; i < edges; ++i, ++salt) {
        const Vec2 a = obj.polygon[i], b = obj.polygon[(i + 1) % n];
        face(v, a, b, obj.height_m, obj.texture, Tint(obj.texture), s0 + 3.7 * (salt % 3),
             [&](int u, int row, bool nearer) {
               if (nearer && !v.agent.empty()) v.agent(row, u) = 0;  // hides any agent drawn there
             });
        s0 += std::hypot(b.x - a.x, b.y - a.y);
      }
    }
  }

  // Agents: a sprite on its plane through the centre facing the left camera (the same
  // plane in both views), or without sprites its box.
  StereoFrame f;
  std::vector<cv::Mat1b> coverage(boxes.size());
  std::vector<const Sprite*> drawn(boxes.size(), nullptr);
  for (size_t i = 0; i < boxes.size(); ++i) {
    const Box3& box = boxes[i];
    const int agent = static_cast<int>(i) + 1;
    coverage[i] = cv::Mat1b(s.height, s.width, uint8_t{0});
    const Sprite* sprite = SpriteFor(box, left_origin);
    drawn[i] = sprite;
    // The sprite's plane (through the centre, facing the left camera) and the sprite
    // at about its size on screen (area averaging when shrinking), for both views.
    Patch p;
    cv::Mat bgr_small, alpha_small;
    cv::Size px;
    double width = 0;
    if (sprite) {
      const double bx = box.pose.x - left_origin[0], by = box.pose.y - left_origin[1], r = std::hypot(bx, by);
      if (r < 0.1) continue;
      p.c = {box.pose.x, box.pose.y, 0};
      p.n = {bx / r, by / r, 0};
      p.e = {by / r, -bx / r, 0};  // to the camera's right
      width = box.height_m * sprite->Aspect();
      p.s0 = -width / 2, p.s1 = width / 2, p.height = box.height_m;
      const double range = (world_from_cam.t() * (p.c - left_origin))[2];
      if (range < 0.3) continue;  // beside or behind the camera
      px = cv::Size(std::max(2, static_cast<int>(std::lround(s.focal_px * width / range))),
                    std::max(2, static_cast<int>(std::lround(s.focal_px * box.height_m / range))));
      const int interp = px.height < sprite->bgr.rows ? cv::INTER_AREA : cv::INTER_LINEAR;
      cv::resize(sprite->bgr, bgr_small, px, 0, 0, interp);
      cv::resize(sprite->alpha, alpha_small, px, 0, 0, interp);
    }
    for (int k = 0; k < 2; ++k) {
      View& v = views[k];
      const auto covered = [&](int u, int row, bool nearer) {
        if (k != 0) return;
        coverage[i](row, u) = 1;
        if (nearer) v.agent(row, u) = agent;
      };
      if (!sprite) {
        double s0 = 0;
        for (const auto& seg : BoxOutline(box.pose, box.length_m, box.width_m)) {
          face(v, seg.a, seg.b, box.height_m, box.cls == "Car" ? "checker" : "noise", cv::Vec3d(1, 1, 1),
               s0 + 1.3 * (box.id % 7), covered);
          s0 += std::hypot(seg.b.x - seg.a.x, seg.b.y - seg.a.y);
        }
        continue;
      }
      v.Draw(
          p,
          [&](double ss, double z, cv::Vec3b& bgr) {
            const int col = std::min(px.width - 1, static_cast<int>((ss - p.s0) / width * px.width));
            const int row = std::min(px.height - 1, static_cast<int>((box.height_m - z) / box.height_m * px.height));
            if (alpha_small.at<uint8_t>(row, col) < 128) return false;
            bgr = bgr_small.at<cv::Vec3b>(row, col);
            return true;
          },
          covered);
    }
  }

  f.left_bgr = views[0].image;
  f.right_bgr = views[1].image;
  cv::cvtColor(f.left_bgr, f.left, cv::COLOR_BGR2GRAY);
  cv::cvtColor(f.right_bgr, f.right, cv::COLOR_BGR2GRAY);
  f.depth = views[0].depth;
  f.depth_right = views[1].depth;
  f.disparity = cv::Mat(s.height, s.width, CV_32F, cv::Scalar(0));
  for (int v = 0; v < s.height; ++v) {
    for (int u = 0; u < s.width; ++u) {
      const float z = f.depth.at<float>(v, u);
      if (z > 0) f.disparity.at<float>(v, u) = static_cast<float>(s.focal_px * s.baseline_m / z);
    }
  }

  // What each agent shows the left camera, and its KITTI object label:
  //   type truncated occluded alpha bbox(4) dims(h w l) location(x y z) rotation_y
  for (size_t i = 0; i < boxes.size(); ++i) {
    const Box3& box = boxes[i];
    const int covered = cv::countNonZero(coverage[i]);
    if (covered == 0) continue;
    const int seen = cv::countNonZero(views[0].agent == static_cast<int>(i) + 1);
    const cv::Rect extent = cv::boundingRect(coverage[i]);
    const cv::Vec3d c_cam = world_from_cam.t() * (cv::Vec3d(box.pose.x, box.pose.y, box.height_m / 2) - left_origin);
    if (c_cam[2] > 60 || c_cam[2] <= 0.1) continue;
    // Truncation: the full extent's box against the part inside the image.
    const double full_h = s.focal_px * box.height_m / c_cam[2];
    const double truncated = std::clamp(1.0 - extent.height / std::max(1.0, full_h), 0.0, 1.0);
    AgentView view{box.id,
                   box.cls,
                   drawn[i] ? drawn[i]->name : "",
                   cv::Rect2d(extent),
                   truncated,
                   static_cast<double>(seen) / covered,
                   c_cam[2]};
    if (view.visible < 0.05) continue;
    const int occluded = view.visible > 0.8 ? 0 : view.visible > 0.4 ? 1 : 2;
    const double rotation_y = -(box.pose.yaw_rad - yaw);  // about the camera's y (down) axis
    const double alpha = rotation_y - std::atan2(c_cam[0], c_cam[2]);
    char line[320];
    std::snprintf(line, sizeof(line), "%s %.2f %d %.2f %.2f %.2f %.2f %.2f %.2f %.2f %.2f %.2f %.2f %.2f %.2f",
                  box.cls.c_str(), truncated, occluded, std::atan2(std::sin(alpha), std::cos(alpha)), view.box.x,
                  view.box.y, view.box.br().x - 1, view.box.br().y - 1, box.height_m, box.width_m, box.length_m,
                  c_cam[0], c_cam[1] + box.height_m / 2, c_cam[2],
                  std::atan2(std::sin(rotation_y), std::cos(rotation_y)));
    f.kitti_labels.push_back(line);
    f.agents.push_back(std::move(view));
  }
  return f;
}

}  // namespace specht::sim
