// The module graph of modules/dependencies.txt holds in the tree: every module's
// #include "specht/<m>/…" lines and CMake links (specht::<m>) name only itself and
// the modules its line allows, every module directory is listed, and the graph has
// no cycle. The checker is tried on a made-up tree too, so it is known to fail.
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.h"

namespace specht {
namespace {

namespace fs = std::filesystem;
using Graph = std::map<std::string, std::set<std::string>>;

// "module: a b c" lines; '#' starts a comment.
Graph ReadGraph(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  Graph g;
  std::string line;
  while (std::getline(in, line)) {
    line = line.substr(0, line.find('#'));
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    std::istringstream name(line.substr(0, colon)), deps(line.substr(colon + 1));
    std::string module, dep;
    name >> module;
    auto& allowed = g[module];
    while (deps >> dep) allowed.insert(dep);
  }
  return g;
}

// Every use of another module by `module`'s sources and build file, as
// "file:line: uses X".
std::vector<std::pair<std::string, std::string>> Uses(const fs::path& dir) {
  static const std::regex include(R"(#include\s*"specht/([a-z_]+)/)"), link(R"(specht::([a-z_]+))");
  std::vector<std::pair<std::string, std::string>> uses;
  const auto scan = [&](const fs::path& file, const std::regex& pattern) {
    std::ifstream in(file);
    std::string line;
    for (int n = 1; std::getline(in, line); ++n) {
      const std::string code = line.substr(0, line.find(file.extension() == ".txt" ? "#" : "//"));
      for (std::sregex_iterator m(code.begin(), code.end(), pattern), end; m != end; ++m)
        uses.push_back({(*m)[1], file.string() + ":" + std::to_string(n)});
    }
  };
  for (const auto& entry : fs::recursive_directory_iterator(dir)) {
    const auto ext = entry.path().extension();
    if (ext == ".h" || ext == ".cpp") scan(entry.path(), include);
  }
  if (fs::exists(dir / "CMakeLists.txt")) scan(dir / "CMakeLists.txt", link);
  return uses;
}

std::vector<std::string> Violations(const Graph& graph, const fs::path& modules) {
  std::vector<std::string> problems;
  for (const auto& entry : fs::directory_iterator(modules)) {
    if (!entry.is_directory()) continue;
    const std::string module = entry.path().filename();
    const auto allowed = graph.find(module);
    if (allowed == graph.end()) {
      problems.push_back("module " + module + " is not in the graph");
      continue;
    }
    for (const auto& [used, where] : Uses(entry.path())) {
      if (used != module && !allowed->second.count(used))
        problems.push_back(where + ": " + module + " uses " + used + ", which its line does not allow");
    }
  }
  for (const auto& [module, deps] : graph) {
    for (const auto& d : deps)
      if (!graph.count(d)) problems.push_back("module " + module + " names " + d + ", which is not in the graph");
  }
  // A cycle: depth-first search with the path on a stack.
  std::map<std::string, int> state;  // 1 on the path, 2 done
  std::function<void(const std::string&, std::vector<std::string>&)> visit = [&](const std::string& m,
                                                                                 std::vector<std::string>& path) {
    state[m] = 1;
    path.push_back(m);
    const auto it = graph.find(m);
    if (it != graph.end()) {
      for (const auto& d : it->second) {
        if (state[d] == 1) {
          std::string cycle;
          for (auto p = std::find(path.begin(), path.end(), d); p != path.end(); ++p) cycle += *p + " → ";
          problems.push_back("cycle: " + cycle + d);
        } else if (state[d] == 0) {
          visit(d, path);
        }
      }
    }
    path.pop_back();
    state[m] = 2;
  };
  for (const auto& [module, deps] : graph) {
    std::vector<std::string> path;
    if (state[module] == 0) visit(module, path);
  }
  return problems;
}

std::string Joined(const std::vector<std::string>& lines) {
  std::string s;
  for (const auto& l : lines) s += l + "\n";
  return s;
}

TEST(DependencyTest, TheTreeKeepsTheModuleGraph) {
  const fs::path root = testing::SourceDir();
  const Graph graph = ReadGraph(root / "modules/dependencies.txt");
  ASSERT_GE(graph.size(), 10u);
  const auto problems = Violations(graph, root / "modules");
  EXPECT_TRUE(problems.empty()) << Joined(problems);
}

TEST(DependencyTest, OnlyThePipelineUsesTheSimulatorAndTheWorldModelReadsNoProducer) {
  const Graph graph = ReadGraph(fs::path(testing::SourceDir()) / "modules/dependencies.txt");
  for (const auto& [module, deps] : graph) {
    if (module != "pipeline") {
      EXPECT_FALSE(deps.count("sim")) << module << " may use the simulator";
    }
  }
  for (const char* producer : {"slam", "stereo", "detect", "track", "classify"}) {
    EXPECT_FALSE(graph.at("world").count(producer)) << "the world model depends on " << producer;
    EXPECT_FALSE(graph.at("plan").count(producer)) << "the planner reads " << producer << " directly";
    EXPECT_FALSE(graph.at("decide").count(producer)) << "decisions read " << producer << " directly";
  }
}

TEST(DependencyTest, TheCheckFindsAForbiddenIncludeALinkAndACycle) {
  const fs::path tree = testing::TempDir() + "/modules";
  fs::create_directories(tree / "a/src");
  fs::create_directories(tree / "b/include/specht/b");
  fs::create_directories(tree / "stray");
  testing::WriteFile(tree / "a/src/a.cpp", "#include \"specht/b/b.h\"\n// #include \"specht/c/c.h\" (a comment)\n");
  testing::WriteFile(tree / "b/include/specht/b/b.h", "#pragma once\n#include \"specht/b/other.h\"\n");
  testing::WriteFile(tree / "b/CMakeLists.txt", "specht_module(b PUBLIC_DEPS specht::a)  # specht::c\n");

  const Graph fine = {{"a", {"b"}}, {"b", {}}, {"stray", {}}};
  EXPECT_EQ(Joined(Violations(fine, tree)),
            (tree / "b/CMakeLists.txt").string() + ":1: b uses a, which its line does not allow\n");

  const Graph wrong = {{"a", {}}, {"b", {"a"}}};
  const std::string problems = Joined(Violations(wrong, tree));
  EXPECT_THAT(problems, ::testing::HasSubstr("a.cpp:1: a uses b, which its line does not allow"));
  EXPECT_THAT(problems, ::testing::HasSubstr("module stray is not in the graph"));

  const Graph cyclic = {{"a", {"b"}}, {"b", {"a"}}, {"stray", {}}};
  EXPECT_THAT(Joined(Violations(cyclic, tree)), ::testing::HasSubstr("cycle: a → b → a"));
}

}  // namespace
}  // namespace specht
