// A scope in which no new thread can be made, as in a process at its limit of threads or of
// address space: every new thread's default stack is set larger than the machine maps, so
// std::thread and std::async throw std::system_error. Threads made before keep running.
#pragma once

#include <pthread.h>

#include <cstddef>

namespace ricci::test {

class NoNewThreads {
 public:
  NoNewThreads() {
    pthread_getattr_default_np(&saved_);
    pthread_attr_t huge;
    pthread_attr_init(&huge);
    pthread_attr_setstacksize(&huge, std::size_t{1} << 46);  // 64 TiB
    pthread_setattr_default_np(&huge);
    pthread_attr_destroy(&huge);
  }
  ~NoNewThreads() {
    pthread_setattr_default_np(&saved_);
    pthread_attr_destroy(&saved_);
  }
  NoNewThreads(const NoNewThreads&) = delete;
  NoNewThreads& operator=(const NoNewThreads&) = delete;

 private:
  pthread_attr_t saved_;
};

}  // namespace ricci::test
