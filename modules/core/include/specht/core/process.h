// specht/core/process.h: a child process that stops with its parent.
//
// `tune` runs each evaluation, and `launch` each node, as a child process. The child
// runs in its own process group (so a signal to it reaches whatever it starts, and a
// Ctrl-C in the terminal reaches only the parent, which passes it on once), with
// stdout and stderr appended to a file. It is killed when the parent dies, even by a
// second Ctrl-C that gives the parent no time to clean up (PR_SET_PDEATHSIG): no
// orphan keeps running after the command that started it.
#pragma once

#include <sys/types.h>

#include <chrono>
#include <optional>
#include <string>
#include <vector>

namespace specht {

class ChildProcess {
 public:
  // Starts `argv` (argv[0] a path, or a name looked up in PATH) with stdout and stderr
  // appended to `output_path`. Throws RuntimeError when the file cannot be opened or
  // the fork fails; a program that cannot be executed exits 127.
  ChildProcess(const std::vector<std::string>& argv, const std::string& output_path);
  // Kills the group (SIGKILL) and reaps the child if it still runs.
  ~ChildProcess();
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;

  pid_t pid() const { return pid_; }
  // The exit code once the child ended (128 + the signal when a signal ended it);
  // never blocks.
  std::optional<int> Poll();
  // Sends `signal` to the child's process group (nothing once it ended).
  void Signal(int signal);
  // Waits up to `timeout_s` for the child to end; then kills the group and waits.
  // Returns the exit code.
  int WaitOrKill(double timeout_s);
  double seconds() const;  // since the start, or the start to the end once it ended

 private:
  pid_t pid_ = -1;
  std::optional<int> exit_code_;
  std::chrono::steady_clock::time_point start_, end_;
};

}  // namespace specht
