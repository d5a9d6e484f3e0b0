#include "internal/perception_video.h"

#include <cmath>
#include <cstdio>
#include <opencv2/imgproc.hpp>

namespace specht::pipeline::internal {
namespace {

cv::Scalar Bgr(const std::string& cls) {
  const auto c = ClassColour(cls);
  return cv::Scalar(c[2], c[1], c[0]);
}

}  // namespace

void Label(cv::Mat& image, const std::string& text, cv::Point at, const cv::Scalar& colour, double scale) {
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, scale, 1, &baseline);
  at.x = std::clamp(at.x, 0, std::max(0, image.cols - size.width));
  at.y = std::clamp(at.y, size.height + 2, image.rows - 2);
  cv::rectangle(image, {at.x, at.y - size.height - 2}, {at.x + size.width, at.y + baseline}, colour, cv::FILLED);
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
}

namespace {

const types::Track* NearestTrack(const types::Obstacle& o, const std::vector<types::Track>& tracks) {
  const types::Track* best = nullptr;
  double best_d = 2.0;
  for (const auto& t : tracks) {
    if (t.stamp != o.stamp) continue;
    const double d = std::hypot(t.x_m - o.x_m, t.y_m - o.y_m);
    if (d < best_d) best_d = d, best = &t;
  }
  return best;
}

// The cost layer's grey levels: unknown as the background, free white, margins
// shaded darker with the cost, inscribed dark grey, lethal black.
cv::Mat CostColours() {
  cv::Mat lut(1, 256, CV_8UC3);
  for (int v = 0; v < 256; ++v) {
    const auto shade = static_cast<uint8_t>(255 - v * 150 / 252);
    lut.at<cv::Vec3b>(v) = v == types::CostGrid::kUnknown     ? cv::Vec3b(160, 160, 160)
                           : v == types::CostGrid::kInscribed ? cv::Vec3b(90, 90, 90)
                           : v == types::CostGrid::kLethal    ? cv::Vec3b(0, 0, 0)
                                                              : cv::Vec3b(shade, shade, shade);
  }
  return lut;
}

// The part of the cost grid in view, resampled (nearest cell) onto `image`, north up.
void DrawCost(const types::CostGrid& g, double x0, double y1, double px_per_m, cv::Mat& image) {
  static const cv::Mat lut = CostColours();
  // Pixel (c, r) centre at map (x0 + (c + ½)/s, y1 − (r + ½)/s): its grid cell column
  // and row are affine in c and r; rows flip (grid rows grow with y).
  const double cells_per_px = 1.0 / (px_per_m * g.resolution_m);
  cv::Mat map_x(image.size(), CV_32F), map_y(image.size(), CV_32F);
  for (int c = 0; c < image.cols; ++c)
    map_x.at<float>(0, c) = static_cast<float>((x0 - g.origin_x_m) / g.resolution_m + (c + 0.5) * cells_per_px - 0.5);
  for (int r = 1; r < image.rows; ++r) map_x.row(0).copyTo(map_x.row(r));
  for (int r = 0; r < image.rows; ++r)
    map_y.row(r).setTo(static_cast<float>((y1 - g.origin_y_m) / g.resolution_m - (r + 0.5) * cells_per_px - 0.5));
  cv::Mat cost;
  cv::remap(g.cost, cost, map_x, map_y, cv::INTER_NEAREST, cv::BORDER_CONSTANT, cv::Scalar(types::CostGrid::kUnknown));
  cv::Mat colour;
  cv::cvtColor(cost, colour, cv::COLOR_GRAY2BGR);
  cv::LUT(colour, lut, image);
}

}  // namespace

std::array<unsigned char, 3> ClassColour(const std::string& cls) {
  if (cls == "pedestrian") return {220, 30, 30};
  if (cls == "cyclist") return {230, 180, 0};
  if (cls == "car") return {240, 120, 0};
  return {120, 0, 160};
}

cv::Mat AnnotatedCamera(const PerceivedFrame& frame, const std::vector<types::Track>& tracks) {
  cv::Mat image;
  if (frame.image.channels() == 1)
    cv::cvtColor(frame.image, image, cv::COLOR_GRAY2BGR);
  else
    image = frame.image.clone();
  for (size_t i = 0; i < frame.detections.size(); ++i) {
    const auto& d = frame.detections[i];
    const cv::Scalar colour = Bgr(d.cls);
    cv::rectangle(image, cv::Rect(d.box), colour, 2);
    std::string text = d.cls;
    const int k = i < frame.obstacle_of.size() ? frame.obstacle_of[i] : -1;
    if (k >= 0) {
      const types::Obstacle& o = frame.obstacles[k];
      char range[32];
      std::snprintf(range, sizeof(range), " %.1f m", o.range_m);
      text += range;
      if (const types::Track* t = NearestTrack(o, tracks)) text = "#" + std::to_string(t->id) + " " + text;
    }
    Label(image, text, {static_cast<int>(d.box.x), static_cast<int>(d.box.y) - 3}, colour);
  }
  return image;
}

BirdsEyeView BirdsEyeView::Around(const mrpt::poses::CPose3D& car, double extent_m, int size_px) {
  return {car.x(), car.y(), extent_m, size_px};
}

cv::Mat BirdsEye(const world::Snapshot& s, const mrpt::poses::CPose3D& car, double t_s, const BirdsEyeView& view,
                 const std::vector<cv::Point2d>& path) {
  const int size_px = view.size_px;
  const double px_per_m = size_px / view.extent_m;
  const double x0 = view.centre_x_m - view.extent_m / 2, y1 = view.centre_y_m + view.extent_m / 2;
  const auto inside = [&](const cv::Point& p) { return p.x >= 0 && p.y >= 0 && p.x < size_px && p.y < size_px; };
  const auto pixel = [&](double x, double y) {
    return cv::Point(static_cast<int>(std::lround((x - x0) * px_per_m)),
                     static_cast<int>(std::lround((y1 - y) * px_per_m)));
  };
  cv::Mat image(size_px, size_px, CV_8UC3, cv::Scalar(160, 160, 160));
  if (s.cost && !s.cost->cost.empty()) DrawCost(*s.cost, x0, y1, px_per_m, image);
  for (const auto& o : s.obstacles) cv::circle(image, pixel(o.x_m, o.y_m), 3, Bgr(o.cls), cv::FILLED, cv::LINE_AA);
  for (const auto& t : s.tracks) {
    const cv::Scalar colour = Bgr(t.cls);
    for (const auto& p : t.prediction) {
      // The 2σ ellipse of the predicted position: the covariance's eigenvectors.
      cv::Mat values, vectors;
      cv::eigen(cv::Mat(p.covariance), values, vectors);
      const double angle = std::atan2(vectors.at<double>(0, 1), vectors.at<double>(0, 0)) * 180 / CV_PI;
      const cv::Size axes(std::max(1, static_cast<int>(2 * std::sqrt(std::max(0.0, values.at<double>(0))) * px_per_m)),
                          std::max(1, static_cast<int>(2 * std::sqrt(std::max(0.0, values.at<double>(1))) * px_per_m)));
      cv::ellipse(image, pixel(p.x_m, p.y_m), axes, -angle, 0, 360, colour, 1, cv::LINE_AA);
    }
    const cv::Point at = pixel(t.x_m, t.y_m);
    if (!inside(at)) continue;  // its label would cling to the edge
    cv::circle(image, at, 6, colour, 2, cv::LINE_AA);
    if (!t.prediction.empty()) cv::line(image, at, pixel(t.prediction.back().x_m, t.prediction.back().y_m), colour, 1);
    Label(image, "#" + std::to_string(t.id) + " " + t.cls, at + cv::Point(8, -8), colour, 0.4);
  }
  std::vector<cv::Point> line;
  for (const auto& p : path) line.push_back(pixel(p.x, p.y));
  cv::polylines(image, line, false, cv::Scalar(200, 90, 30), 2, cv::LINE_AA);
  const double yaw = car.yaw();
  const auto ahead = [&](double forward, double left) {
    return pixel(car.x() + forward * std::cos(yaw) - left * std::sin(yaw),
                 car.y() + forward * std::sin(yaw) + left * std::cos(yaw));
  };
  const std::vector<cv::Point> triangle = {ahead(1.5, 0), ahead(-0.8, 0.8), ahead(-0.8, -0.8)};
  cv::fillConvexPoly(image, triangle, cv::Scalar(200, 90, 30), cv::LINE_AA);
  char stamp[64];
  std::snprintf(stamp, sizeof(stamp), "t = %.1f s   %zu tracks   %zu obstacles", t_s, s.tracks.size(),
                s.obstacles.size());
  Label(image, stamp, {4, 18}, cv::Scalar(255, 255, 255), 0.5);
  return image;
}

}  // namespace specht::pipeline::internal
