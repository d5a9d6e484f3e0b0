#include "specht/tune/search.h"

#include <algorithm>
#include <numeric>
#include <random>

#include "specht/core/error.h"

namespace specht::tune {
namespace {

class RandomSearch : public Search {
 public:
  RandomSearch(size_t dims, int batch, uint64_t seed) : dims_(dims), batch_(batch), rng_(seed) {}
  std::vector<Genes> Ask() override {
    std::uniform_real_distribution<double> u(0, 1);
    std::vector<Genes> out(batch_, Genes(dims_));
    for (auto& g : out)
      for (double& x : g) x = u(rng_);
    return out;
  }
  void Tell(const std::vector<double>&) override {}

 private:
  size_t dims_;
  int batch_;
  std::mt19937_64 rng_;
};

class GridSearch : public Search {
 public:
  GridSearch(const std::vector<int>& choice_counts, int levels, int batch) : batch_(batch) {
    for (int c : choice_counts) counts_.push_back(c > 0 ? c : levels);
    index_.assign(counts_.size(), 0);
  }
  std::vector<Genes> Ask() override {
    std::vector<Genes> out;
    while (static_cast<int>(out.size()) < batch_ && !done_) {
      Genes g(counts_.size());
      for (size_t i = 0; i < counts_.size(); ++i) g[i] = (index_[i] + 0.5) / counts_[i];
      out.push_back(std::move(g));
      // Odometer increment, last dimension fastest.
      size_t i = counts_.size();
      while (i > 0 && ++index_[i - 1] == counts_[i - 1]) index_[--i] = 0;
      done_ = i == 0;
    }
    return out;
  }
  void Tell(const std::vector<double>&) override {}

 private:
  std::vector<int> counts_;
  std::vector<int> index_;
  int batch_;
  bool done_ = false;
};

class GeneticSearch : public Search {
 public:
  GeneticSearch(size_t dims, const SearchOptions& o) : dims_(dims), o_(o), rng_(static_cast<uint64_t>(o.seed)) {}

  std::vector<Genes> Ask() override {
    std::uniform_real_distribution<double> u(0, 1);
    asked_.clear();
    if (population_.empty()) {  // first generation: uniform
      asked_.assign(o_.population, Genes(dims_));
      for (auto& g : asked_)
        for (double& x : g) x = u(rng_);
      return asked_;
    }
    std::uniform_int_distribution<size_t> pick(0, population_.size() - 1);
    for (int c = 0; c < o_.population; ++c) {
      const Genes& a = population_[pick(rng_)].genes;
      const Genes& b = population_[pick(rng_)].genes;
      Genes child(dims_);
      for (size_t i = 0; i < dims_; ++i) child[i] = u(rng_) < 0.5 ? a[i] : b[i];  // multi-point crossover
      if (u(rng_) < o_.mutation_individual)
        for (double& x : child)
          if (u(rng_) < o_.mutation_gene) x = u(rng_);
      asked_.push_back(std::move(child));
    }
    return asked_;
  }

  void Tell(const std::vector<double>& values) override {
    if (values.size() != asked_.size()) throw RuntimeError("tune: told a different number of values than asked");
    for (size_t i = 0; i < values.size(); ++i) population_.push_back({asked_[i], values[i]});
    // (μ+λ): the best `population` survive; stable, so ties keep the older first.
    std::stable_sort(population_.begin(), population_.end(),
                     [](const Member& x, const Member& y) { return x.value < y.value; });
    if (static_cast<int>(population_.size()) > o_.population) population_.resize(o_.population);
  }

 private:
  struct Member {
    Genes genes;
    double value;
  };
  size_t dims_;
  SearchOptions o_;
  std::mt19937_64 rng_;
  std::vector<Member> population_;
  std::vector<Genes> asked_;
};

}  // namespace

std::unique_ptr<Search> MakeSearch(const SearchOptions& o, const std::vector<int>& choice_counts) {
  const size_t dims = choice_counts.size();
  if (dims == 0) throw InputError("tune: nothing to search (no parameters)");
  if (o.method == "random") return std::make_unique<RandomSearch>(dims, o.population, static_cast<uint64_t>(o.seed));
  if (o.method == "grid") return std::make_unique<GridSearch>(choice_counts, o.levels, o.population);
  if (o.method == "ga") return std::make_unique<GeneticSearch>(dims, o);
  throw InputError("tune: unknown search method '" + o.method + "' (ga, random, grid)");
}

}  // namespace specht::tune
