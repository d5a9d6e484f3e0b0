#include "specht/io/map_io.h"

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/io/CFileOutputStream.h>
#include <mrpt/serialization/CArchive.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sstream>

#include "specht/core/error.h"
#include "specht/core/text.h"
#include "specht/io/atomic_file.h"

namespace fs = std::filesystem;
using mrpt::maps::COccupancyGridMap2D;

namespace specht::io {
namespace {

// A map picture's longest side at most: a building-sized grid (9,000 cells across) is
// drawn averaged rather than at one pixel a cell.
constexpr int kMaxPictureSidePx = 4096;

// MRPT cells hold the probability of being free; ROS and people think in occupancy.
double Occupancy(const COccupancyGridMap2D& grid, unsigned cx, unsigned cy) { return 1.0 - grid.getCell(cx, cy); }

}  // namespace

void WriteRosMap(const COccupancyGridMap2D& grid, const std::string& yaml_path) {
  const fs::path yaml(yaml_path);
  const fs::path pgm = fs::path(yaml).replace_extension(".pgm");
  const unsigned w = grid.getSizeX(), h = grid.getSizeY();
  std::string data = "P5\n# specht occupancy grid\n" + std::to_string(w) + " " + std::to_string(h) + "\n255\n";
  data.reserve(data.size() + size_t(w) * h);
  // PGM rows run top to bottom; the grid's y axis points up.
  for (unsigned row = 0; row < h; ++row) {
    const unsigned cy = h - 1 - row;
    for (unsigned cx = 0; cx < w; ++cx) {
      const double p = Occupancy(grid, cx, cy);
      data.push_back(static_cast<char>(p > kRosOccupiedThresh ? 0 : p < kRosFreeThresh ? 254 : 205));
    }
  }
  WriteTextAtomically(pgm.string(), data);

  std::ostringstream y;
  char origin[128];
  std::snprintf(origin, sizeof(origin), "[%.6f, %.6f, 0.0]", grid.getXMin(), grid.getYMin());
  y << "image: " << pgm.filename().string() << "\n"
    << "mode: trinary\n"
    << "resolution: " << grid.getResolution() << "\n"
    << "origin: " << origin << "\n"
    << "negate: 0\n"
    << "occupied_thresh: " << kRosOccupiedThresh << "\n"
    << "free_thresh: " << kRosFreeThresh << "\n";
  WriteTextAtomically(yaml_path, y.str());
}

COccupancyGridMap2D ReadRosMap(const std::string& yaml_path) {
  YAML::Node y;
  try {
    y = YAML::LoadFile(yaml_path);
  } catch (const YAML::BadFile&) {
    throw InputError(yaml_path + ": cannot read map file");
  } catch (const YAML::ParserException& e) {
    throw InputError(Where(yaml_path, e.mark.line + 1) + "YAML syntax error: " + e.msg);
  }
  auto field = [&](const char* key) {
    if (!y[key]) throw InputError(yaml_path + ": missing field '" + std::string(key) + "'");
    return y[key];
  };
  double resolution = 0, occupied = 0, free = 0;
  std::vector<double> origin;
  std::string image;
  int negate = 0;
  try {
    image = field("image").as<std::string>();
    resolution = field("resolution").as<double>();
    origin = field("origin").as<std::vector<double>>();
    negate = y["negate"] ? y["negate"].as<int>() : 0;
    occupied = y["occupied_thresh"] ? y["occupied_thresh"].as<double>() : kRosOccupiedThresh;
    free = y["free_thresh"] ? y["free_thresh"].as<double>() : kRosFreeThresh;
  } catch (const YAML::Exception& e) {
    throw InputError(Where(yaml_path, e.mark.line + 1) + "bad map field: " + e.msg);
  }
  if (!(resolution > 0) || origin.size() < 2) {
    throw InputError(yaml_path + ": 'resolution' must be > 0 and 'origin' needs [x, y, yaw]");
  }
  const fs::path img_path = fs::path(yaml_path).parent_path() / image;
  const cv::Mat img = cv::imread(img_path.string(), cv::IMREAD_GRAYSCALE);
  if (img.empty()) throw InputError(img_path.string() + ": cannot read map image");
  COccupancyGridMap2D grid(static_cast<float>(origin[0]), static_cast<float>(origin[0] + img.cols * resolution),
                           static_cast<float>(origin[1]), static_cast<float>(origin[1] + img.rows * resolution),
                           static_cast<float>(resolution));
  for (int row = 0; row < img.rows; ++row) {
    for (int col = 0; col < img.cols; ++col) {
      const double v = img.at<unsigned char>(row, col) / 255.0;
      const double p_occ = negate ? v : 1.0 - v;
      const float p_free = p_occ > occupied ? 0.0f : p_occ < free ? 1.0f : 0.5f;
      grid.setCell(col, img.rows - 1 - row, p_free);
    }
  }
  return grid;
}

void WriteMrptGridmap(const COccupancyGridMap2D& grid, const std::string& path) {
  WriteAtomically(path, [&](const std::string& tmp) {
    mrpt::io::CFileOutputStream out(tmp);
    if (!out.fileOpenCorrectly()) throw RuntimeError(path + ": cannot write");
    auto archive = mrpt::serialization::archiveFrom(out);
    archive << grid;
  });
}

COccupancyGridMap2D ReadMrptGridmap(const std::string& path) {
  mrpt::io::CFileGZInputStream in;
  if (!in.open(path)) throw InputError(path + ": cannot open gridmap");
  COccupancyGridMap2D grid;
  try {
    auto archive = mrpt::serialization::archiveFrom(in);
    archive >> grid;
  } catch (const std::exception& e) {
    throw InputError(path + ": not a readable MRPT gridmap");
  }
  return grid;
}

void WriteMapPng(const COccupancyGridMap2D& grid, const std::vector<PathOverlay>& paths, const std::string& path,
                 int min_width_px) {
  const int w = static_cast<int>(grid.getSizeX()), h = static_cast<int>(grid.getSizeY());
  // Crop to the observed cells (and the paths), with a margin.
  int x0 = w, y0 = h, x1 = -1, y1 = -1;
  auto grow = [&](int cx, int cy) {
    x0 = std::min(x0, cx), y0 = std::min(y0, cy), x1 = std::max(x1, cx), y1 = std::max(y1, cy);
  };
  for (int cy = 0; cy < h; ++cy) {
    for (int cx = 0; cx < w; ++cx) {
      if (std::abs(grid.getCell(cx, cy) - 0.5f) > 0.05f) grow(cx, cy);
    }
  }
  for (const auto& overlay : paths) {
    for (const auto& p : *overlay.trajectory) grow(grid.x2idx(p.pose.x()), grid.y2idx(p.pose.y()));
  }
  if (x1 < 0) x0 = 0, y0 = 0, x1 = std::max(0, w - 1), y1 = std::max(0, h - 1);
  const int margin = 10;
  x0 = std::max(0, x0 - margin), y0 = std::max(0, y0 - margin);
  x1 = std::min(w - 1, x1 + margin), y1 = std::min(h - 1, y1 + margin);
  const int cw = x1 - x0 + 1, ch = y1 - y0 + 1;
  // One pixel per cell, scaled up (a whole number of pixels a cell) to min_width_px,
  // or down (averaged) so that neither side exceeds kMaxPictureSidePx.
  cv::Mat cells(ch, cw, CV_8UC1);
  for (int cy = y0; cy <= y1; ++cy) {
    for (int cx = x0; cx <= x1; ++cx) {
      const float free = grid.getCell(cx, cy);
      // Unknown light grey; known cells from black (occupied) to white (free).
      cells.at<unsigned char>(y1 - cy, cx - x0) =
          std::abs(free - 0.5f) <= 0.05f ? 205 : static_cast<unsigned char>(255 * free);
    }
  }
  const double up = std::max(1, (min_width_px + cw - 1) / cw);
  const double scale = std::min(up, static_cast<double>(kMaxPictureSidePx) / std::max(cw, ch));
  cv::Mat grey;
  cv::resize(cells, grey, cv::Size(), scale, scale, scale >= 1 ? cv::INTER_NEAREST : cv::INTER_AREA);
  cells.release();
  cv::Mat img;
  cv::cvtColor(grey, img, cv::COLOR_GRAY2BGR);
  auto to_px = [&](double x, double y) {
    return cv::Point(static_cast<int>((grid.x2idx(x) - x0 + 0.5) * scale),
                     static_cast<int>((y1 - grid.y2idx(y) + 0.5) * scale));
  };
  const int thickness = std::max(1, static_cast<int>(scale) / 2 + 1);
  int legend_y = 24;
  for (const auto& overlay : paths) {
    const cv::Scalar color(overlay.rgb[2], overlay.rgb[1], overlay.rgb[0]);
    std::vector<cv::Point> pts;
    for (const auto& p : *overlay.trajectory) pts.push_back(to_px(p.pose.x(), p.pose.y()));
    if (pts.empty()) continue;
    if (overlay.markers) {
      for (const auto& pt : pts) cv::circle(img, pt, 3 + thickness, color, cv::FILLED, cv::LINE_AA);
    } else if (overlay.segments) {
      for (size_t i = 0; i + 1 < pts.size(); i += 2) cv::line(img, pts[i], pts[i + 1], color, 1, cv::LINE_AA);
    } else {
      cv::polylines(img, pts, false, color, thickness, cv::LINE_AA);
      cv::circle(img, pts.front(), 4 + thickness, color, 2, cv::LINE_AA);
      cv::rectangle(img, pts.back() - cv::Point(5, 5), pts.back() + cv::Point(5, 5), color, cv::FILLED);
    }
    if (!overlay.label.empty()) {
      cv::line(img, {10, legend_y - 5}, {40, legend_y - 5}, color, 3);
      cv::putText(img, AsciiForImage(overlay.label), {48, legend_y}, cv::FONT_HERSHEY_SIMPLEX, 0.55,
                  cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
      legend_y += 22;
    }
  }
  // Scale bar: the largest of 1, 2, 5, 10, 20, 50 m that fits a quarter of the width.
  const double px_per_m = scale / grid.getResolution();
  double bar_m = 1;
  for (double c : {1.0, 2.0, 5.0, 10.0, 20.0, 50.0}) {
    if (c * px_per_m <= img.cols / 4.0) bar_m = c;
  }
  const int bar_px = static_cast<int>(bar_m * px_per_m);
  const cv::Point bar0(15, img.rows - 15);
  cv::rectangle(img, bar0 - cv::Point(0, 6), bar0 + cv::Point(bar_px, 0), cv::Scalar(0, 0, 0), cv::FILLED);
  cv::putText(img, std::to_string(static_cast<int>(bar_m)) + " m", bar0 + cv::Point(bar_px + 8, 0),
              cv::FONT_HERSHEY_SIMPLEX, 0.55, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
  WritePng(img, path);
}

void WritePng(const cv::Mat& image, const std::string& path) {
  WriteAtomically(path, [&](const std::string& tmp) {
    if (!cv::imwrite(tmp, image)) throw RuntimeError(path + ": cannot write PNG");
  });
}

void WriteTrajectoryPng(const std::vector<PathOverlay>& paths, const std::string& path, int min_width_px) {
  double x0 = 1e18, y0 = 1e18, x1 = -1e18, y1 = -1e18;
  for (const auto& overlay : paths) {
    for (const auto& p : *overlay.trajectory) {
      x0 = std::min(x0, p.pose.x()), x1 = std::max(x1, p.pose.x());
      y0 = std::min(y0, p.pose.y()), y1 = std::max(y1, p.pose.y());
    }
  }
  if (x1 < x0) x0 = y0 = 0, x1 = y1 = 1;
  const double extent = std::max({x1 - x0, y1 - y0, 1.0});
  const float res = static_cast<float>(extent / 400.0);
  const float margin = static_cast<float>(extent * 0.05);
  COccupancyGridMap2D canvas(static_cast<float>(x0) - margin, static_cast<float>(x1) + margin,
                             static_cast<float>(y0) - margin, static_cast<float>(y1) + margin, res);
  canvas.fill(1.0f);  // all free: a white background
  WriteMapPng(canvas, paths, path, min_width_px);
}

}  // namespace specht::io
