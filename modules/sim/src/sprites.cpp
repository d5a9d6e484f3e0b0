#include "specht/sim/sprites.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <set>

#include "specht/core/error.h"

namespace specht::sim {
namespace {

namespace fs = std::filesystem;

cv::Mat Read(const std::string& path, int flags) {
  cv::Mat m = cv::imread(path, flags);
  if (m.empty()) throw InputError(path + ": cannot read the image (missing or corrupt)");
  return m;
}

// The cut-out of `mask` (non-zero = object) from `image`, if it passes the filters.
std::optional<Sprite> CutOut(const cv::Mat& image, const cv::Mat& mask, std::string name, std::string cls,
                             bool held_out, const SpriteOptions& o) {
  const cv::Rect box = cv::boundingRect(mask);
  if (box.height < o.min_height_px || box.width < 4) return std::nullopt;
  if (box.x <= 1 || box.y <= 1 || box.br().x >= image.cols - 1 || box.br().y >= image.rows - 1) return std::nullopt;
  const double fill = static_cast<double>(cv::countNonZero(mask(box))) / box.area();
  if (fill < o.min_fill) return std::nullopt;
  Sprite s{std::move(name), std::move(cls), image(box).clone(), cv::Mat(), held_out};
  s.alpha = (mask(box) > 0);
  return s;
}

cv::Mat PolygonMask(const nlohmann::json& segmentation, cv::Size size) {
  cv::Mat mask(size, CV_8U, cv::Scalar(0));
  std::vector<std::vector<cv::Point>> polygons;
  for (const auto& poly : segmentation) {
    std::vector<cv::Point> points;
    // Sub-pixel vertices: 3 fractional bits (fillPoly's shift).
    for (size_t i = 0; i + 1 < poly.size(); i += 2)
      points.emplace_back(static_cast<int>(std::lround(poly[i].get<double>() * 8)),
                          static_cast<int>(std::lround(poly[i + 1].get<double>() * 8)));
    if (points.size() >= 3) polygons.push_back(std::move(points));
  }
  cv::fillPoly(mask, polygons, cv::Scalar(255), cv::LINE_8, 3);
  return mask;
}

double OverlapOfSecond(const std::vector<double>& a, const std::vector<double>& b) {  // COCO [x y w h]
  const double x0 = std::max(a[0], b[0]), y0 = std::max(a[1], b[1]);
  const double x1 = std::min(a[0] + a[2], b[0] + b[2]), y1 = std::min(a[1] + a[3], b[1] + b[3]);
  return x1 > x0 && y1 > y0 ? (x1 - x0) * (y1 - y0) / (b[2] * b[3]) : 0.0;
}

void LoadCoco(const std::string& dir, const SpriteOptions& o, std::vector<Sprite>& out) {
  const std::string path = dir + "/annotations.json";
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open the COCO annotations");
  nlohmann::json j;
  try {
    in >> j;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path + ": not JSON (" + std::string(e.what()) + ")");
  }
  std::map<int, std::string> category;
  for (const auto& c : j.at("categories")) category[c.at("id").get<int>()] = c.at("name").get<std::string>();
  std::map<int, std::vector<const nlohmann::json*>> by_image;
  for (const auto& a : j.at("annotations"))
    if (a.value("iscrowd", 0) == 0) by_image[a.at("image_id").get<int>()].push_back(&a);
  for (const auto& image_json : j.at("images")) {
    const int id = image_json.at("id").get<int>();
    const auto found = by_image.find(id);
    if (found == by_image.end()) continue;
    const cv::Mat image = Read(dir + "/images/" + image_json.at("file_name").get<std::string>(), cv::IMREAD_COLOR);
    const auto& anns = found->second;
    const auto bbox = [](const nlohmann::json* a) { return a->at("bbox").get<std::vector<double>>(); };
    const auto name = [&](const nlohmann::json* a) {
      return "coco/" + std::to_string(id) + "/" + std::to_string(a->at("id").get<long>());
    };
    std::set<const nlohmann::json*> riders;
    for (const auto* v : anns) {
      const std::string vc = category[v->at("category_id").get<int>()];
      if (vc != "bicycle" && vc != "motorcycle") continue;
      // The rider: the person covering most of the vehicle's box.
      const nlohmann::json* rider = nullptr;
      double best = 0.5;
      for (const auto* p : anns) {
        if (category[p->at("category_id").get<int>()] != "person") continue;
        const double overlap = OverlapOfSecond(bbox(p), bbox(v));
        if (overlap >= best) best = overlap, rider = p;
      }
      if (!rider) continue;
      riders.insert(rider);
      cv::Mat mask =
          PolygonMask(v->at("segmentation"), image.size()) | PolygonMask(rider->at("segmentation"), image.size());
      if (auto s = CutOut(image, mask, name(v), "cyclist", id % 3 == 0, o)) out.push_back(std::move(*s));
    }
    for (const auto* a : anns) {
      const std::string c = category[a->at("category_id").get<int>()];
      if (riders.count(a) || (c != "person" && c != "car")) continue;
      const cv::Mat mask = PolygonMask(a->at("segmentation"), image.size());
      if (auto s = CutOut(image, mask, name(a), c == "person" ? "pedestrian" : "car", id % 3 == 0, o))
        out.push_back(std::move(*s));
    }
  }
}

void LoadDavis(const std::string& dir, const SpriteOptions& o, std::vector<Sprite>& out) {
  const std::map<std::string, std::string> sequences = {
      {"car-shadow", "car"}, {"car-roundabout", "car"}, {"bmx-trees", "cyclist"}};
  for (const auto& [sequence, cls] : sequences) {
    const std::string seq_dir = dir + "/" + sequence;
    if (!fs::is_directory(seq_dir)) throw InputError(seq_dir + ": missing (a DAVIS sequence of the sprites)");
    std::vector<std::string> frames;
    for (const auto& e : fs::directory_iterator(seq_dir))
      if (e.path().extension() == ".jpg") frames.push_back(e.path().stem().string());
    std::sort(frames.begin(), frames.end());
    for (const auto& f : frames) {
      const cv::Mat image = Read(seq_dir + "/" + f + ".jpg", cv::IMREAD_COLOR);
      const cv::Mat mask = Read(seq_dir + "/" + f + ".png", cv::IMREAD_GRAYSCALE);
      if (mask.size() != image.size())
        throw InputError(seq_dir + "/" + f + ".png: the mask is not the size of its image");
      const bool held_out = sequence == "car-roundabout" || (sequence == "bmx-trees" && std::stoi(f) >= 40);
      if (auto s = CutOut(image, mask, "davis/" + sequence + "/" + f, cls, held_out, o)) out.push_back(std::move(*s));
    }
  }
}

}  // namespace

SpriteSet ParseSpriteSet(const std::string& text, const std::string& what) {
  if (text == "tuning") return SpriteSet::kTuning;
  if (text == "held_out") return SpriteSet::kHeldOut;
  if (text == "all") return SpriteSet::kAll;
  throw InputError(what + ": \"" + text + "\" is not a sprite set (tuning, held_out, all)");
}

SpriteLibrary SpriteLibrary::Load(const std::string& dir, const SpriteOptions& options) {
  SpriteLibrary lib;
  LoadCoco(dir + "/coco128", options, lib.sprites_);
  LoadDavis(dir + "/davis", options, lib.sprites_);
  std::sort(lib.sprites_.begin(), lib.sprites_.end(), [](const Sprite& a, const Sprite& b) { return a.name < b.name; });
  return lib;
}

std::vector<const Sprite*> SpriteLibrary::Of(const std::string& cls, SpriteSet set) const {
  std::vector<const Sprite*> out;
  for (const auto& s : sprites_) {
    if (s.cls != cls) continue;
    if (set == SpriteSet::kAll || (set == SpriteSet::kHeldOut) == s.held_out) out.push_back(&s);
  }
  return out;
}

const Sprite& SpriteLibrary::Named(const std::string& name) const {
  const auto it = std::lower_bound(sprites_.begin(), sprites_.end(), name,
                                   [](const Sprite& s, const std::string& n) { return s.name < n; });
  if (it != sprites_.end() && it->name == name) return *it;
  std::string known;
  for (const auto& s : sprites_) known += (known.empty() ? "" : ", ") + s.name;
  throw InputError("no sprite named \"" + name + "\" (there are: " + known.substr(0, 300) + "…)");
}

}  // namespace specht::sim
