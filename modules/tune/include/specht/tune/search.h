// specht/tune/search.h: searches over the unit cube (space.h), as ask/tell
// generations so an evaluation log can replay them (runner.h): each search draws
// only from its own seeded generator and from the values it was told, so the same
// seed and the same values give the same candidates — which is what makes a
// resumed search identical to an uninterrupted one.
//
// All searches minimise; failed evaluations are told as +∞.
//
//   random  `batch` uniform points per generation.
//   grid    `levels` evenly spaced values per real/integer dimension (cell centres
//           of a levels-grid: (i + ½)/levels), every choice of a choice dimension;
//           the full product in lexicographic order, `batch` at a time.
//   ga      the walking paper's plain genetic algorithm
//           (../shared/papers/learning-to-walk-genetic-algorithm.md §3.4): a
//           population of `population` (first generation uniform), each child from
//           two parents drawn at random ("Monte-Carlo selection"), multi-point
//           crossover (each gene from either parent), random mutation (10 % of the
//           children, each of their genes redrawn uniformly with 20 %); survivors
//           are the best `population` of parents and children ((μ+λ)), which is
//           where the selection pressure comes from when parents are drawn at random.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "specht/core/params.h"

namespace specht::tune {

using Genes = std::vector<double>;

// Section "tune" of a tune file's `search:` (also a params section so the GA's
// settings are declared and documented once).
struct SearchOptions {
  std::string method = "ga";
  int budget = 200;     // evaluations (candidates, not counting repeats)
  int population = 20;  // ga: population; random: batch per generation
  int levels = 5;       // grid
  double mutation_individual = 0.10;
  double mutation_gene = 0.20;
  int seed = 1;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Choice("method", method, {"ga", "random", "grid"}, "search method (see tune/search.h)");
    v.Param("budget", budget, "candidates evaluated at most", Range::Of(1, 1000000).Fixed());
    v.Param("population", population, "ga population; random/grid batch per generation", Range::Of(2, 100000).Fixed());
    v.Param("levels", levels, "grid: values per real or integer dimension", Range::Of(2, 1000).Fixed());
    v.Param("mutation_individual", mutation_individual, "ga: share of children mutated (paper: 0.10)",
            Range::Of(0.0, 1.0).Fixed());
    v.Param("mutation_gene", mutation_gene, "ga: chance per gene of a mutated child (paper: 0.20)",
            Range::Of(0.0, 1.0).Fixed());
    v.Param("seed", seed, "random seed of the search", Range::Of(0, 1 << 30).Fixed());
  }
};

class Search {
 public:
  virtual ~Search() = default;
  // The next generation's candidates (empty when the search has nothing left).
  virtual std::vector<Genes> Ask() = 0;
  // The values of the last Ask's candidates, in the same order.
  virtual void Tell(const std::vector<double>& values) = 0;
};

// `choice_counts[i]` is the number of choices of dimension i, 0 for numeric ones
// (the grid enumerates choices exactly).
std::unique_ptr<Search> MakeSearch(const SearchOptions& options, const std::vector<int>& choice_counts);

}  // namespace specht::tune
