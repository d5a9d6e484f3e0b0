// specht/sim/sprites.h: photographs of pedestrians, cyclists and cars cut out with
// their masks, so the simulator renders agents a COCO detector recognises.
//
// Sources, in the data directory (sprites/, see its README for licences):
//   coco128/annotations.json + images/   COCO instance polygons: person → pedestrian;
//       a bicycle or motorcycle together with the person riding it (the person's box
//       overlaps the vehicle's by at least half the vehicle's) → cyclist; car → car
//   davis/<sequence>/NNNNN.jpg + .png    binary masks: car-shadow, car-roundabout → car;
//       bmx-trees → cyclist
// A cut-out is kept when it is at least min_height_px tall, does not touch its
// image's border (a cut object), is no COCO crowd, and its mask fills at least
// min_fill of its box. Names: "coco/<image id>/<annotation id>", "davis/<sequence>/<frame>".
//
// Held out from tuning (the set evaluation runs on), so no figure is measured on the
// sprites it was tuned with: COCO cut-outs of images whose id is divisible by 3;
// car-roundabout (tuning has car-shadow); bmx-trees frames from 40 on (the same rider
// as the earlier frames, later in the sequence: the weakest split, for want of another
// cyclist).
#pragma once

#include <map>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace specht::sim {

struct Sprite {
  std::string name;
  std::string cls;  // pedestrian, cyclist, car
  cv::Mat bgr;      // CV_8UC3, cropped to the mask's box
  cv::Mat alpha;    // CV_8U, 255 where the object is
  bool held_out = false;
  double Aspect() const { return static_cast<double>(bgr.cols) / bgr.rows; }
};

enum class SpriteSet { kTuning, kHeldOut, kAll };
// "tuning", "held_out", "all"; throws InputError naming `what` otherwise.
SpriteSet ParseSpriteSet(const std::string& text, const std::string& what);

struct SpriteOptions {
  int min_height_px = 80;
  double min_fill = 0.25;
};

class SpriteLibrary {
 public:
  // Reads every source under `sprites_dir` (<data>/sprites). Throws InputError naming
  // the file and the reason when one is missing or unreadable.
  static SpriteLibrary Load(const std::string& sprites_dir, const SpriteOptions& options = {});

  // The sprites of `cls` in `set`, by name (a stable order).
  std::vector<const Sprite*> Of(const std::string& cls, SpriteSet set) const;
  // The sprite named `name`; throws InputError listing what `cls` has when unknown.
  const Sprite& Named(const std::string& name) const;
  size_t size() const { return sprites_.size(); }
  const std::vector<Sprite>& all() const { return sprites_; }

 private:
  std::vector<Sprite> sprites_;  // sorted by name
};

}  // namespace specht::sim
