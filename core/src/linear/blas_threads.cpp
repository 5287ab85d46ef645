#include "linear/blas_threads.h"

#include <dlfcn.h>

namespace ricci::detail {

namespace {

using GetThreads = int (*)();
using SetThreads = void (*)(int);

// OpenBLAS's thread count calls, where the process has them.
struct OpenBlasThreads {
  GetThreads get = nullptr;
  SetThreads set = nullptr;
};

OpenBlasThreads open_blas_threads() {
  OpenBlasThreads t;
  t.get = reinterpret_cast<GetThreads>(dlsym(RTLD_DEFAULT, "openblas_get_num_threads"));
  t.set = reinterpret_cast<SetThreads>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads"));
  return t;
}

}  // namespace

SingleThreadedBlas::SingleThreadedBlas() {
  const OpenBlasThreads t = open_blas_threads();
  if (t.get == nullptr || t.set == nullptr) return;
  const int threads = t.get();
  if (threads <= 1) return;
  former_ = threads;
  t.set(1);
}

SingleThreadedBlas::~SingleThreadedBlas() {
  if (former_ <= 1) return;
  const OpenBlasThreads t = open_blas_threads();
  if (t.set != nullptr) t.set(former_);
}

}  // namespace ricci::detail
