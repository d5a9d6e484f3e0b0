// specht/eval/relation_error.h: the relation error of Kümmerle et al. (2009), the
// metric Cartographer and most 2D SLAM papers report on the Radish logs.
//
// A relation (i, j) is a pair of scans. Its error compares the estimated relative
// motion with the reference one:
//   δ_ij = x_i ⊖ x_j (pose of j seen from i),  e_ij = δ̂_ij ⊖ δ*_ij
//   translational error |t(e_ij)| in metres, rotational |θ(e_ij)| in degrees.
// Relations are every pair of consecutive scans, plus every pair whose reference
// poses lie within `loop_max_distance_m` but more than `loop_min_separation` scans
// apart (the loops, where global consistency shows).
#pragma once

#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

#include "specht/core/trajectory.h"
#include "specht/io/trajectory_io.h"

namespace specht::eval {

struct RelationStats {
  size_t count = 0;
  double mean_m = 0, std_m = 0, max_m = 0;
  double mean_deg = 0, std_deg = 0, max_deg = 0;
};

// One relation: scans i < j (indices into the paired poses) and its errors.
struct Relation {
  size_t i = 0, j = 0;
  Stamp stamp_i, stamp_j;  // the estimate's stamps
  bool loop = false;       // a loop relation (else consecutive)
  double m = 0, deg = 0;
};

struct RelationError {
  RelationStats consecutive, loop, all;
  size_t paired_poses = 0;
  // The relations with the largest translational error, largest first: where a
  // map broke (ties in index order).
  std::vector<Relation> worst;
};

struct RelationOptions {
  double loop_max_distance_m = 3.0;
  int loop_min_separation = 100;
  double max_dt_s = 0.001;  // estimate and reference poses pair by stamp within this
  size_t worst_count = 10;  // relations kept in RelationError::worst
};

// Throws InputError when fewer than 2 poses pair up.
RelationError ComputeRelationError(const Trajectory& estimate, const Trajectory& reference,
                                   const RelationOptions& options = {});

// The same metric on published relations (the Freiburg benchmark's .relations
// files): each relation names its two scans by stamp, and its reference motion is
// the hand-verified one. Kümmerle et al. report the errors absolute and squared:
//   ε = δ̂ ⊖ δ*,  |t(ε)| m and |θ(ε)| deg,  and t(ε)² m², θ(ε)² deg².
struct PublishedRelationError {
  RelationStats absolute;       // m, deg
  RelationStats squared;        // m², deg²
  size_t relations = 0;         // in the file, all matched
  std::vector<Relation> worst;  // largest translational error first (i, j: estimate indices)
};

struct PublishedRelationOptions {
  double max_dt_s = 1e-4;  // a relation's stamps match the estimate's within this (the benchmark's 0.1 ms)
  size_t worst_count = 10;
};

// Throws InputError naming the file, the first relation whose stamp is not in the
// estimate (its line) and how many are not: a score on part of the relations is not
// the benchmark's.
PublishedRelationError ComputePublishedRelationError(const Trajectory& estimate, const io::RelationsFile& relations,
                                                     const PublishedRelationOptions& options = {});

// The relations as pose pairs (i, j, i, j, …) of `estimate`, for a picture with
// io::PathOverlay::segments.
Trajectory RelationSegments(const Trajectory& estimate, const std::vector<Relation>& relations);

// For reports: {count, mean_m, std_m, max_m, mean_deg, std_deg, max_deg}, and
// {consecutive, loop, all, paired_poses, worst: [{i, j, t_i, t_j, kind, m, deg}]}.
nlohmann::json ToJson(const RelationStats& stats);
nlohmann::json ToJson(const RelationError& error);
// {relations, absolute, squared, worst: [...]}.
nlohmann::json ToJson(const PublishedRelationError& error);

}  // namespace specht::eval
