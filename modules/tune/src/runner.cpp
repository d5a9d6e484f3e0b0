#include "specht/tune/runner.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include "specht/core/csv.h"
#include "specht/core/error.h"
#include "specht/core/interrupt.h"

namespace specht::tune {
namespace {

std::string Header(const SearchSpace& space) {
  std::string h = "index,generation,status,value,seconds";
  for (const auto& d : space.dimensions()) h += "," + d.key;
  return h + ",error";
}

std::string Clean(std::string s) {
  for (char& c : s)
    if (c == ',' || c == '\n' || c == '\r') c = ';';
  return s;
}

std::string LogLine(const Evaluation& e, size_t dims) {
  std::ostringstream line;
  line.precision(10);
  line << e.index << ',' << e.generation << ',' << (e.ok ? "ok" : "failed") << ',';
  if (e.ok) line << e.value;
  line << ',' << e.seconds;
  for (size_t i = 0; i < dims; ++i) line << ',' << (e.values.empty() ? "default" : e.values[i]);
  line << ',' << Clean(e.error) << '\n';
  return line.str();
}

// The log's evaluations by index. A last line cut short by a kill is dropped (it
// is evaluated again); any other bad line is an error naming the line.
std::map<int, Evaluation> ReadLog(const std::string& path, const SearchSpace& space) {
  std::map<int, Evaluation> out;
  std::ifstream f(path, std::ios::binary);
  if (!f) return out;
  std::stringstream all;
  all << f.rdbuf();
  const std::string text = all.str();
  const size_t dims = space.size();
  size_t pos = 0;
  int line_no = 0;
  while (pos < text.size()) {
    const size_t end = text.find('\n', pos);
    if (end == std::string::npos) break;  // unterminated last line: the write was interrupted
    const std::string line = text.substr(pos, end - pos);
    pos = end + 1;
    ++line_no;
    if (line_no == 1) {
      if (line != Header(space))
        throw InputError(path + ":1: the log's columns differ from this search's parameters (expected \"" +
                         Header(space) + "\")");
      continue;
    }
    const auto f = SplitCsv(line);
    const std::string where = path + ":" + std::to_string(line_no) + ": ";
    if (f.size() != dims + 6) throw InputError(where + "expected " + std::to_string(dims + 6) + " fields");
    Evaluation e;
    try {
      e.index = std::stoi(f[0]);
      e.generation = std::stoi(f[1]);
      e.ok = f[2] == "ok";
      if (e.ok) e.value = std::stod(f[3]);
      e.seconds = std::stod(f[4]);
    } catch (const std::exception&) {
      throw InputError(where + "not a number where one is expected");
    }
    if (f[2] != "ok" && f[2] != "failed") throw InputError(where + "status must be ok or failed");
    if (e.index != 0) e.values.assign(f.begin() + 5, f.begin() + 5 + static_cast<long>(dims));
    e.error = f.back();
    out[e.index] = std::move(e);
  }
  return out;
}

}  // namespace

RunResult RunTuning(const SearchSpace& space, const RunOptions& o, const Evaluator& evaluate) {
  if (o.log_path.empty()) throw InputError("tune: a log path is required");
  if (o.repeats < 1 || o.jobs < 1) throw InputError("tune: repeats and jobs must be at least 1");
  std::map<int, Evaluation> logged;
  if (o.resume) logged = ReadLog(o.log_path, space);
  if (logged.empty()) {
    std::ofstream(o.log_path, std::ios::trunc) << Header(space) << '\n';
    if (!std::ofstream(o.log_path, std::ios::app)) throw InputError(o.log_path + ": cannot write the log");
  }
  std::vector<int> choice_counts;
  for (const auto& d : space.dimensions())
    choice_counts.push_back(d.kind == Dimension::Kind::kChoice ? static_cast<int>(d.choices.size()) : 0);
  const auto search = MakeSearch(o.search, choice_counts);

  RunResult r;
  std::mutex mutex;  // guards r, the log and the progress callback
  std::atomic<int> started{0};
  const int planned = 1 + o.search.budget;
  const auto better = [&](const Evaluation& a, const Evaluation& b) {  // a better than b
    if (!a.ok) return false;
    if (!b.ok) return true;
    return o.maximise ? a.value > b.value : a.value < b.value;
  };
  const auto record = [&](Evaluation e, bool reused) {
    std::lock_guard<std::mutex> lock(mutex);
    if (!reused) std::ofstream(o.log_path, std::ios::app) << LogLine(e, space.size());
    if (static_cast<int>(r.evaluations.size()) <= e.index) r.evaluations.resize(e.index + 1);
    r.evaluations[e.index] = e;
    r.reused += reused;
    if (e.ok && (r.best < 0 || better(e, r.evaluations[r.best]))) r.best = e.index;
    int done = 0;
    for (const auto& x : r.evaluations) done += x.seconds > 0 || x.ok || !x.error.empty();
    if (o.progress) o.progress(done, planned, r.best >= 0 ? r.evaluations[r.best] : e);
  };
  // Runs one candidate's repeats; false when stop_after says not to start it.
  // An interrupt (core/interrupt.h) stops the same way, and an evaluation it cut short
  // is not logged: a resumed search runs it again.
  const auto run_one = [&](Evaluation e) {
    if (InterruptRequested()) return false;
    if (o.stop_after > 0 && started.fetch_add(1) >= o.stop_after) return false;
    const auto t0 = std::chrono::steady_clock::now();
    double sum = 0;
    e.ok = true;
    for (int k = 0; k < o.repeats && e.ok; ++k) {
      Outcome out;
      if (e.index == 0) {
        out = evaluate(0, k, {});  // exceptions stop the tuner: the setup is wrong
      } else {
        try {
          out = evaluate(e.index, k, e.values);
        } catch (const std::exception& ex) {
          out.ok = false, out.error = ex.what();
        }
      }
      if (out.ok && !std::isfinite(out.value)) out.ok = false, out.error = "metric is not a finite number";
      e.ok = out.ok;
      e.error = out.error;
      sum += out.value;
    }
    if (InterruptRequested()) return false;
    e.value = e.ok ? sum / o.repeats : std::numeric_limits<double>::quiet_NaN();
    e.seconds = std::max(1e-9, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    record(std::move(e), false);
    return true;
  };
  const auto check_logged = [&](const Evaluation& fresh) {
    const auto it = logged.find(fresh.index);
    if (it == logged.end()) return false;
    if (it->second.values != fresh.values || it->second.generation != fresh.generation)
      throw InputError(o.log_path + ": evaluation " + std::to_string(fresh.index) +
                       " in the log has other values: the log belongs to another search (method, seed or ranges)");
    record(it->second, true);
    return true;
  };

  // A candidate whose values an earlier one already had takes that one's outcome
  // (evaluations are deterministic): logged with 0 s, not run again.
  std::map<std::vector<std::string>, int> first_with;  // values -> index of the first candidate with them
  const auto finished = [&](int i) {
    std::lock_guard<std::mutex> lock(mutex);
    if (static_cast<int>(r.evaluations.size()) <= i) return false;
    const Evaluation& e = r.evaluations[i];
    return e.seconds > 0 || e.ok || !e.error.empty();
  };
  const auto copy_outcome = [&](Evaluation e, int original) {
    const Evaluation& from = r.evaluations[original];
    e.ok = from.ok, e.value = from.value, e.error = from.error, e.seconds = 0;
    ++r.duplicates;
    record(std::move(e), false);
  };

  Evaluation defaults;
  if (!check_logged(defaults) && !run_one(defaults)) return r;

  int next = 1;
  bool stopped = false;
  for (int generation = 1; next <= o.search.budget && !stopped; ++generation) {
    std::vector<Genes> asked = search->Ask();
    if (asked.empty()) break;
    const bool last = static_cast<int>(asked.size()) > o.search.budget - next + 1;
    if (last) asked.resize(o.search.budget - next + 1);
    std::vector<Evaluation> pending;
    std::vector<std::pair<Evaluation, int>> repeated;  // candidate, index of the first with its values
    std::vector<int> indices;
    for (const auto& g : asked) {
      Evaluation e;
      e.index = next++, e.generation = generation, e.values = space.Decode(g);
      indices.push_back(e.index);
      const auto [first, is_first] = first_with.emplace(e.values, e.index);
      if (check_logged(e)) continue;
      if (is_first) {
        pending.push_back(std::move(e));
      } else {
        repeated.emplace_back(std::move(e), first->second);
      }
    }
    std::atomic<size_t> cursor{0};
    std::atomic<bool> skipped{false};
    std::vector<std::thread> workers;
    for (int j = 0; j < std::min<int>(o.jobs, static_cast<int>(pending.size())); ++j)
      workers.emplace_back([&] {
        for (size_t i; (i = cursor.fetch_add(1)) < pending.size();)
          if (!run_one(pending[i])) skipped = true;
      });
    for (auto& w : workers) w.join();
    for (auto& [e, original] : repeated) {
      if (finished(original)) copy_outcome(std::move(e), original);
    }
    stopped = skipped;
    if (stopped || last) break;
    std::vector<double> values;
    for (int i : indices) {
      const Evaluation& e = r.evaluations[i];
      const double v = o.maximise ? -e.value : e.value;
      values.push_back(e.ok ? v : std::numeric_limits<double>::infinity());
    }
    search->Tell(values);
  }
  r.complete = !stopped;
  return r;
}

}  // namespace specht::tune
