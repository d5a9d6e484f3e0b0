#include "test_support.h"

#include <mrpt/io/CFileGZInputStream.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace specht::testing {

namespace {

std::string EnvOr(const char* name, const char* fallback) {
  const char* v = std::getenv(name);
  return v != nullptr && *v != '\0' ? std::string(v) : std::string(fallback);
}

// This process's scratch root: every TempDir() lies below it.
fs::path ProcessTempRoot() { return fs::path(::testing::TempDir()) / ("specht-" + std::to_string(getpid())); }

// Removes the process's scratch root when every test passed, so that a suite run
// (ctest starts one process per test) leaves nothing behind; a failing run keeps
// its files for inspection, as does SPECHT_KEEP_TEST_FILES=1.
class TempRootCleanup : public ::testing::Environment {
 public:
  void TearDown() override {
    const fs::path root = ProcessTempRoot();
    if (!fs::exists(root)) return;
    if (::testing::UnitTest::GetInstance()->Passed() && EnvOr("SPECHT_KEEP_TEST_FILES", "").empty()) {
      std::error_code ignored;
      fs::remove_all(root, ignored);
    } else {
      std::fprintf(stderr, "test files kept in %s\n", root.c_str());
    }
  }
};

// gtest_main runs RUN_ALL_TESTS; an environment registered during static
// initialisation takes part (the registration gtest documents for that case).
[[maybe_unused]] ::testing::Environment* const kTempRootCleanup =
    ::testing::AddGlobalTestEnvironment(new TempRootCleanup);

}  // namespace

std::string DataDir() {
  const std::string d = EnvOr("SPECHT_DATA_DIR", SPECHT_DEFAULT_DATA_DIR);
  return fs::is_directory(d) ? d : std::string();
}

std::string SourceDir() { return EnvOr("SPECHT_SOURCE_DIR", SPECHT_DEFAULT_SOURCE_DIR); }

std::string BuiltInRawlog() {
  const std::string p = "/usr/share/mrpt/datasets/2006-01ENE-21-SENA_Telecom Faculty_one_loop_only.rawlog";
  return fs::exists(p) ? p : std::string();
}

std::string MrptDemoDir() {
  const std::string p = "/usr/share/mrpt/datasets/graphslam-engine-demos/action_observations_map";
  return fs::is_directory(p) ? p : std::string();
}

std::string TempDir(const std::string& suffix) {
  const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string name = std::string(info->test_suite_name()) + "." + info->name() + suffix;
  const fs::path dir = ProcessTempRoot() / name;
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir.string();
}

namespace {

// The shell command running the binary with `args`, its output into `out` and `err`.
std::string SpechtCommand(const std::string& args, const std::string& out, const std::string& err) {
  const std::string bin = EnvOr("SPECHT_BINARY", SPECHT_DEFAULT_BINARY);
  return "'" + bin + "' " + args + " >'" + out + "' 2>'" + err + "' </dev/null";
}

}  // namespace

CommandResult RunSpecht(const std::string& args) {
  CommandResult r;
  const std::string dir = TempDir("-cmd");
  const std::string out = dir + "/stdout", err = dir + "/stderr";
  const int status = std::system(SpechtCommand(args, out, err).c_str());
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = ReadFile(out);
  r.err = ReadFile(err);
  return r;
}

BackgroundSpecht::BackgroundSpecht(const std::string& args) {
  static int started = 0;  // each background process its own output files
  const std::string dir = TempDir("-bg" + std::to_string(++started));
  out_ = dir + "/stdout", err_ = dir + "/stderr";
  // `exec`: the shell becomes specht, so the signals go to it.
  const std::string cmd = "exec " + SpechtCommand(args, out_, err_);
  pid_ = fork();
  if (pid_ == 0) {
    execl("/bin/sh", "sh", "-c", cmd.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
}

BackgroundSpecht::~BackgroundSpecht() {
  if (pid_ > 0) {
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
  }
}

void BackgroundSpecht::Signal(int signal) {
  if (pid_ > 0) kill(pid_, signal);
}

bool BackgroundSpecht::WaitForFile(const std::string& path, double timeout_s) {
  for (double waited = 0; waited < timeout_s; waited += 0.05) {
    if (std::filesystem::exists(path)) return true;
    siginfo_t info{};
    if (pid_ <= 0 || waitid(P_PID, pid_, &info, WEXITED | WNOHANG | WNOWAIT) != 0 || info.si_pid != 0)
      return std::filesystem::exists(path);  // it ended
    usleep(50000);
  }
  return std::filesystem::exists(path);
}

CommandResult BackgroundSpecht::Wait() {
  CommandResult r;
  int status = 0;
  if (pid_ > 0 && waitpid(pid_, &status, 0) == pid_)
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  pid_ = -1;
  r.out = ReadFile(out_);
  r.err = ReadFile(err_);
  return r;
}

bool DataRequired() {
  const char* v = std::getenv("SPECHT_REQUIRE_DATA");
  return v != nullptr && std::string(v) == "1";
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void WriteFile(const std::string& path, const std::string& bytes) {
  std::ofstream out(path, std::ios::binary);
  out << bytes;
}

std::string ReadDecompressed(const std::string& path) {
  mrpt::io::CFileGZInputStream in(path);
  std::string bytes;
  char buf[65536];
  size_t n = 0;
  while ((n = in.Read(buf, sizeof(buf))) > 0) bytes.append(buf, n);
  return bytes;
}

}  // namespace specht::testing
