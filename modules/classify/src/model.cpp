#include "specht/classify/model.h"

#include <torch/torch.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>

#include "internal/object_hash.h"
#include "specht/classify/metrics.h"
#include "specht/core/error.h"
#include "specht/core/interrupt.h"
#include "specht/io/atomic_file.h"

namespace specht::classify {
namespace nn = torch::nn;

namespace {

struct ResBlockImpl : nn::Module {
  nn::Conv1d c1{nullptr}, c2{nullptr}, c3{nullptr}, shortcut{nullptr};
  nn::BatchNorm1d b1{nullptr}, b2{nullptr}, b3{nullptr}, bs{nullptr};
  bool bn;
  ResBlockImpl(int in, int out, bool batch_norm) : bn(batch_norm) {
    auto conv = [&](const char* name, int i, int k) {
      return register_module(name, nn::Conv1d(nn::Conv1dOptions(i, out, k).padding(torch::kSame)));
    };
    c1 = conv("c1", in, 8), c2 = conv("c2", out, 5), c3 = conv("c3", out, 3);
    if (in != out) shortcut = register_module("shortcut", nn::Conv1d(nn::Conv1dOptions(in, out, 1)));
    if (bn) {
      b1 = register_module("b1", nn::BatchNorm1d(out));
      b2 = register_module("b2", nn::BatchNorm1d(out));
      b3 = register_module("b3", nn::BatchNorm1d(out));
      bs = register_module("bs", nn::BatchNorm1d(out));
    }
  }
  torch::Tensor Norm(nn::BatchNorm1d& b, const torch::Tensor& x) { return bn ? b(x) : x; }
  torch::Tensor forward(const torch::Tensor& x) {
    auto y = torch::relu(Norm(b1, c1(x)));
    y = torch::relu(Norm(b2, c2(y)));
    y = Norm(b3, c3(y));
    const auto s = shortcut ? shortcut(x) : x;
    return torch::relu(y + Norm(bs, s));
  }
};
TORCH_MODULE(ResBlock);

// Setting the thread count rebuilds libtorch's pool, which costs more than classifying
// one window, so it is set only when it changes.
void UseThreads(int threads) {
  if (torch::get_num_threads() != threads) torch::set_num_threads(threads);
}

// Residual block widths of one path.
std::vector<int> Filters(const std::string& variant) {
  if (variant == "tiny") return {32, 32};
  if (variant == "shallow") return {64, 128, 128};
  if (variant == "deep") return {64, 64, 64, 128, 128, 128, 128, 128, 128};
  if (variant == "split") return {32, 48};  // per feature
  return {};
}

}  // namespace

// The convolutional variants are one or more paths of residual blocks, each over a
// slice of the input channels (all of them, or one input row each for "split": the
// row's bins when encoded), concatenated and pooled over time.
struct Classifier::Net : nn::Module {
  struct Path {
    int first_channel = 0, channels = 0;
    std::vector<ResBlock> blocks;
  };
  std::vector<Path> paths;
  nn::Linear head{nullptr}, h1{nullptr}, h2{nullptr};
  int widest = 0;  // channels of the widest activation
  int rows = 0, bins = 0;
  torch::Tensor bin_lower, bin_width;  // rows × bins: the piecewise-linear encoding's bins
  Net(const ModelOptions& o, int input_rows, int length, int classes) : rows(input_rows), bins(o.input_bins) {
    if (bins > 0) {
      bin_lower = register_buffer("bin_lower", torch::zeros({rows, bins}));
      bin_width = register_buffer("bin_width", torch::ones({rows, bins}));
    }
    const int per_row = std::max(bins, 1);  // channels of one input row after encoding
    const int features = rows * per_row;
    const bool split = o.variant == "split";
    const std::vector<int> filters = Filters(o.variant);
    int pooled = 0;
    for (int f = 0; f < (split ? rows : 1) && !filters.empty(); ++f) {
      Path path{split ? f * per_row : 0, split ? per_row : features, {}};
      int width = path.channels;
      for (int out : filters) {
        const std::string name =
            (split ? "path" + std::to_string(f) + "_" : "") + "block" + std::to_string(path.blocks.size());
        path.blocks.push_back(register_module(name, ResBlock(width, out, o.batch_norm)));
        width = out;
      }
      pooled += width;
      paths.push_back(std::move(path));
    }
    widest = features;
    for (int out : filters) widest = std::max(widest, out);
    if (paths.empty()) {  // mlp
      h1 = register_module("h1", nn::Linear(features * length, 64));
      h2 = register_module("h2", nn::Linear(64, 64));
      pooled = 64;
    }
    head = register_module("head", nn::Linear(pooled, classes));
  }
  // Piecewise-linear encoding: row value v → for each bin [l, l + w):
  // clamp((v − l) / w, 0, 1), i.e. 0 below the bin, 1 above, linear inside.
  torch::Tensor Encode(const torch::Tensor& x) const {
    if (bins == 0) return x;
    const auto e =
        ((x.unsqueeze(2) - bin_lower.view({1, rows, bins, 1})) / bin_width.view({1, rows, bins, 1})).clamp(0, 1);
    return e.reshape({x.size(0), rows * bins, x.size(2)});
  }
  // Bins at the quantiles 0, 1/B, … of each row's values in `x` (windows × rows × length).
  void FitBins(const std::vector<float>& x, size_t windows, int length) {
    if (bins == 0) return;
    torch::NoGradGuard no_grad;
    const size_t step = std::max<size_t>(1, windows / 4000);
    for (int r = 0; r < rows; ++r) {
      std::vector<float> v;
      for (size_t n = 0; n < windows; n += step)
        v.insert(v.end(), x.begin() + (n * rows + r) * length, x.begin() + (n * rows + r + 1) * length);
      std::sort(v.begin(), v.end());
      for (int b = 0; b < bins; ++b) {
        const float lo = v[static_cast<size_t>(b * (v.size() - 1.0) / bins)];
        const float hi = v[static_cast<size_t>((b + 1) * (v.size() - 1.0) / bins)];
        bin_lower[r][b] = lo;
        bin_width[r][b] = std::max(hi - lo, 1e-6f);
      }
    }
  }
  torch::Tensor forward(torch::Tensor x) {
    x = Encode(x);
    if (paths.empty()) {
      x = torch::relu(h1(x.flatten(1)));
      return head(torch::relu(h2(x)));
    }
    std::vector<torch::Tensor> outputs;
    for (auto& path : paths) {
      torch::Tensor y = x.narrow(1, path.first_channel, path.channels);
      for (auto& b : path.blocks) y = b(y);
      outputs.push_back(y.mean(2));  // global average pooling over time
    }
    return head(outputs.size() == 1 ? outputs[0] : torch::cat(outputs, 1));
  }
};

Dataset Dataset::Subset(const std::vector<size_t>& rows) const {
  Dataset d;
  d.features = features, d.length = length;
  const size_t stride = static_cast<size_t>(features) * length;
  const size_t k = size() ? teacher.size() / size() : 0;
  d.x.reserve(rows.size() * stride);
  for (size_t r : rows) {
    d.x.insert(d.x.end(), x.begin() + r * stride, x.begin() + (r + 1) * stride);
    d.y.push_back(y[r]);
    d.object_ids.push_back(object_ids[r]);
    d.teacher.insert(d.teacher.end(), teacher.begin() + r * k, teacher.begin() + (r + 1) * k);
  }
  return d;
}

void Dataset::Append(const Dataset& other) {
  if (other.features != features || other.length != length)
    throw InputError("Dataset::Append: windows of " + std::to_string(other.features) + " × " +
                     std::to_string(other.length) + " after windows of " + std::to_string(features) + " × " +
                     std::to_string(length));
  const bool taught = (size() == 0 || !teacher.empty()) && (other.size() == 0 || !other.teacher.empty());
  x.insert(x.end(), other.x.begin(), other.x.end());
  y.insert(y.end(), other.y.begin(), other.y.end());
  object_ids.insert(object_ids.end(), other.object_ids.begin(), other.object_ids.end());
  if (taught)
    teacher.insert(teacher.end(), other.teacher.begin(), other.teacher.end());
  else
    teacher.clear();
}

void SplitByObject(const std::vector<std::string>& ids, double fraction, int seed, std::vector<size_t>& kept,
                   std::vector<size_t>& held_out) {
  kept.clear(), held_out.clear();
  for (size_t i = 0; i < ids.size(); ++i) {
    const uint64_t h = internal::ObjectHash(ids[i], seed);
    ((h % 1000003) / 1000003.0 < fraction ? held_out : kept).push_back(i);
  }
}

Classifier::Classifier(const ModelOptions& options, int features, int length, std::vector<std::string> classes)
    : options_(options), features_(features), length_(length), classes_(std::move(classes)) {
  if (features < 1 || length < 1 || classes_.size() < 2)
    throw InputError("classify: a model needs features, a window length and at least two classes");
  UseThreads(options.threads);
  torch::manual_seed(options.seed);
  net_ = std::make_shared<Net>(options, features, length, static_cast<int>(classes_.size()));
}
Classifier::~Classifier() = default;
Classifier::Classifier(Classifier&&) noexcept = default;
Classifier& Classifier::operator=(Classifier&&) noexcept = default;

long Classifier::parameter_count() const {
  long n = 0;
  for (const auto& p : net_->parameters()) n += p.numel();
  return n;
}

// A stride-1 "same" convolution costs its weight count per output time step; a
// linear layer its weight count once (batch norm and ReLU are not counted).
double Classifier::multiply_adds_per_window() const {
  double n = 0;
  for (const auto& m : net_->modules(/*include_self=*/false)) {
    if (const auto* conv = m->as<nn::Conv1d>()) n += static_cast<double>(conv->weight.numel()) * length_;
    if (const auto* linear = m->as<nn::Linear>()) n += static_cast<double>(linear->weight.numel());
  }
  return n;
}

namespace {

torch::Tensor Inputs(const Dataset& d, const std::vector<int64_t>& rows) {
  const int64_t stride = static_cast<int64_t>(d.features) * d.length;
  auto t = torch::empty({static_cast<int64_t>(rows.size()), d.features, d.length});
  float* out = t.data_ptr<float>();
  for (size_t i = 0; i < rows.size(); ++i) std::copy_n(d.x.data() + rows[i] * stride, stride, out + i * stride);
  return t;
}

void CheckShape(const Dataset& d, int features, int length, const char* what) {
  if (d.features != features || d.length != length)
    throw InputError(std::string("classify: ") + what + " has windows of " + std::to_string(d.features) + " × " +
                     std::to_string(d.length) + ", the model takes " + std::to_string(features) + " × " +
                     std::to_string(length));
  if (d.x.size() != d.size() * static_cast<size_t>(features) * length)
    throw InputError(std::string("classify: ") + what + ": data and labels disagree in size");
}

}  // namespace

namespace {

// Everything Train needs to continue after an epoch.
struct TrainingState {
  int epoch = 0;  // last finished epoch
  double learning_rate = 0, best = std::numeric_limits<double>::infinity();
  int since_best = 0, since_lr = 0;
  std::string best_weights;  // torch::save of the best epoch's network
  std::vector<EpochReport> reports;
};

torch::Tensor BytesTensor(const std::string& s) {
  return torch::from_blob(const_cast<char*>(s.data()), {static_cast<int64_t>(s.size())}, torch::kUInt8).clone();
}
std::string TensorBytes(const torch::Tensor& t) {
  return std::string(reinterpret_cast<const char*>(t.data_ptr<uint8_t>()), static_cast<size_t>(t.numel()));
}

nlohmann::json ReportsJson(const std::vector<EpochReport>& reports) {
  nlohmann::json j = nlohmann::json::array();
  for (const auto& r : reports)
    j.push_back({r.epoch, r.train_loss, r.validation_loss, r.validation_macro_f1, r.learning_rate, r.seconds});
  return j;
}
std::vector<EpochReport> ReportsFromJson(const nlohmann::json& j) {
  std::vector<EpochReport> reports;
  for (const auto& e : j)
    reports.push_back({e[0].get<int>(), e[1].get<double>(), e[2].get<double>(), e[3].get<double>(), e[4].get<double>(),
                       e[5].get<double>()});
  return reports;
}

void WriteCheckpoint(const std::string& path, const nlohmann::json& run, const TrainingState& s, nn::Module& net,
                     torch::optim::Optimizer& optimiser) {
  torch::serialize::OutputArchive archive, net_archive, optimiser_archive;
  net.save(net_archive);
  optimiser.save(optimiser_archive);
  const nlohmann::json meta = {{"format", "specht-classifier-checkpoint-1"},
                               {"run", run},
                               {"epoch", s.epoch},
                               {"learning_rate", s.learning_rate},
                               {"best", s.best},
                               {"since_best", s.since_best},
                               {"since_lr", s.since_lr},
                               {"reports", ReportsJson(s.reports)}};
  archive.write("meta", BytesTensor(meta.dump()));
  archive.write("best_weights", BytesTensor(s.best_weights));
  archive.write("net", net_archive);
  archive.write("optimiser", optimiser_archive);
  std::ostringstream bytes;
  archive.save_to(bytes);
  io::WriteTextAtomically(path, bytes.str());
}

// Restores `s`, the network and the optimiser; false when there is no checkpoint.
bool ReadCheckpoint(const std::string& path, const nlohmann::json& run, TrainingState& s, nn::Module& net,
                    torch::optim::Optimizer& optimiser) {
  if (!std::ifstream(path)) return false;
  try {
    torch::serialize::InputArchive archive, net_archive, optimiser_archive;
    archive.load_from(path);
    torch::Tensor meta_bytes, best;
    archive.read("meta", meta_bytes);
    const auto meta = nlohmann::json::parse(TensorBytes(meta_bytes));
    if (meta.value("format", "") != "specht-classifier-checkpoint-1")
      throw InputError(path + ": not a specht classifier checkpoint");
    if (meta.at("run") != run)
      throw InputError(path + ": checkpoint of another training run (was " + meta.at("run").dump() + ", now " +
                       run.dump() + "); delete it to start over");
    archive.read("best_weights", best);
    archive.read("net", net_archive);
    archive.read("optimiser", optimiser_archive);
    net.load(net_archive);
    optimiser.load(optimiser_archive);
    s.epoch = meta.at("epoch").get<int>();
    s.learning_rate = meta.at("learning_rate").get<double>();
    s.best = meta.at("best").is_null() ? std::numeric_limits<double>::infinity() : meta.at("best").get<double>();
    s.since_best = meta.at("since_best").get<int>();
    s.since_lr = meta.at("since_lr").get<int>();
    s.best_weights = TensorBytes(best);
    s.reports = ReportsFromJson(meta.at("reports"));
    return true;
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(path + ": unreadable checkpoint (" + std::string(e.what()).substr(0, 200) + ")");
  }
}

}  // namespace

std::vector<EpochReport> Classifier::Train(const Dataset& train, const Dataset& validation,
                                           const std::function<void(const EpochReport&)>& on_epoch,
                                           const std::string& checkpoint) {
  return Fit(train, validation, on_epoch, checkpoint, options_.learning_rate, true);
}

std::vector<EpochReport> Classifier::FineTune(const Dataset& train, const Dataset& validation, double learning_rate,
                                              const std::function<void(const EpochReport&)>& on_epoch) {
  if (net_->paths.empty()) throw InputError("classify: an mlp takes one window length, it cannot be fine-tuned");
  if (!(learning_rate > 0)) throw InputError("classify: fine-tuning needs a positive learning rate");
  const int length = length_;
  length_ = train.length;
  try {
    return Fit(train, validation, on_epoch, "", learning_rate, false);
  } catch (...) {  // refused windows: the model stays as it was
    length_ = length;
    throw;
  }
}

std::vector<EpochReport> Classifier::Fit(const Dataset& train, const Dataset& validation,
                                         const std::function<void(const EpochReport&)>& on_epoch,
                                         const std::string& checkpoint, double learning_rate, bool fit_bins) {
  CheckShape(train, features_, length_, "the training set");
  if (validation.size()) CheckShape(validation, features_, length_, "the validation set");
  if (train.size() == 0) throw InputError("classify: the training set is empty");
  const int k = static_cast<int>(classes_.size());
  for (int y : train.y)
    if (y < 0 || y >= k) throw InputError("classify: a training label is outside the model's classes");
  UseThreads(options_.threads);

  std::vector<double> weights(k, 1.0);
  if (options_.class_weights) {
    std::vector<double> counts(k, 0);
    for (int y : train.y) counts[y] += 1;
    for (int c = 0; c < k; ++c) weights[c] = counts[c] > 0 ? train.size() / (k * counts[c]) : 0.0;
  }
  const auto weight = torch::tensor(std::vector<float>(weights.begin(), weights.end()));
  torch::optim::Adam optimiser(net_->parameters(), torch::optim::AdamOptions(learning_rate));

  // What must match for a checkpoint to be continued (epochs may grow).
  const nlohmann::json run = {{"variant", options_.variant},
                              {"batch_norm", options_.batch_norm},
                              {"features", features_},
                              {"length", length_},
                              {"classes", classes_},
                              {"train", train.size()},
                              {"validation", validation.size()},
                              {"batch_size", options_.batch_size},
                              {"seed", options_.seed},
                              {"input_noise", options_.input_noise},
                              {"class_weights", options_.class_weights},
                              {"input_bins", options_.input_bins},
                              {"distillation", options_.distillation}};
  TrainingState state;
  state.learning_rate = learning_rate;
  if (checkpoint.empty() || !ReadCheckpoint(checkpoint, run, state, *net_, optimiser)) {
    if (fit_bins) net_->FitBins(train.x, train.size(), length_);
    std::stringstream initial;
    torch::save(net_, initial);
    state.best_weights = initial.str();
  }
  for (auto& g : optimiser.param_groups()) static_cast<torch::optim::AdamOptions&>(g.options()).lr(state.learning_rate);
  if (on_epoch)
    for (const auto& r : state.reports) on_epoch(r);

  const auto labels_all = torch::tensor(std::vector<int64_t>(train.y.begin(), train.y.end()));
  const double alpha = options_.distillation;
  if (alpha > 0 && train.teacher.size() != train.size() * k)
    throw InputError("classify: distillation needs the teacher's probabilities for every training window");
  const auto teacher_all =
      alpha > 0 ? torch::tensor(train.teacher).reshape({static_cast<int64_t>(train.size()), k}) : torch::Tensor();
  // An interrupt (core/interrupt.h) stops at the epoch boundary: the checkpoint holds
  // every finished epoch, so a resumed run continues to the same result.
  for (int epoch = state.epoch + 1;
       epoch <= options_.epochs && state.since_best < options_.early_stop_patience && !InterruptRequested(); ++epoch) {
    const auto t0 = std::chrono::steady_clock::now();
    torch::manual_seed(static_cast<uint64_t>(options_.seed) * 100003u + static_cast<uint64_t>(epoch));
    net_->train();
    const auto order = torch::randperm(static_cast<int64_t>(train.size()), torch::kLong);
    const int64_t* idx = order.data_ptr<int64_t>();
    double loss_sum = 0;
    for (size_t start = 0; start < train.size(); start += options_.batch_size) {
      const size_t end = std::min(train.size(), start + options_.batch_size);
      if (end - start < 2 && options_.batch_norm && start > 0) break;  // batch norm needs two windows
      std::vector<int64_t> rows(idx + start, idx + end);
      auto x = Inputs(train, rows);
      if (options_.input_noise > 0) x = x + options_.input_noise * torch::randn_like(x);
      const auto target = labels_all.index_select(0, torch::tensor(rows));
      optimiser.zero_grad();
      const auto logits = net_->forward(x);
      auto loss = torch::nn::functional::cross_entropy(logits, target,
                                                       torch::nn::functional::CrossEntropyFuncOptions().weight(weight));
      if (alpha > 0) {
        const auto soft = teacher_all.index_select(0, torch::tensor(rows));
        loss = (1 - alpha) * loss - alpha * (soft * torch::log_softmax(logits, 1)).sum(1).mean();
      }
      loss.backward();
      optimiser.step();
      loss_sum += loss.item<double>() * static_cast<double>(end - start);
    }
    EpochReport r;
    r.epoch = epoch;
    r.train_loss = loss_sum / train.size();
    r.learning_rate = state.learning_rate;
    double score = r.train_loss;
    if (validation.size()) {
      const std::vector<float> p = Predict(validation);
      double nll = 0;
      std::vector<int> predicted(validation.size());
      for (size_t i = 0; i < validation.size(); ++i) {
        const float* row = p.data() + i * k;
        predicted[i] = static_cast<int>(std::max_element(row, row + k) - row);
        nll -= std::log(std::max(1e-12f, row[std::clamp(validation.y[i], 0, k - 1)]));
      }
      r.validation_loss = nll / validation.size();
      r.validation_macro_f1 = Score(validation.y, predicted, k).macro_f1;
      score = r.validation_loss;
    }
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    state.reports.push_back(r);
    state.epoch = epoch;
    if (score < state.best - 1e-6) {
      state.best = score, state.since_best = 0, state.since_lr = 0;
      std::stringstream best;
      torch::save(net_, best);
      state.best_weights = best.str();
    } else {
      ++state.since_best, ++state.since_lr;
      if (state.since_lr >= options_.plateau_patience) {
        state.learning_rate /= 2, state.since_lr = 0;
        for (auto& g : optimiser.param_groups())
          static_cast<torch::optim::AdamOptions&>(g.options()).lr(state.learning_rate);
      }
    }
    if (!checkpoint.empty()) WriteCheckpoint(checkpoint, run, state, *net_, optimiser);
    if (on_epoch) on_epoch(r);
  }
  std::stringstream best(state.best_weights);
  torch::load(net_, best);
  return state.reports;
}

std::vector<float> Classifier::Predict(const Dataset& data, int batch_size) const {
  CheckShape(data, features_, length_, "the input");
  UseThreads(options_.threads);
  torch::NoGradGuard no_grad;
  net_->eval();
  const int k = static_cast<int>(classes_.size());
  std::vector<float> out(data.size() * k);
  if (batch_size <= 0) batch_size = std::clamp((1 << 20) / (net_->widest * length_), 8, 256);
  for (size_t start = 0; start < data.size(); start += batch_size) {
    const size_t end = std::min(data.size(), start + batch_size);
    std::vector<int64_t> rows(end - start);
    for (size_t i = 0; i < rows.size(); ++i) rows[i] = static_cast<int64_t>(start + i);
    const auto p = torch::softmax(net_->forward(Inputs(data, rows)), 1).contiguous();
    std::copy_n(p.data_ptr<float>(), p.numel(), out.data() + start * k);
  }
  return out;
}

std::vector<int> Classifier::PredictClasses(const Dataset& data) const {
  return MostProbable(Predict(data), static_cast<int>(classes_.size()));
}

void Classifier::Save(const std::string& path, const nlohmann::json& extra) const {
  std::stringstream weights;
  torch::save(net_, weights);
  io::WriteTextAtomically(path + ".pt", weights.str());
  nlohmann::json meta = {{"format", "specht-classifier-1"},
                         {"variant", options_.variant},
                         {"batch_norm", options_.batch_norm},
                         {"input_bins", options_.input_bins},
                         {"features", features_},
                         {"length", length_},
                         {"classes", classes_},
                         {"parameters", parameter_count()},
                         {"extra", extra}};
  io::WriteTextAtomically(path + ".json", meta.dump(2) + "\n");
}

Classifier Classifier::Load(const std::string& path, nlohmann::json* extra) {
  std::ifstream f(path + ".json");
  if (!f) throw InputError(path + ".json: cannot open (a model is <name>.json + <name>.pt)");
  nlohmann::json meta;
  try {
    f >> meta;
  } catch (const std::exception& e) {
    throw InputError(path + ".json: not JSON: " + e.what());
  }
  if (meta.value("format", "") != "specht-classifier-1") throw InputError(path + ".json: not a specht classifier");
  try {
    // The architecture's options go through their declaration (JSON is YAML), so a
    // wrong type, an unknown variant or a value out of range is named by its key.
    nlohmann::json architecture = {{"variant", meta.at("variant")}, {"batch_norm", meta.at("batch_norm")}};
    if (meta.contains("input_bins")) architecture["input_bins"] = meta["input_bins"];  // absent before the option
    const auto o = params::FromYaml<ModelOptions>(architecture.dump(), path + ".json");
    Classifier c(o, meta.at("features").get<int>(), meta.at("length").get<int>(),
                 meta.at("classes").get<std::vector<std::string>>());
    std::ifstream w(path + ".pt", std::ios::binary);
    if (!w) throw InputError(path + ".pt: cannot open");
    torch::load(c.net_, w);
    if (extra) *extra = meta.value("extra", nlohmann::json{});
    return c;
  } catch (const InputError&) {
    throw;
  } catch (const c10::Error& e) {
    throw InputError(path + ".pt: weights do not fit the architecture in " + path + ".json (" +
                     std::string(e.what_without_backtrace()).substr(0, 200) + ")");
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path + ".json: " + e.what());
  }
}

}  // namespace specht::classify
