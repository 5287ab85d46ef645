// A scope in which no new thread of the process's own can be made, as in a process at its limit of
// threads or of address space: every new thread's default stack is set larger than any address
// space, so std::thread and std::async throw std::system_error. Threads made before keep running
// (OpenMP's, which CHOLMOD starts at its first parallel factorization: where libgomp cannot make
// them it ends the process).
#pragma once

#include <pthread.h>

#include <cstddef>

namespace ricci::test {

class NoNewThreads {
 public:
  NoNewThreads() {
    if (pthread_getattr_default_np(&saved_) != 0) return;
    pthread_attr_t huge;
    pthread_attr_init(&huge);
    held_ = pthread_attr_setstacksize(&huge, std::size_t{1} << 62) == 0 &&
            pthread_setattr_default_np(&huge) == 0;
    pthread_attr_destroy(&huge);
    if (!held_) pthread_attr_destroy(&saved_);
  }
  ~NoNewThreads() {
    if (!held_) return;
    pthread_setattr_default_np(&saved_);
    pthread_attr_destroy(&saved_);
  }
  NoNewThreads(const NoNewThreads&) = delete;
  NoNewThreads& operator=(const NoNewThreads&) = delete;

  //! Whether the default stack was set (the tests assert that a thread then fails to start).
  bool held() const { return held_; }

 private:
  pthread_attr_t saved_;
  bool held_ = false;
};

}  // namespace ricci::test
