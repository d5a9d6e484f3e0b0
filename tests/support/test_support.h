// tests/support/test_support.h: what the suites share: where data and the binary
// are, temporary directories, running the CLI, and reading files.
#pragma once

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <string>

namespace specht::testing {

// The evaluation data ($SPECHT_DATA_DIR, else ../shared/data as configured) if it
// is a directory, else "" (tests then skip).
std::string DataDir();
// The source tree ($SPECHT_SOURCE_DIR).
std::string SourceDir();
// The built-in rawlog from Debian's mrpt-common, or "" when not installed.
std::string BuiltInRawlog();
// MRPT's simulated rawlogs with ground truth (graphslam-engine-demos).
std::string MrptDemoDir();

// A fresh empty directory under the test temp dir, named after the running test.
// The process's directories are removed when all its tests pass (kept on failure
// or with SPECHT_KEEP_TEST_FILES=1).
std::string TempDir(const std::string& suffix = "");

struct CommandResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};
// Runs the specht binary (as built, or $SPECHT_BINARY) with the given arguments
// (shell-quoted by the caller).
CommandResult RunSpecht(const std::string& args);

// The specht binary started in the background (for tests of signals): Signal() it
// part-way, then Wait() for its exit code and output. The destructor kills it if
// it still runs.
class BackgroundSpecht {
 public:
  explicit BackgroundSpecht(const std::string& args);
  ~BackgroundSpecht();
  BackgroundSpecht(const BackgroundSpecht&) = delete;
  BackgroundSpecht& operator=(const BackgroundSpecht&) = delete;
  void Signal(int signal);
  // Waits until `path` exists or the process ended (at most `timeout_s`); true if it exists.
  bool WaitForFile(const std::string& path, double timeout_s);
  // The exit code (128 + the signal when a signal ended it), stdout and stderr.
  CommandResult Wait();

 private:
  int pid_ = -1;
  std::string out_, err_;
};

std::string ReadFile(const std::string& path);
void WriteFile(const std::string& path, const std::string& bytes);
// The decompressed bytes of a (possibly gzip) file.
std::string ReadDecompressed(const std::string& path);

// True when SPECHT_REQUIRE_DATA=1 (set by .ci/run): a test whose input is missing
// then fails instead of skipping, so a misplaced data directory cannot pass CI.
bool DataRequired();

}  // namespace specht::testing

// Skips the test for missing input (stream the reason into it), or fails it when
// the input is required (DataRequired). One statement, as gtest's own FAIL() and
// GTEST_SKIP() expand to, so `if (...) SPECHT_SKIP() << ...;` needs no braces.
#define SPECHT_SKIP()                                                                                                \
  return ::testing::internal::AssertHelper(                                                                          \
             ::specht::testing::DataRequired() ? ::testing::TestPartResult::kFatalFailure                            \
                                               : ::testing::TestPartResult::kSkip,                                   \
             __FILE__, __LINE__, ::specht::testing::DataRequired() ? "input missing (SPECHT_REQUIRE_DATA=1)" : "") = \
             ::testing::Message()

#define SPECHT_REQUIRE_FILE(path)                      \
  do {                                                 \
    if ((path).empty()) {                              \
      SPECHT_SKIP() << "test data not available here"; \
    }                                                  \
  } while (0)
