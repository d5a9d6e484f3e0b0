// specht/net/launch.h: several nodes started from one file, on one computer or many.
//
// A launch file (YAML) lists the nodes of a setup and the computer each runs on:
//
//   domain: 7                  # optional: the DDS domain of every node (else dds.domain)
//   hosts:                     # optional: name → IPv4 address; "localhost" is 127.0.0.1
//     car: 192.168.1.10
//     perception-pc: 192.168.1.11
//   nodes:
//     - name: slam             # unique; the node's output folder is <out>/<name>
//       node: slam             # the stage (`specht node <stage>`)
//       host: car              # default localhost
//       args: [--idle-end, 2]  # its command-line arguments, as written
//       params: [car.yaml]     # parameter files, relative to the launch file
//       set: [slam.max_scans=100]
//       required: true         # when it fails, the launch stops the others
//
// `specht launch FILE --host H` starts the nodes of host H (localhost by default) in
// the order listed, each as a child process (core/process.h) with its console in
// <out>/<name>/console.log, shown prefixed with its name; the same file on every
// computer starts each one's share. When the file names hosts beyond localhost,
// every node binds DDS to its host's address and lists every host as a peer
// (dds.interface_address, dds.peers); otherwise the parameters' loopback defaults
// hold. The launch ends when its nodes have ended; when a required node fails, or a
// signal comes, the others get SIGINT (they write what they have, as on Ctrl-C) and
// SIGKILL after shutdown_timeout_s. report.json says how each node ended.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace specht::net {

struct LaunchNode {
  std::string name, stage, host = "localhost";
  std::vector<std::string> args, params, set;  // params: resolved against the launch file's folder
  bool required = false;
  int line = 0;  // in the launch file
};

struct LaunchFile {
  std::string path;
  std::optional<int> domain;
  std::map<std::string, std::string> hosts;  // always holds localhost
  std::vector<LaunchNode> nodes;
};

// Parses a launch file's text; `stages` are the node stages there are. Throws
// InputError naming the file, line and field: YAML syntax, unknown fields, a node
// without name or stage, an unknown stage or host (with the nearest one), a name
// used twice, an address that is not IPv4, a domain out of range.
LaunchFile ParseLaunchFile(const std::string& text, const std::string& path, const std::vector<std::string>& stages);
LaunchFile LoadLaunchFile(const std::string& path, const std::vector<std::string>& stages);

struct LaunchOptions {
  std::string executable;  // the specht binary the nodes run
  std::string out_dir;     // <out_dir>/<node name> per node, report.json
  std::string host = "localhost";
  std::optional<int> domain;                        // overrides the file's
  std::vector<std::string> param_files, overrides;  // for every node, before its own
  double shutdown_timeout_s = 10;
  bool quiet = false;
};

// The arguments that start `node` (after the executable): node <stage> <args> -o
// <out>/<name> [--domain N] [-p FILE]… [--set K=V]… (the DDS addresses when the file
// spans hosts).
std::vector<std::string> NodeCommand(const LaunchFile& file, const LaunchNode& node, const LaunchOptions& options);

// Starts the nodes of options.host and supervises them until they end; writes
// <out_dir>/report.json. Returns 0 when every node ended with 0, 128 + the signal
// when a signal stopped the launch, else 1 (the report and the summary name the
// node). Throws InputError when options.host runs no node of the file.
int Launch(const LaunchFile& file, const LaunchOptions& options);

}  // namespace specht::net
