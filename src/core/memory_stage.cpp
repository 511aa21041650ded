#include "core/memory_stage.hpp"

#include "core/input_file.hpp"

#include <sys/resource.h>

#include <cstring>
#include <new>
#include <vector>

namespace drape {

namespace {

// Per thread, innermost last. Names are made before the work they name, so naming costs nothing when
// memory runs out.
thread_local std::vector<std::string> stages;

// Written by the new-handler, which must not allocate: a fixed buffer.
char failed_stage[256] = "";

// A worker thread (OpenMP) has no stages of its own: its failure is named again by the thread it works for
// (failAllocation).
[[noreturn]] void recordStage() {
  if (!stages.empty()) {
    std::strncpy(failed_stage, stages.back().c_str(), sizeof failed_stage - 1);
    failed_stage[sizeof failed_stage - 1] = '\0';
  }
  throw std::bad_alloc();
}

}  // namespace

void failAllocation() {
  recordStage();
}

MemoryStage::MemoryStage(std::string what) {
  stages.push_back(std::move(what));
}

MemoryStage::~MemoryStage() {
  stages.pop_back();
}

void recordStagesOfFailedAllocations() {
  std::set_new_handler(recordStage);
}

std::string failedAllocationStage() {
  return failed_stage;
}

std::string addressSpaceLimit() {
  struct rlimit limit {};
  if (::getrlimit(RLIMIT_AS, &limit) != 0 || limit.rlim_cur == RLIM_INFINITY) return "";
  return describeBytes((long long)limit.rlim_cur);
}

}  // namespace drape
