// specht/io/object_tracks.h: positions of many objects over time, one CSV row per
// object and time, with a header naming the columns (any order, extra columns kept
// out of the way):
//   id,t_s,x_m,y_m[,class][,truth_class][,ignore][,p_<class>...]
// `id` is any string without commas (a track id, an agent id, "seed3/17"), t_s
// seconds, x_m y_m map-frame metres. Used for the simulator's ground truth, the
// tracker's output (`specht track`), CLEAR MOT evaluation (`specht eval track`) and
// as the classifier's trajectory input (`specht classify prepare`). `ignore` = 1 marks
// a truth row as "don't care" (KITTI's DontCare: an agent present but out of the
// sensor's view): neither missed nor a false positive when tracked. p_<class>
// columns hold a classifier's probability of each class (empty where a row has
// none, e.g. a track too young to classify). Opens in any
// spreadsheet or pandas.read_csv.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace specht::io {

struct ObjectSample {
  std::string id;
  double t_s = 0, x_m = 0, y_m = 0;
  std::string cls;                                    // empty when the file has no class column
  std::string truth_cls;                              // empty when the file has no truth_class column
  bool ignore = false;                                // truth only: don't care
  std::map<std::string, double> class_probabilities;  // p_<class> columns; empty when none
};

// Throws InputError "file:line: column: reason" on a missing required column, a
// short row, a value that is not a finite number.
std::vector<ObjectSample> ReadObjectTracks(const std::string& path);
std::vector<ObjectSample> ParseObjectTracks(const std::string& text, const std::string& source_name);
// Written atomically; truth_class, ignore and p_<class> columns (every class any
// sample has, in name order, four decimals) only when a sample has one.
void WriteObjectTracks(const std::vector<ObjectSample>& samples, const std::string& path);

}  // namespace specht::io
