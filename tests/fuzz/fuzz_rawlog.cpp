// MRPT rawlogs (io/dataset.h, the rawlog source): every record read or rejected.
//
// MRPT's deserializer sizes strings and containers from a record's counts before it
// reads them. A count no memory can hold makes the release build's operator new throw
// std::bad_alloc, which the reader reports as a corrupt record; under ASan the same
// count is fatal (its operator new reports out-of-memory instead of throwing), and each
// such input ended a fork-mode job and cost a restart. Here operator new throws as the
// release build's does, for any request past a bound no record of a few kilobytes
// honestly needs. ASan still checks every access; the pairing of new with delete it
// no longer sees here, the unit tests' ASan build does. MRPT's own aligned allocator
// (scan ranges, dynamic vectors) goes to malloc, not operator new: a count too large
// for it stays fatal here, counted by scripts/fuzz.sh as an unallocatable count.
#include <cstdlib>
#include <new>

#include "fuzz_support.h"
#include "specht/io/dataset.h"

namespace {

// Past this, a request comes from a corrupt count: fail it as an exhausted heap does.
constexpr std::size_t kLargestRequest = std::size_t{256} << 20;

// Null where an exhausted heap would refuse.
void* TryAllocate(std::size_t n) { return n <= kLargestRequest ? std::malloc(n == 0 ? 1 : n) : nullptr; }

void* Allocate(std::size_t n) {
  if (void* p = TryAllocate(n)) return p;
  throw std::bad_alloc();
}

void* AllocateAligned(std::size_t n, std::align_val_t align) {
  void* p = nullptr;
  if (n <= kLargestRequest && posix_memalign(&p, static_cast<std::size_t>(align), n == 0 ? 1 : n) == 0) return p;
  throw std::bad_alloc();
}

}  // namespace

void* operator new(std::size_t n) { return Allocate(n); }
void* operator new[](std::size_t n) { return Allocate(n); }
void* operator new(std::size_t n, std::align_val_t a) { return AllocateAligned(n, a); }
void* operator new[](std::size_t n, std::align_val_t a) { return AllocateAligned(n, a); }
void* operator new(std::size_t n, const std::nothrow_t&) noexcept { return TryAllocate(n); }
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept { return TryAllocate(n); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete[](void* p, const std::nothrow_t&) noexcept { std::free(p); }

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = specht::fuzz::InputFile(data, size, "input.rawlog");
  specht::fuzz::Expect([&] {
    auto source = specht::io::OpenDataset(path, specht::io::OnBadRecord::kSkip);
    while (source->Next()) {
    }
  });
  return 0;
}
