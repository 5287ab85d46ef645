#include "ricci/repair/repair_report.h"

#include <sstream>

#include "mesh/mesh_checks.h"

namespace ricci {

std::vector<std::string> RepairReport::lines() const {
  std::vector<std::string> out;
  for (const Entry& e : entries) {
    std::ostringstream s;
    s << e.count << " " << e.what;
    if (!e.first.empty()) s << " (" << detail::first_indices(e.element, e.first) << ")";
    out.push_back(s.str());
  }
  return out;
}

}  // namespace ricci
