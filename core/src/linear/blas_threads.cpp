#include "linear/blas_threads.h"

#include <dlfcn.h>

#include <mutex>

namespace ricci::detail {

namespace {

using GetThreads = int (*)();
using SetThreads = void (*)(int);

// The guards alive in the process, and the count the first of them found: the count is the
// process's, so only the first guard sets it and only the last restores it (two meshes
// uniformized at once from two threads, as Python's threads may).
std::mutex held_mutex;
int held = 0;
int former = 0;  // 0: the first guard changed nothing

}  // namespace

SingleThreadedBlas::SingleThreadedBlas() {
  const std::lock_guard<std::mutex> lock(held_mutex);
  if (held++ > 0) return;
  const auto get = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  const auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  former = 0;
  if (get == nullptr || set == nullptr) return;
  const int threads = get();
  if (threads <= 1) return;
  former = threads;
  set(1);
}

SingleThreadedBlas::~SingleThreadedBlas() {
  const std::lock_guard<std::mutex> lock(held_mutex);
  if (--held > 0 || former <= 1) return;
  const auto set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  if (set != nullptr) set(former);
  former = 0;
}

}  // namespace ricci::detail
