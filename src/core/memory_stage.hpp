// What drape was doing when memory ran out, for the one line it then ends with ("drape: out of memory
// while building the cpu solver for 4194304 points") instead of "std::bad_alloc". Each stage that
// allocates in proportion to its input names itself with a MemoryStage for its duration; when operator
// new fails, the innermost name is copied aside (without allocating) before std::bad_alloc is thrown.
#pragma once

#include <string>

namespace drape {

class MemoryStage {
 public:
  explicit MemoryStage(std::string what);
  ~MemoryStage();
  MemoryStage(const MemoryStage&) = delete;
  MemoryStage& operator=(const MemoryStage&) = delete;
};

// Installs the new-handler that records the stage (main calls it first).
void recordStagesOfFailedAllocations();

// Records this thread's stage and throws std::bad_alloc: for an allocation that failed on another thread
// (an OpenMP worker, whose own stages are empty) and was caught there.
[[noreturn]] void failAllocation();

// The stage the last failed allocation happened in ("" if none was named), and the process's limit on
// its address space ("" without one): what the out-of-memory line says.
std::string failedAllocationStage();
std::string addressSpaceLimit();

}  // namespace drape
