// A fill-reducing order of a mesh's vertices, found ahead of the flow on a thread of its own.
//
// The flow's sparse systems have one row per free vertex, with the mesh's edges as their pattern.
// At a million faces the nested dissection ordering of that pattern (METIS) takes longer than two
// numeric factorizations of it. The vertex graph is known as soon as the faces are read, so the
// ordering can run while the mesh is repaired and the flow set up; every Hessian pattern of the
// flow on the mesh's own triangulation (any set of free vertices) is then analysed in this order,
// restricted to its rows. Not after edge flips: the 1.07M-face lion head's 316,933 Delaunay flips
// made every factorization in the input's order 13 times slower than in the flipped pattern's own.
#pragma once

#include <array>
#include <functional>
#include <future>
#include <memory>
#include <mutex>
#include <vector>

namespace ricci {

//! From this many rows on, a system's fill-reducing ordering is METIS's nested dissection alone
//! (measured on lion-head.off's subdivisions: at 133k rows CHOLMOD's default keeps AMD's ordering,
//! at 534k it goes on to METIS), and an order found ahead (VertexOrder) is used instead where
//! there is one.
inline constexpr int kNestedDissectionRows = 300000;

class VertexOrder {
 public:
  VertexOrder() = default;  //!< none: each system is ordered by its own analysis

  //! Starts ordering the graph of the faces' edges over num_vertices vertices (METIS's nested
  //! dissection, through CHOLMOD) on another thread; faces with an index out of range or a
  //! repeated index are left out. Below from_vertices vertices, or where no thread can be
  //! started: none (the orderings of smaller systems are quick, and CHOLMOD's default choice is
  //! better there). Destroying the last copy of the result waits for the thread to finish.
  //! `finally` runs on that thread once the ordering is done (the command returns the memory the
  //! thread freed to the system there).
  static VertexOrder start(int num_vertices, const std::vector<std::array<int, 3>>& faces,
                           int from_vertices = kNestedDissectionRows,
                           std::function<void()> finally = {});

  //! The order for a mesh whose vertex v is this one's vertex from[v] (a component of a repaired
  //! mesh; vertices split into copies share their rank, and keep their own order among them).
  //! None when some from[v] is not a vertex of this one.
  VertexOrder restricted(std::vector<int> from) const;

  bool empty() const { return !rank_.valid(); }
  //! The number of vertices of the mesh this order is for (0 when empty).
  int num_vertices() const;
  //! Per vertex, its place in the order (copies of a vertex share it); waits until the ordering
  //! is done. Empty when METIS failed; rethrows what the ordering's thread threw. \pre !empty()
  std::vector<int> ranks() const;
  //! The rows of a system whose row for vertex v is row_of_vertex[v] (-1: none), listed in this
  //! order (copies of a vertex, which share their rank, by vertex index): the permutation a
  //! LinearSolver analysis takes. Waits until the ordering is done. Empty for no order, when
  //! row_of_vertex is not one entry per vertex, or when the ordering failed (METIS, its thread).
  std::vector<int> rows(const std::vector<int>& row_of_vertex) const;

 private:
  std::shared_future<std::vector<int>> rank_;  // per ordered vertex
  std::shared_ptr<const std::vector<int>> from_;
  int num_ordered_ = 0;
};

namespace detail {
//! Held around every call into METIS: it draws from libc's one rand() state, so two orderings at
//! once would each depend on the other's timing. (Other users of rand() in the process, none in
//! this project, could still move an ordering running in the background.)
std::mutex& nested_dissection_mutex();
}  // namespace detail

}  // namespace ricci
