// specht/pipeline/track_classification.h: the trajectory classifier on object tracks
// (io/object_tracks.h: id,t_s,x_m,y_m[,class][,truth_class]) — what `specht classify
// prepare|eval|predict` run. A track's label is its truth_class, else its class. Map
// features come from the scenario whose name is the second part of the track id
// ("s3/urban-crossing/t7": its true static grid, and its parking bays as points of
// interest).
#pragma once

#include <string>
#include <vector>

#include "specht/core/params.h"

namespace specht::pipeline {

// Cuts the labelled tracks into windows (section "classify") with their map features
// and writes the dataset (classify/dataset_io.h) into `out_dir`, printing the class
// counts after each step. Inputs are read before the directory is created.
int PrepareTrackWindows(const params::Params& params, const std::vector<std::string>& tracks,
                        const std::vector<std::string>& scenarios, const std::string& out_dir);

// Scores a trained model (model.pt and forest.yml in `model_dir`) on a prepared
// dataset: macro, weighted and per-class F1 of the network, the forest and the two
// combined (mean probabilities), confusion matrices as PNG, the inference rate.
int EvaluateClassifier(const std::string& model_dir, const std::string& dataset, const std::string& out_dir);

// Classifies tracks with the model's own preprocessing (the network combined with its
// forest unless `network_only`): windows.csv (class and probabilities per window) and
// objects.csv (per track, the mean of its windows' probabilities); tracks that carry a
// label are scored too.
int PredictTrackClasses(const std::string& model_dir, const std::vector<std::string>& tracks,
                        const std::vector<std::string>& scenarios, bool network_only, const std::string& out_dir);

}  // namespace specht::pipeline
