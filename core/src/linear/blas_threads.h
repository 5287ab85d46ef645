// The BLAS's own threads held to one while the caller keeps the cores busy itself.
#pragma once

namespace ricci::detail {

// While one lives, a multithreaded OpenBLAS (the one CHOLMOD's dense kernels call, found by its
// symbols at run time) runs each call on the calling thread; its former count comes back when the
// last one alive ends (the count is the process's: guards on several threads share it). Where the
// components of a mesh are uniformized two at a time, both cores are busy: OpenBLAS's threads
// then only wait for work, spinning (on gymnasium's Adroit forearm plate assembly, 218 parts on
// two cores: the system time 1.1 s to 0.6 s, the whole command about 5 % faster). Without
// OpenBLAS (another BLAS, a static one) nothing; with OpenBLAS built for OpenMP, the count of the
// thread that made the guard only. Made where no other thread of the caller's is inside BLAS.
class SingleThreadedBlas {
 public:
  SingleThreadedBlas();
  ~SingleThreadedBlas();
  SingleThreadedBlas(const SingleThreadedBlas&) = delete;
  SingleThreadedBlas& operator=(const SingleThreadedBlas&) = delete;
};

}  // namespace ricci::detail
