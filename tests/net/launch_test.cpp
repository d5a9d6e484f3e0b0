// Launch files (net/launch.h): the shipped ones parse and start each node with the
// addresses of its computer; a broken file names its line and reason.
#include "specht/net/launch.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "specht/core/error.h"
#include "test_support.h"

namespace specht::net {
namespace {

using ::testing::HasSubstr;

const std::vector<std::string> kStages = {"play", "slam", "record"};

std::string Joined(const std::vector<std::string>& words) {
  std::string s;
  for (const auto& w : words) s += (s.empty() ? "" : " ") + w;
  return s;
}

const LaunchNode& Named(const LaunchFile& f, const std::string& name) {
  for (const auto& n : f.nodes)
    if (n.name == name) return n;
  throw std::runtime_error("no node " + name);
}

TEST(LaunchFileTest, OneComputerKeepsTheLoopbackDefaults) {
  const LaunchFile f = LoadLaunchFile(testing::SourceDir() + "/params/launch/slam-over-dds.yaml", kStages);
  ASSERT_EQ(f.nodes.size(), 3u);
  EXPECT_EQ(f.nodes[0].name, "slam");
  EXPECT_TRUE(f.nodes[0].required);
  EXPECT_FALSE(f.domain);
  LaunchOptions o;
  o.out_dir = "out";
  EXPECT_EQ(Joined(NodeCommand(f, Named(f, "slam"), o)), "node slam --idle-end 2 -o out/slam");
  o.domain = 12;
  o.param_files = {"base.yaml"};
  o.overrides = {"slam.max_scans=5"};
  EXPECT_EQ(Joined(NodeCommand(f, Named(f, "play"), o)),
            "node play --rate 0 --subscribers 2 -o out/play --domain 12 -p base.yaml --set slam.max_scans=5");
}

TEST(LaunchFileTest, EachComputerBindsItsAddressAndListsEveryPeer) {
  const LaunchFile f = LoadLaunchFile(testing::SourceDir() + "/params/launch/two-computers.yaml", kStages);
  EXPECT_EQ(f.domain, 7);
  LaunchOptions o;
  o.out_dir = "o";
  EXPECT_EQ(Joined(NodeCommand(f, Named(f, "slam"), o)),
            "node slam --idle-end 2 -o o/slam --domain 7 --set dds.interface_address=192.168.1.10 --set "
            "dds.peers=[192.168.1.10, 192.168.1.20]");
  EXPECT_THAT(Joined(NodeCommand(f, Named(f, "record"), o)),
              HasSubstr("--set dds.interface_address=192.168.1.20 --set dds.peers=[192.168.1.10, 192.168.1.20]"));
}

TEST(LaunchFileTest, ParameterFilesAreRelativeToTheLaunchFile) {
  const LaunchFile f =
      ParseLaunchFile("nodes:\n  - {name: a, node: slam, params: [p.yaml, /abs/q.yaml, ../r.yaml], set: [x.y=1]}\n",
                      "/cars/one/launch.yaml", kStages);
  EXPECT_EQ(f.nodes[0].params, (std::vector<std::string>{"/cars/one/p.yaml", "/abs/q.yaml", "/cars/r.yaml"}));
  EXPECT_EQ(f.nodes[0].set, (std::vector<std::string>{"x.y=1"}));
  EXPECT_EQ(f.nodes[0].host, "localhost");
}

TEST(LaunchFileTest, BadFilesNameLineAndReason) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"nodes: [", "f.yaml:1: YAML syntax error"},
      {"domain: 3\n", "f.yaml:1: a launch file is a map with a 'nodes' list"},
      {"nodes: []\n", "nodes must be a non-empty list"},
      {"nodes:\n  - {name: a, node: slma}\n",
       "f.yaml:2: unknown node 'slma' (did you mean 'slam'?); there are play, slam, record"},
      {"nodes:\n  - {name: a, node: slam}\n  - {name: a, node: play}\n",
       "f.yaml:3: node name 'a' is used twice (line 2)"},
      {"nodes:\n  - {name: a, node: slam, host: car}\n", "f.yaml:2: unknown host 'car'"},
      {"hosts: {car: 10.0.0.300}\nnodes:\n  - {name: a, node: slam}\n",
       "f.yaml:1: host 'car': '10.0.0.300' is not an IPv4 address"},
      {"hosts: {car: 10.0.0.3}\nnodes:\n  - {name: a, node: slam, host: cra}\n",
       "unknown host 'cra' (did you mean 'car'?)"},
      {"nodes:\n  - {name: a, node: slam, arg: [x]}\n",
       "f.yaml:2: unknown field 'arg' in a node (did you mean 'args'?)"},
      {"nodes:\n  - {name: a, node: slam, required: yes please}\n", "required must be true or false"},
      {"domain: 300\nnodes:\n  - {name: a, node: slam}\n",
       "f.yaml:1: domain must be an integer in [0, 232], not '300'"},
      {"nodes:\n  - {name: ../a, node: slam}\n", "must be a folder name"},
      {"nodes:\n  - {node: slam}\n", "f.yaml:2: a node needs 'name' and 'node'"},
      {"nodes:\n  - {name: a, node: slam, args: x}\n", "args must be a list"},
      {"nodes:\n  - slam\n", "a node is a map"},
      {"nodez: []\n", "a launch file is a map with a 'nodes' list"},
  };
  for (const auto& [text, expected] : cases) {
    try {
      ParseLaunchFile(text, "f.yaml", kStages);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_THAT(e.what(), HasSubstr(expected)) << text;
    }
  }
}

TEST(LaunchFileTest, AHostWithoutNodesIsAnError) {
  const LaunchFile f = ParseLaunchFile("nodes:\n  - {name: a, node: slam}\n", "f.yaml", kStages);
  LaunchOptions o;
  o.host = "car";
  o.out_dir = testing::TempDir("launch_no_host");
  EXPECT_THROW(Launch(f, o), InputError);
}

}  // namespace
}  // namespace specht::net
