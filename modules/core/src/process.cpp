#include "specht/core/process.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <thread>

#include "specht/core/error.h"

namespace specht {
namespace {

int ExitCodeOf(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return WIFSIGNALED(status) ? 128 + WTERMSIG(status) : -1;
}

}  // namespace

ChildProcess::ChildProcess(const std::vector<std::string>& argv, const std::string& output_path) {
  if (argv.empty()) throw RuntimeError("child process: no program to run");
  std::vector<char*> args;
  for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  const int out_fd = open(output_path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (out_fd < 0) throw RuntimeError(output_path + ": cannot open for " + argv[0] + "'s output");
  const pid_t parent = getpid();
  start_ = std::chrono::steady_clock::now();
  pid_ = fork();
  if (pid_ == 0) {  // child: only async-signal-safe calls until exec
    setpgid(0, 0);
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(127);  // the parent died before the line above
    dup2(out_fd, 1);
    dup2(out_fd, 2);
    execvp(args[0], args.data());
    _exit(127);
  }
  close(out_fd);
  if (pid_ < 0) throw RuntimeError(std::string("child process: fork failed for ") + argv[0]);
  setpgid(pid_, pid_);  // also from the parent, so that a signal right after cannot miss the group
}

ChildProcess::~ChildProcess() {
  if (!Poll()) {
    kill(-pid_, SIGKILL);
    int status = 0;
    waitpid(pid_, &status, 0);
  }
}

std::optional<int> ChildProcess::Poll() {
  if (exit_code_) return exit_code_;
  int status = 0;
  if (waitpid(pid_, &status, WNOHANG) != pid_) return std::nullopt;
  end_ = std::chrono::steady_clock::now();
  exit_code_ = ExitCodeOf(status);
  return exit_code_;
}

void ChildProcess::Signal(int signal) {
  if (!Poll()) kill(-pid_, signal);
}

int ChildProcess::WaitOrKill(double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (!Poll() && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  if (!Poll()) {
    kill(-pid_, SIGKILL);
    int status = 0;
    waitpid(pid_, &status, 0);
    end_ = std::chrono::steady_clock::now();
    exit_code_ = ExitCodeOf(status);
  }
  return *exit_code_;
}

double ChildProcess::seconds() const {
  const auto end = exit_code_ ? end_ : std::chrono::steady_clock::now();
  return std::chrono::duration<double>(end - start_).count();
}

}  // namespace specht
