// Loops whose iterations are independent, on the machine's second core when they are long enough
// to pay for a thread. Each half's results go to slots of their own, so nothing depends on the
// threads' timing. Where no thread can be made (std::system_error: a process at its limit of
// threads or of address space), this thread runs both halves, one after the other. (CHOLMOD's
// factorization starts OpenMP threads of its own; where libgomp cannot make them it ends the
// process, which OMP_THREAD_LIMIT=1 in the environment avoids.) Not installed API.
#pragma once

#include <exception>
#include <optional>
#include <system_error>
#include <thread>

namespace ricci::detail {

//! Below this many iterations one thread runs them all (a thread costs some 0.1 ms).
inline constexpr int kTwoThreadsFromIterations = 50000;

//! work(part, begin, end) for part 0 on [0, n / 2) and part 1 on [n / 2, n), on two threads; for
//! loops shorter than `from` part 0 on [0, n) and part 1 on the empty [n, n), on this one.
template <class Work>
void in_two_halves(int n, const Work& work, int from = kTwoThreadsFromIterations) {
  if (n < from) {
    work(0, 0, n);
    work(1, n, n);
    return;
  }
  const int middle = n / 2;
  // An exception of either half (bad_alloc) is thrown here once both have ended, not left to
  // terminate the process from a joinable thread.
  std::exception_ptr failed[2];
  const auto second_half = [&] {
    try {
      work(1, middle, n);
    } catch (...) {
      failed[1] = std::current_exception();
    }
  };
  std::optional<std::thread> other;
  try {
    other.emplace(second_half);
  } catch (const std::system_error&) {  // no second thread: this one runs it after the first half
  }
  try {
    work(0, 0, middle);
  } catch (...) {
    failed[0] = std::current_exception();
  }
  if (other) {
    other->join();
  } else {
    second_half();
  }
  for (const std::exception_ptr& e : failed) {
    if (e) std::rethrow_exception(e);
  }
}

//! first() and second(), on two threads where `two_threads` (and a thread can be made), else one
//! after the other on this one. An exception is thrown here: where `two_threads` once both have
//! run, else as it happens (an exception of first() leaves second() not run).
template <class First, class Second>
void both(const First& first, const Second& second, bool two_threads) {
  in_two_halves(
      2, [&](int part, int, int) { part == 0 ? first() : second(); }, two_threads ? 0 : 3);
}

}  // namespace ricci::detail
