// The BLAS's own threads held to one while the caller keeps the cores busy itself.
#pragma once

namespace ricci::detail {

// While it lives, a multithreaded OpenBLAS (the one CHOLMOD's dense kernels call, found by its
// symbols at run time) runs each call on the calling thread; its former count comes back after.
// Where the components of a mesh are uniformized two at a time, both cores are busy: OpenBLAS's
// threads then only wait for work, spinning (on gymnasium's Adroit forearm plate assembly, 218
// parts on two cores: the system time 1.1 s to 0.6 s, the whole command about 6 % faster).
// Without OpenBLAS (another BLAS, or a static one), nothing.
class SingleThreadedBlas {
 public:
  SingleThreadedBlas();
  ~SingleThreadedBlas();
  SingleThreadedBlas(const SingleThreadedBlas&) = delete;
  SingleThreadedBlas& operator=(const SingleThreadedBlas&) = delete;

 private:
  int former_ = 0;  // the count to restore; 0: none was changed
};

}  // namespace ricci::detail
