// Typed errors of the Ricci flow library. Every message names the function or
// stage, the fact that was wrong, where (counts, first indices), and what to do.
#pragma once

#include <new>
#include <stdexcept>
#include <string>

namespace ricci {

//! Base of every error the library throws.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

//! The mesh cannot be used: non-manifold, several components, degenerate faces, ...
class InvalidMeshError : public Error {
 public:
  using Error::Error;
};

//! A caller-supplied value is out of range: options, eps, per-vertex arrays.
class InvalidArgumentError : public Error {
 public:
  using Error::Error;
};

//! The target curvature admits no solution (Gauss-Bonnet, Kbar >= 2 pi, geometry vs topology).
class InvalidTargetError : public Error {
 public:
  using Error::Error;
};

//! The flow stopped without reaching the tolerance (iteration limit, degenerate triangles).
class ConvergenceError : public Error {
 public:
  ConvergenceError(const std::string& message, int iterations, double residual)
      : Error(message), iterations_(iterations), residual_(residual) {}
  int iterations() const { return iterations_; }
  double residual() const { return residual_; }

 private:
  int iterations_;
  double residual_;
};

//! The flow converged but its layout is not a valid map: faces turned over, boundary loops off
//! their circles.
class LayoutError : public Error {
 public:
  using Error::Error;
};

//! A sparse factorization failed in a way that step control cannot recover from.
class SolverError : public Error {
 public:
  using Error::Error;
};

//! A file could not be read or written.
class IoError : public Error {
 public:
  using Error::Error;
};

//! What a front end says of an exception that ended a run: its message, or, for std::bad_alloc
//! (whose message is its type's name), that the process ran out of memory.
inline std::string failure_message(const std::exception& e) {
  if (dynamic_cast<const std::bad_alloc*>(&e)) {
    return "out of memory: the process could not allocate what this mesh needs (the machine's "
           "memory, or a limit on the process's address space such as ulimit -v)";
  }
  return e.what();
}

}  // namespace ricci
