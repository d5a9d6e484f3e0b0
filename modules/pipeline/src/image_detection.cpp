// Detection on images (image_detection.h): the CNN
// detector (section "detect") on each image and, when right images and a
// calibration are given, our SGM and the box depth fusion (section "fusion"):
//   labels/<name>.txt      KITTI object labels (type, bbox; with depth: dimensions
//                          height/width (length = width), location = bottom centre
//                          in the camera frame; score last)
//   annotated/<name>.png   boxes with class, score and distance
//   detections.json        every detection (and its 3D position and covariance)
//   report.json/.md        counts per class, ms per stage
#include "specht/pipeline/image_detection.h"

#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>

#include "specht/core/error.h"
#include "specht/core/progress.h"
#include "specht/core/text.h"
#include "specht/detect/detector.h"
#include "specht/detect/fusion.h"
#include "specht/io/atomic_file.h"
#include "specht/io/map_io.h"
#include "specht/io/report.h"
#include "specht/pipeline/run_directory.h"
#include "specht/stereo/calibration.h"
#include "specht/stereo/images.h"
#include "specht/stereo/sgm.h"

namespace specht::pipeline {
namespace {

std::string KittiType(const std::string& cls) {
  static const std::map<std::string, std::string> types = {
      {"car", "Car"}, {"pedestrian", "Pedestrian"}, {"cyclist", "Cyclist"}, {"truck", "Truck"}};
  const auto it = types.find(cls);
  return it == types.end() ? "Misc" : it->second;
}

std::string KittiLine(const detect::Detection& d, const std::optional<detect::Obstacle3D>& o) {
  char line[256];
  if (o) {
    const double h = o->size_m.height, w = o->size_m.width;
    std::snprintf(line, sizeof(line), "%s -1 -1 -10 %.2f %.2f %.2f %.2f %.2f %.2f %.2f %.2f %.2f %.2f -10 %.3f",
                  KittiType(d.cls).c_str(), d.box.x, d.box.y, d.box.br().x, d.box.br().y, h, w, w, o->position_camera.x,
                  o->position_camera.y + h / 2, o->position_camera.z, d.score);
  } else {
    std::snprintf(line, sizeof(line), "%s -1 -1 -10 %.2f %.2f %.2f %.2f -1 -1 -1 -1000 -1000 -1000 -10 %.3f",
                  KittiType(d.cls).c_str(), d.box.x, d.box.y, d.box.br().x, d.box.br().y, d.score);
  }
  return line;
}

cv::Mat Annotate(const cv::Mat& image, const std::vector<detect::Detection>& detections,
                 const std::vector<std::optional<detect::Obstacle3D>>& obstacles) {
  cv::Mat out = image.clone();
  for (size_t i = 0; i < detections.size(); ++i) {
    const auto& d = detections[i];
    const cv::Scalar colour = d.cls == "car"          ? cv::Scalar(255, 160, 0)
                              : d.cls == "pedestrian" ? cv::Scalar(0, 0, 255)
                              : d.cls == "cyclist"    ? cv::Scalar(0, 200, 255)
                                                      : cv::Scalar(0, 220, 0);
    cv::rectangle(out, d.box, colour, 2);
    char text[96];
    if (obstacles[i])
      std::snprintf(text, sizeof(text), "%s %.2f %.1f m", d.cls.c_str(), d.score, obstacles[i]->distance_m);
    else
      std::snprintf(text, sizeof(text), "%s %.2f", d.cls.c_str(), d.score);
    const cv::Point corner(static_cast<int>(d.box.x), std::max(12, static_cast<int>(d.box.y) - 4));
    const std::string label = AsciiForImage(text);  // class names come from the model's label file
    cv::putText(out, label, corner, cv::FONT_HERSHEY_SIMPLEX, 0.5, cv::Scalar(0, 0, 0), 3, cv::LINE_AA);
    cv::putText(out, label, corner, cv::FONT_HERSHEY_SIMPLEX, 0.5, colour, 1, cv::LINE_AA);
  }
  return out;
}

}  // namespace

int DetectInImages(const params::Params& params, const ImageDetectionInputs& a, const std::string& data_dir,
                   const std::string& out, bool quiet) {
  if (!a.rights.empty() && a.rights.size() != a.images.size())
    throw InputError("--right: give one right image per image (" + std::to_string(a.images.size()) + "), got " +
                     std::to_string(a.rights.size()));
  if (!a.rights.empty() && a.calib.empty()) throw InputError("--right needs --calib (focal length and baseline)");
  detect::Detector detector(params.Get<detect::DetectorOptions>("detect"), data_dir);
  const auto& fusion = params.Get<detect::FusionOptions>("fusion");
  std::optional<stereo::RectifiedCamera> camera;
  if (!a.calib.empty()) {
    const stereo::StereoCalibration c = stereo::LoadCalibration(a.calib);
    if (!c.rectified) throw InputError(c.source + ": detect needs rectified images and their calibration");
    camera = c.camera;
  }
  std::unique_ptr<stereo::SemiGlobalMatcher> matcher;
  if (!a.rights.empty())
    matcher = std::make_unique<stereo::SemiGlobalMatcher>(params.Get<stereo::SgmOptions>("stereo"));

  PrepareRunDirectory(out, params);
  io::MakeOutputDir(out + "/labels");
  io::MakeOutputDir(out + "/annotated");
  io::RunReport report("detect");
  io::StageTimer timer;
  nlohmann::json all = nlohmann::json::array();
  std::map<std::string, long> counts;
  ProgressLine progress("detect", "images", !quiet);
  for (size_t i = 0; i < a.images.size(); ++i) {
    const cv::Mat image = cv::imread(a.images[i], cv::IMREAD_COLOR);
    if (image.empty()) throw InputError(a.images[i] + ": not a readable image");
    std::vector<detect::Detection> detections;
    {
      auto t = timer.Time("detect");
      detections = detector.Detect(image);
    }
    std::vector<std::optional<detect::Obstacle3D>> obstacles(detections.size());
    if (matcher) {
      cv::Mat disparity;
      {
        auto t = timer.Time("stereo");
        disparity = matcher->Compute(stereo::ReadGray8(a.images[i]), stereo::ReadGray8(a.rights[i]));
      }
      auto t = timer.Time("fusion");
      for (size_t k = 0; k < detections.size(); ++k)
        obstacles[k] = detect::Fuse(detections[k], disparity, *camera, fusion);
    }
    const std::string name = std::filesystem::path(a.images[i]).stem().string();
    std::string labels;
    for (size_t k = 0; k < detections.size(); ++k) {
      const auto& d = detections[k];
      ++counts[d.cls];
      labels += KittiLine(d, obstacles[k]) + "\n";
      nlohmann::json j = {{"image", a.images[i]},
                          {"class", d.cls},
                          {"label", d.label},
                          {"score", d.score},
                          {"box", {d.box.x, d.box.y, d.box.width, d.box.height}}};
      if (obstacles[k]) {
        const auto& o = *obstacles[k];
        j["distance_m"] = o.distance_m;
        j["position_camera"] = {o.position_camera.x, o.position_camera.y, o.position_camera.z};
        j["covariance"] = std::vector<double>(o.covariance.val, o.covariance.val + 9);
      }
      all.push_back(j);
    }
    io::WriteTextAtomically(out + "/labels/" + name + ".txt", labels);
    io::WritePng(Annotate(image, detections, obstacles), out + "/annotated/" + name + ".png");
    progress.Update(static_cast<double>(i + 1), static_cast<double>(i + 1) / a.images.size());
  }
  io::WriteTextAtomically(out + "/detections.json", all.dump(1) + "\n");
  report.json()["counts"] = counts;
  report.json()["timing"] = timer.ToJson();
  report.json()["inputs"] = {{"images", a.images.size()}, {"stereo", matcher != nullptr}};
  report.AddOutput("detections.json");
  report.Write(out);
  progress.Finish();
  long total = 0;
  for (const auto& [cls, n] : counts) total += n;
  std::printf("detect: %ld detections in %zu images (%.1f ms per image)\n", total, a.images.size(),
              timer.TotalMs("detect") / std::max<size_t>(1, a.images.size()));
  return 0;
}

}  // namespace specht::pipeline
