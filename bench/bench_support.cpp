#include "bench_support.h"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <iostream>
#include <thread>

namespace specht::bench {

nlohmann::json MachineNotes() {
  std::string cpu = "unknown";
  std::ifstream info("/proc/cpuinfo");
  for (std::string line; std::getline(info, line);) {
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  }
#ifdef NDEBUG
  const char* build = "release";
#else
  const char* build = "debug";
#endif
  return {{"cpu", cpu}, {"cores", std::thread::hardware_concurrency()}, {"build", build}};
}

void Emit(const nlohmann::json& result) { std::cout << result.dump() << std::endl; }

namespace {

// A benchmark given bad input (a missing dataset, a malformed log) throws, and an
// uncaught exception would end it with only "terminate called after throwing an
// instance of …". Every benchmark links this file: the reason is printed under the
// benchmark's name and it exits 2, as the apps do. (A terminate without an exception
// still aborts.)
[[noreturn]] void ReportUncaughtException() {
  if (const std::exception_ptr uncaught = std::current_exception()) {
    try {
      std::rethrow_exception(uncaught);
    } catch (const std::exception& e) {
      std::cerr << program_invocation_short_name << ": " << e.what() << std::endl;
    } catch (...) {
      std::cerr << program_invocation_short_name << ": stopped by an exception of unknown type" << std::endl;
    }
    std::_Exit(2);
  }
  std::abort();
}
const std::terminate_handler kPreviousHandler = std::set_terminate(ReportUncaughtException);

}  // namespace

}  // namespace specht::bench
