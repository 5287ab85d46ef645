// What a repair changed, as counts and first indices per kind of change (repair.h).
#pragma once

#include <string>
#include <vector>

namespace ricci {

//! What a repair changed: one entry per kind, with the count and the first input indices.
struct RepairReport {
  struct Entry {
    std::string what;     //!< e.g. "duplicate faces dropped"
    std::string element;  //!< "face", "vertex" or "edge"
    int count = 0;
    std::vector<int> first;  //!< up to three input indices (an edge as its first vertex)
  };
  std::vector<Entry> entries;  //!< only the kinds that happened

  bool empty() const { return entries.empty(); }
  //! "3 duplicate faces dropped (first: face 7, face 9, face 12)", one line per entry.
  std::vector<std::string> lines() const;
};

}  // namespace ricci
