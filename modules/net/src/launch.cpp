#include "specht/net/launch.h"

#include <signal.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <sstream>
#include <thread>

#include "internal/address.h"
#include "specht/core/error.h"
#include "specht/core/interrupt.h"
#include "specht/core/params.h"
#include "specht/core/process.h"
#include "specht/io/report.h"

namespace specht::net {
namespace {

namespace fs = std::filesystem;

constexpr char kLocalhost[] = "localhost";

class FileReader {
 public:
  explicit FileReader(std::string path) : path_(std::move(path)) {}
  [[noreturn]] void Fail(const YAML::Node& at, const std::string& why) const {
    throw InputError(Where(path_, at.IsDefined() ? at.Mark().line + 1 : 0) + why);
  }
  // The keys of `map` must be among `known`.
  void OnlyKeys(const YAML::Node& map, const std::vector<std::string>& known, const std::string& what) const {
    for (const auto& kv : map) {
      const std::string key = Scalar(kv.first, what + " key");
      if (std::find(known.begin(), known.end(), key) != known.end()) continue;
      const std::string nearest = params::NearestKey(key, known);
      Fail(kv.first,
           "unknown field '" + key + "' in " + what + (nearest.empty() ? "" : " (did you mean '" + nearest + "'?)"));
    }
  }
  std::string Scalar(const YAML::Node& n, const std::string& what) const {
    if (!n.IsScalar()) Fail(n, what + " must be a single value");
    return n.Scalar();
  }
  std::vector<std::string> Strings(const YAML::Node& n, const std::string& what) const {
    if (!n.IsSequence()) Fail(n, what + " must be a list");
    std::vector<std::string> out;
    for (const auto& item : n) out.push_back(Scalar(item, what + " entries"));
    return out;
  }
  bool Bool(const YAML::Node& n, const std::string& what) const {
    const std::string v = Scalar(n, what);
    if (v == "true") return true;
    if (v == "false") return false;
    Fail(n, what + " must be true or false, not '" + v + "'");
  }
  int Domain(const YAML::Node& n) const {
    const std::string v = Scalar(n, "domain");
    size_t used = 0;
    int domain = -1;
    try {
      domain = std::stoi(v, &used);
    } catch (const std::exception&) {
    }
    if (used != v.size() || domain < 0 || domain > 232)
      Fail(n, "domain must be an integer in [0, 232], not '" + v + "'");
    return domain;
  }

 private:
  std::string path_;
};

LaunchNode ParseNode(const FileReader& in, const YAML::Node& n, const std::vector<std::string>& stages,
                     const std::string& folder) {
  if (!n.IsMap()) in.Fail(n, "a node is a map (name, node, host, args, params, set, required)");
  in.OnlyKeys(n, {"name", "node", "host", "args", "params", "set", "required"}, "a node");
  LaunchNode node;
  node.line = n.Mark().line + 1;
  if (!n["name"] || !n["node"]) in.Fail(n, "a node needs 'name' and 'node' (the stage)");
  node.name = in.Scalar(n["name"], "name");
  if (node.name.empty() || node.name.find_first_of("/\\ ") != std::string::npos || node.name[0] == '.')
    in.Fail(n["name"], "name '" + node.name + "' must be a folder name (no slash, space or leading dot)");
  node.stage = in.Scalar(n["node"], "node");
  if (std::find(stages.begin(), stages.end(), node.stage) == stages.end()) {
    const std::string nearest = params::NearestKey(node.stage, stages);
    std::string all;
    for (const auto& s : stages) all += (all.empty() ? "" : ", ") + s;
    in.Fail(n["node"], "unknown node '" + node.stage + "'" +
                           (nearest.empty() ? "" : " (did you mean '" + nearest + "'?)") + "; there are " + all);
  }
  if (n["host"]) node.host = in.Scalar(n["host"], "host");
  if (n["args"]) node.args = in.Strings(n["args"], "args");
  if (n["set"]) node.set = in.Strings(n["set"], "set");
  if (n["params"])
    for (const auto& p : in.Strings(n["params"], "params"))
      node.params.push_back(fs::path(p).is_absolute() ? p : (fs::path(folder) / p).lexically_normal().string());
  if (n["required"]) node.required = in.Bool(n["required"], "required");
  return node;
}

bool SpansHosts(const LaunchFile& file) {
  return std::any_of(file.nodes.begin(), file.nodes.end(), [](const auto& n) { return n.host != kLocalhost; });
}

// Appends what `path` gained since `offset` to `pending` and prints its complete
// lines as "[name] line" (a progress line ended by '\r' counts as a line).
void ShowNewLines(const std::string& path, const std::string& name, std::streamoff& offset, std::string& pending,
                  bool flush) {
  std::ifstream in(path, std::ios::binary);
  if (in) {
    in.seekg(offset);
    std::ostringstream text;
    text << in.rdbuf();
    offset += static_cast<std::streamoff>(text.str().size());
    pending += text.str();
  }
  size_t start = 0;
  for (size_t end; (end = pending.find_first_of("\r\n", start)) != std::string::npos; start = end + 1)
    if (end > start) std::printf("[%s] %s\n", name.c_str(), pending.substr(start, end - start).c_str());
  pending.erase(0, start);
  if (flush && !pending.empty()) {
    std::printf("[%s] %s\n", name.c_str(), pending.c_str());
    pending.clear();
  }
  std::fflush(stdout);
}

struct RunningNode {
  const LaunchNode* node = nullptr;
  std::vector<std::string> command;
  std::string console;
  std::unique_ptr<ChildProcess> process;
  std::streamoff shown = 0;
  std::string pending;
};

std::string NodeStatus(const std::string& node_dir) {
  std::ifstream in(node_dir + "/report.json");
  if (!in) return "";
  try {
    return nlohmann::json::parse(in).value("status", "");
  } catch (const nlohmann::json::exception&) {
    return "";
  }
}

}  // namespace

LaunchFile ParseLaunchFile(const std::string& text, const std::string& path, const std::vector<std::string>& stages) {
  const FileReader in(path);
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(Where(path, e.mark.line + 1) + "YAML syntax error: " + e.msg);
  }
  if (!root.IsMap() || !root["nodes"]) in.Fail(root, "a launch file is a map with a 'nodes' list");
  in.OnlyKeys(root, {"domain", "hosts", "nodes"}, "the launch file");
  LaunchFile file;
  file.path = path;
  file.hosts[kLocalhost] = "127.0.0.1";
  if (root["domain"]) file.domain = in.Domain(root["domain"]);
  if (const YAML::Node hosts = root["hosts"]) {
    if (!hosts.IsMap()) in.Fail(hosts, "hosts must be a map of host name to IPv4 address");
    for (const auto& kv : hosts) {
      const std::string name = in.Scalar(kv.first, "a host name"), address = in.Scalar(kv.second, "an address");
      if (!internal::IsIpv4(address))
        in.Fail(kv.second, "host '" + name + "': '" + address + "' is not an IPv4 address");
      if (name == kLocalhost && address != "127.0.0.1") in.Fail(kv.second, "localhost is 127.0.0.1");
      file.hosts[name] = address;
    }
  }
  const YAML::Node nodes = root["nodes"];
  if (!nodes.IsSequence() || nodes.size() == 0) in.Fail(nodes, "nodes must be a non-empty list");
  const std::string folder = fs::path(path).parent_path().string();
  std::vector<std::string> host_names;
  for (const auto& [name, address] : file.hosts) host_names.push_back(name);
  for (const auto& n : nodes) {
    LaunchNode node = ParseNode(in, n, stages, folder);
    if (!file.hosts.count(node.host)) {
      const std::string nearest = params::NearestKey(node.host, host_names);
      in.Fail(n["host"], "unknown host '" + node.host + "'" +
                             (nearest.empty() ? " (list it under hosts)" : " (did you mean '" + nearest + "'?)"));
    }
    for (const auto& other : file.nodes)
      if (other.name == node.name)
        in.Fail(n["name"], "node name '" + node.name + "' is used twice (line " + std::to_string(other.line) + ")");
    file.nodes.push_back(std::move(node));
  }
  return file;
}

LaunchFile LoadLaunchFile(const std::string& path, const std::vector<std::string>& stages) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the launch file");
  std::ostringstream text;
  text << in.rdbuf();
  return ParseLaunchFile(text.str(), path, stages);
}

std::vector<std::string> NodeCommand(const LaunchFile& file, const LaunchNode& node, const LaunchOptions& options) {
  std::vector<std::string> argv = {"node", node.stage};
  argv.insert(argv.end(), node.args.begin(), node.args.end());
  argv.insert(argv.end(), {"-o", (fs::path(options.out_dir) / node.name).string()});
  const std::optional<int> domain = options.domain ? options.domain : file.domain;
  if (domain) argv.insert(argv.end(), {"--domain", std::to_string(*domain)});
  for (const auto* files : {&options.param_files, &node.params})
    for (const auto& p : *files) argv.insert(argv.end(), {"-p", p});
  if (SpansHosts(file)) {
    std::set<std::string> used;
    for (const auto& n : file.nodes) used.insert(file.hosts.at(n.host));
    std::string peers;
    for (const auto& address : used) peers += (peers.empty() ? "" : ", ") + address;
    argv.insert(argv.end(),
                {"--set", "dds.interface_address=" + file.hosts.at(node.host), "--set", "dds.peers=[" + peers + "]"});
  }
  for (const auto* sets : {&options.overrides, &node.set})
    for (const auto& s : *sets) argv.insert(argv.end(), {"--set", s});
  return argv;
}

int Launch(const LaunchFile& file, const LaunchOptions& options) {
  std::vector<RunningNode> nodes;
  std::vector<const LaunchNode*> elsewhere;
  for (const auto& n : file.nodes) {
    if (n.host != options.host) {
      elsewhere.push_back(&n);
      continue;
    }
    RunningNode& running = nodes.emplace_back();
    running.node = &n;
    running.command = NodeCommand(file, n, options);
    running.console = (fs::path(options.out_dir) / n.name / "console.log").string();
  }
  if (nodes.empty())
    throw InputError(file.path + ": no node runs on host '" + options.host + "' (--host names one of the file's)");
  io::RunReport report("launch");
  report.json()["inputs"] = {{"launch_file", file.path}, {"host", options.host}};
  for (auto& n : nodes) {
    fs::create_directories(fs::path(n.console).parent_path());
    std::vector<std::string> argv = {options.executable};
    argv.insert(argv.end(), n.command.begin(), n.command.end());
    if (!options.quiet) std::printf("[launch] %s: %s\n", n.node->name.c_str(), n.node->stage.c_str());
    n.process = std::make_unique<ChildProcess>(argv, n.console);
  }
  for (const auto* n : elsewhere)
    std::printf("[launch] %s runs on %s (%s): specht launch %s --host %s\n", n->name.c_str(), n->host.c_str(),
                file.hosts.at(n->host).c_str(), file.path.c_str(), n->host.c_str());
  // Supervise: show consoles; on a signal or a required node's failure, stop the rest.
  std::string stopped_by;  // why the launch stopped its nodes, "" when they ended by themselves
  auto deadline = std::chrono::steady_clock::time_point::max();
  for (;;) {
    bool running = false;
    for (auto& n : nodes) {
      const std::optional<int> code = n.process->Poll();
      if (!options.quiet) ShowNewLines(n.console, n.node->name, n.shown, n.pending, code.has_value());
      running |= !code;
      if (code && *code != 0 && n.node->required && stopped_by.empty())
        stopped_by = "required node " + n.node->name + " exited with " + std::to_string(*code);
    }
    if (!running) break;
    if (InterruptRequested() && stopped_by.empty()) stopped_by = InterruptName();
    if (!stopped_by.empty() && deadline == std::chrono::steady_clock::time_point::max()) {
      if (!options.quiet) std::printf("[launch] stopping the nodes: %s\n", stopped_by.c_str());
      for (auto& n : nodes) n.process->Signal(SIGINT);
      deadline = std::chrono::steady_clock::now() + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                                        std::chrono::duration<double>(options.shutdown_timeout_s));
    }
    if (std::chrono::steady_clock::now() > deadline)
      for (auto& n : nodes) n.process->Signal(SIGKILL);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  // Summary and report.
  nlohmann::json table = nlohmann::json::array();
  std::string failed;
  std::printf("%-16s %-8s %-10s %6s %9s  %s\n", "node", "stage", "host", "exit", "wall_s", "status");
  for (auto& n : nodes) {
    const int code = *n.process->Poll();
    const std::string status = NodeStatus((fs::path(options.out_dir) / n.node->name).string());
    std::printf("%-16s %-8s %-10s %6d %9.1f  %s\n", n.node->name.c_str(), n.node->stage.c_str(), n.node->host.c_str(),
                code, n.process->seconds(), status.empty() ? "-" : status.c_str());
    table.push_back({{"name", n.node->name},
                     {"node", n.node->stage},
                     {"host", n.node->host},
                     {"command", n.command},
                     {"exit_code", code},
                     {"wall_s", n.process->seconds()},
                     {"status", status},
                     {"console", fs::path(n.node->name) / "console.log"}});
    if (code != 0 && failed.empty()) failed = n.node->name + " exited with " + std::to_string(code);
  }
  report.json()["nodes"] = table;
  for (const auto* n : elsewhere) report.json()["elsewhere"].push_back({{"name", n->name}, {"host", n->host}});
  int exit_code = 0;
  if (InterruptRequested()) {
    report.SetInterrupted(std::to_string(nodes.size()) + " nodes stopped");
    exit_code = InterruptExitCode();
  } else if (!failed.empty()) {
    report.json()["status"] = "failed";
    report.json()["error"] = stopped_by.empty() ? failed : stopped_by;
    exit_code = 1;
  }
  report.Write(options.out_dir);
  return exit_code;
}

}  // namespace specht::net
