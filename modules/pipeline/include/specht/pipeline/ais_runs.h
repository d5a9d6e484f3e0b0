// specht/pipeline/ais_runs.h: vessel classification from AIS, as in the vessel
// paper — what `specht ais decode|prepare|predict` run (training and cross-validation
// are classifier_runs.h, shared with the robot classes).
#pragma once

#include <string>
#include <vector>

#include "specht/core/params.h"

namespace specht::pipeline {

// NMEA 0183 (section "ais_decoder") → messages.jsonl (gpsd-style objects) and
// positions.csv (mmsi,time,lon,lat,sog,cog,heading,ship_type; grouped by MMSI, only
// reports with a receive time), counts and rejections by reason in the report.
int DecodeAis(const params::Params& params, const std::vector<std::string>& nmea, const std::string& out_dir);

// Tabular AIS (ais/positions.h layouts) → windows (sections "ais", "ais_classify"),
// the class counts after each step (counts.png, the paper's Figure 3) and the dataset
// files as classify writes them. `data_dir` holds the coastline and harbours.
int PrepareAisWindows(const params::Params& params, const std::vector<std::string>& tracks, const std::string& data_dir,
                      const std::string& out_dir, bool quiet);

// Classes per vessel (objects.csv: the mean of its windows' probabilities) and per
// window (windows.csv: its own class and the class from the vessel's windows so far)
// with the model's own preprocessing; the network combined with its forest unless
// `network_only`.
int PredictVesselClasses(const params::Params& params, const std::string& model_dir,
                         const std::vector<std::string>& tracks, bool network_only, const std::string& data_dir,
                         const std::string& out_dir);

}  // namespace specht::pipeline
