// specht/classify/model.h: the trajectory classifier, a 1D residual network
// (Fawaz et al. 2019, as the vessel paper uses it) on libtorch (CPU).
//
// A residual block: three 1D convolutions (kernels 8, 5, 3, "same" padding), each
// followed by batch norm and ReLU (the last ReLU after the sum), with a shortcut
// (1×1 convolution + batch norm when the width changes):
//   y = ReLU(BN(conv3(ReLU(BN(conv2(ReLU(BN(conv1(x))))))) + shortcut(x))
// Variants (section "classify_model", variant):
//   tiny     2 blocks of 32 filters             (~28 k parameters; the default:
//            on the robot classes it beat shallow on 3 of 3 seeds, 0.970 vs
//            0.953 macro F1, and runs 12× faster; see README)
//   shallow  3 blocks of 64, 128, 128 filters   (the paper's best on AIS; ~0.5 M)
//   deep     9 blocks: 3 × 64, 6 × 128
//   split    the paper's split ResNet: one path of 2 blocks (32, 48 filters) per
//            input feature, the paths' pooled outputs concatenated (~0.38 M for 9
//            features); features that are "not necessarily logically linked" get
//            their own filters
//   mlp      the paper's baseline: two hidden layers of 64 on the flattened window
// then global average pooling over time and a linear layer to the classes.
//
// Optional input encoding (input_bins = B > 0; Gorishniy et al. 2022, "On
// embeddings for numerical features"): each input row r is replaced by B rows, one
// per bin [l_rb, l_rb + w_rb) between the row's quantiles b/B and (b+1)/B over the
// training windows (fitted once, at the start of training, and saved with the
// weights):
//   e_rb(v) = clamp((v − l_rb) / w_rb, 0, 1)
// so a convolution can respond to a range of a value (a flag's codes, a region's
// band) as a tree's split does, instead of only to its linear trend.
//
// Optional distillation (distillation = α > 0; Hinton et al. 2015, "Distilling the
// knowledge in a neural network"): each training window carries a teacher's class
// probabilities q (Dataset::teacher) and the loss on a batch of n windows is
//   L = (1 − α) · CE_w(logits, y) − α · (1/n) Σ_i Σ_c q_ic · log softmax(logits_i)_c
// where CE_w is the (class-weighted) cross-entropy with the labels. The teacher's
// term is a plain mean (weighting it by the classes' weights too was worse; see
// docs/ais-experiments.md). The teacher is
// the forest out of fold (OutOfFoldForest, crossval.h): the network learns from its
// answers on vessels it has not seen, which generalise across vessels better than
// the labels of the 58–81 vessels of a small AIS class alone. Validation (early
// stopping) still scores the labels.
//
// Training: Adam; the learning rate halves after plateau_patience epochs without a
// lower validation loss; training stops after early_stop_patience such epochs and
// the best epoch's weights are kept. Optional Gaussian input noise and inverse-
// frequency class weights. Seeded: the same data, options and seed give the same
// model on the same machine and thread count.
#pragma once

#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "specht/core/params.h"

namespace specht::classify {

// The network variants above, in the order the help lists them.
inline const std::vector<std::string>& ModelVariants() {
  static const std::vector<std::string> variants = {"tiny", "shallow", "deep", "split", "mlp"};
  return variants;
}

// Section "classify_model".
struct ModelOptions {
  std::string variant = "tiny";
  bool batch_norm = true;
  int epochs = 100;
  int batch_size = 64;
  double learning_rate = 1e-3;
  int plateau_patience = 10;
  int early_stop_patience = 15;
  double input_noise = 0.01;
  bool class_weights = true;
  int seed = 1;
  int threads = 2;
  double validation_fraction = 0.2;
  int input_bins = 0;
  double distillation = 0.0;

  template <class V>
  void Visit(V& v) {
    using params::Range;
    v.Choice("variant", variant, ModelVariants(), "network (see classify/model.h)");
    v.Param("batch_norm", batch_norm, "batch normalisation after each convolution");
    v.Param("epochs", epochs, "maximum training epochs", Range::Of(1, 10000));
    v.Param("batch_size", batch_size, "windows per optimiser step", Range::Of(1, 4096).Log());
    v.Param("learning_rate", learning_rate, "Adam's initial learning rate", Range::Of(1e-6, 1.0).Log());
    v.Param("plateau_patience", plateau_patience, "halve the rate after this many epochs without improvement",
            Range::Of(1, 1000));
    v.Param("early_stop_patience", early_stop_patience, "stop after this many epochs without improvement",
            Range::Of(1, 1000));
    v.Param("input_noise", input_noise, "σ of Gaussian noise added to training inputs (paper: 0.01)",
            Range::Of(0.0, 1.0));
    v.Param("class_weights", class_weights, "weight the loss by inverse class frequency");
    v.Param("seed", seed, "random seed (weights, shuffling, noise, validation split)", Range::Of(0, 1 << 30).Fixed());
    v.Param("threads", threads, "CPU threads for libtorch", Range::Of(1, 256).Fixed());
    v.Param("validation_fraction", validation_fraction, "objects held out for validation (by object id)",
            Range::Of(0.0, 0.9));
    v.Param("input_bins", input_bins,
            "piecewise-linear encoding of each input row over this many quantile bins of the training data "
            "(Gorishniy et al. 2022); 0 = the rows as they are",
            Range::Of(0, 64));
    v.Param("distillation", distillation,
            "weight of a teacher's class probabilities in the training loss (Hinton et al. 2015; the teacher is "
            "the random forest, asked about each training window out of fold); 0 = the labels only",
            Range::Of(0.0, 1.0));
  }
};

// Windows as a tensor: x is size × features × length, row-major.
struct Dataset {
  int features = 0, length = 0;
  std::vector<float> x;
  std::vector<int> y;                   // class index (−1 unknown)
  std::vector<std::string> object_ids;  // one per window
  std::vector<float> teacher;           // size × classes: a teacher's probabilities (distillation), or empty
  size_t size() const { return y.size(); }
  // The windows whose index is in `rows`.
  Dataset Subset(const std::vector<size_t>& rows) const;
  // `other`'s windows after these (the same features and length, else InputError).
  // The teacher's probabilities are kept only when both have them.
  void Append(const Dataset& other);
};

struct EpochReport {
  int epoch = 0;
  double train_loss = 0, validation_loss = 0, validation_macro_f1 = 0, learning_rate = 0;
  double seconds = 0;
};

class Classifier {
 public:
  Classifier(const ModelOptions& options, int features, int length, std::vector<std::string> classes);
  ~Classifier();
  Classifier(Classifier&&) noexcept;
  Classifier& operator=(Classifier&&) noexcept;

  // Trains on `train`, selecting the epoch by `validation` (which may be empty:
  // then the training loss decides). `on_epoch` is called after every epoch
  // (also for the epochs restored from a checkpoint).
  //
  // With a `checkpoint` path the whole training state (weights, Adam's moments,
  // the best epoch's weights, learning rate, patience counters, the epoch reports)
  // is written there atomically after every epoch, and if the file exists when
  // Train starts, training continues from it. Each epoch's randomness (shuffle,
  // noise) is seeded by (seed, epoch), so an interrupted and resumed training gives
  // the same model as an uninterrupted one. A checkpoint of another run (other
  // data sizes, architecture or options) is refused with an InputError.
  std::vector<EpochReport> Train(const Dataset& train, const Dataset& validation,
                                 const std::function<void(const EpochReport&)>& on_epoch = nullptr,
                                 const std::string& checkpoint = "");
  // Continues training from the current weights on windows of another length (or
  // the same), at `learning_rate`, as Train does otherwise; the model then takes
  // windows of that length. Transfer: a model of every vessel's 60-point windows
  // tuned on the 360-point windows of the few that have them. The input encoding's
  // bins stay as first fitted; the options' learning rate is left as it was. The
  // convolutional variants only (they pool over time): InputError for mlp.
  // `on_epoch` as for Train.
  std::vector<EpochReport> FineTune(const Dataset& train, const Dataset& validation, double learning_rate,
                                    const std::function<void(const EpochReport&)>& on_epoch = nullptr);
  // Class probabilities, size × classes, row-major (batched, no gradients).
  // batch_size 0 picks one whose activations stay near 4 MiB: cache-sized batches
  // ran 2× faster than 256 on 360-point windows (bench/classify_bench).
  std::vector<float> Predict(const Dataset& data, int batch_size = 0) const;
  std::vector<int> PredictClasses(const Dataset& data) const;

  // <path>.pt (weights, libtorch archive) and <path>.json (architecture, classes,
  // `extra` such as the preprocessing). Load checks that both agree and throws
  // InputError naming the file otherwise.
  void Save(const std::string& path, const nlohmann::json& extra = {}) const;
  static Classifier Load(const std::string& path, nlohmann::json* extra = nullptr);

  const std::vector<std::string>& classes() const { return classes_; }
  int features() const { return features_; }
  int length() const { return length_; }
  long parameter_count() const;
  // Multiply-adds of one forward pass of one window (convolutions and linear layers).
  double multiply_adds_per_window() const;
  const ModelOptions& options() const { return options_; }
  // libtorch threads for Predict (the saved model's options say 2; a caller whose
  // own threads keep the cores busy may want 1).
  void set_threads(int threads) { options_.threads = threads; }

 private:
  struct Net;
  // Train and FineTune: trains from the current weights at `learning_rate`; with
  // `fit_bins` the input encoding's bins are fitted to `train` first (a new model),
  // else kept (a model tuned on other windows keeps its inputs' meaning).
  std::vector<EpochReport> Fit(const Dataset& train, const Dataset& validation,
                               const std::function<void(const EpochReport&)>& on_epoch, const std::string& checkpoint,
                               double learning_rate, bool fit_bins);
  ModelOptions options_;
  int features_, length_;
  std::vector<std::string> classes_;
  std::shared_ptr<Net> net_;
};

// Splits window indices by object identity: an object's windows all go to one side.
// Deterministic: by a hash of the id and the seed.
void SplitByObject(const std::vector<std::string>& object_ids, double held_out_fraction, int seed,
                   std::vector<size_t>& kept, std::vector<size_t>& held_out);

}  // namespace specht::classify
