// Child processes (core/process.h): exit codes, output, signals to the group, and no
// orphan once the parent is gone.
#include "specht/core/process.h"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <thread>

#include "test_support.h"

namespace specht {
namespace {

bool Alive(pid_t pid) {  // running, not a zombie waiting to be reaped
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string pid_field, name, state;
  return stat >> pid_field >> name >> state && state != "Z" && state != "X";
}

TEST(ChildProcessTest, ExitCodeAndOutput) {
  const std::string log = testing::TempDir("process") + "/out.log";
  ChildProcess child({"sh", "-c", "echo out; echo err >&2; exit 3"}, log);
  EXPECT_EQ(child.WaitOrKill(10), 3);
  EXPECT_EQ(testing::ReadFile(log), "out\nerr\n");
  ChildProcess missing({"/no/such/program"}, log);
  EXPECT_EQ(missing.WaitOrKill(10), 127);
}

TEST(ChildProcessTest, SignalReachesTheGroupAndWaitOrKillEnds) {
  const std::string log = testing::TempDir("process_signal") + "/out.log";
  ChildProcess child({"sleep", "30"}, log);
  EXPECT_FALSE(child.Poll());
  child.Signal(SIGTERM);
  EXPECT_EQ(child.WaitOrKill(10), 128 + SIGTERM);
  ChildProcess stubborn({"sh", "-c", "trap '' INT; sleep 30"}, log);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  stubborn.Signal(SIGINT);
  EXPECT_EQ(stubborn.WaitOrKill(0.3), 128 + SIGKILL);
  EXPECT_LT(stubborn.seconds(), 5);
}

TEST(ChildProcessTest, ChildDiesWithItsParent) {
  const std::string log = testing::TempDir("process_orphan") + "/out.log";
  int fds[2];
  ASSERT_EQ(pipe(fds), 0);
  const pid_t parent = fork();
  if (parent == 0) {  // a parent that dies without cleaning up (as on a second Ctrl-C)
    auto* child = new ChildProcess({"sleep", "30"}, log);
    const pid_t pid = child->pid();
    (void)!write(fds[1], &pid, sizeof(pid));
    _exit(0);
  }
  pid_t child = -1;
  ASSERT_EQ(read(fds[0], &child, sizeof(child)), static_cast<ssize_t>(sizeof(child)));
  waitpid(parent, nullptr, 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (Alive(child) && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_FALSE(Alive(child));
  close(fds[0]);
  close(fds[1]);
}

}  // namespace
}  // namespace specht
