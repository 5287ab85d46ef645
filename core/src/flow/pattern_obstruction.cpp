#include "flow/pattern_obstruction.h"

#include <cmath>
#include <sstream>
#include <vector>

namespace ricci {

namespace {

bool is_intersection_angle(double eta) {
  return eta >= 0 && eta <= 1;
}

}  // namespace

std::string circle_pattern_obstruction(const Triangulation& mesh,
                                       const ConformalStructure& structure,
                                       const TargetCurvature& target) {
  const int n = mesh.num_vertices();
  // Per vertex: the bound sum (pi - Phi_ab), and whether every circle and angle around it
  // qualifies (eps = +1, 0 <= eta <= 1 on the spokes and the link).
  std::vector<double> bound(n, 0);
  std::vector<char> qualifies(n, 1);
  std::vector<int> degree(n, 0);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const int v = mesh.face_vertex(f, c);
      const double eta_link = structure.eta[mesh.face_edge(f, c)];
      const double eta_1 = structure.eta[mesh.face_edge(f, (c + 1) % 3)];
      const double eta_2 = structure.eta[mesh.face_edge(f, (c + 2) % 3)];
      if (structure.eps[v] != 1 || structure.eps[mesh.face_vertex(f, (c + 1) % 3)] != 1 ||
          structure.eps[mesh.face_vertex(f, (c + 2) % 3)] != 1 ||
          !is_intersection_angle(eta_link) || !is_intersection_angle(eta_1) ||
          !is_intersection_angle(eta_2)) {
        qualifies[v] = 0;
      }
      bound[v] += M_PI - std::acos(eta_link);
      ++degree[v];
    }
  }
  int first = -1, count = 0;
  double first_needed = 0;
  for (int v = 0; v < n; ++v) {
    if (!qualifies[v] || target.is_fixed(v)) continue;
    const double needed = (mesh.is_boundary_vertex(v) ? M_PI : 2 * M_PI) - target.curvature[v];
    if (needed < bound[v] - 1e-12) continue;
    if (first < 0) first = v, first_needed = needed;
    ++count;
  }
  if (first < 0) return "";
  const double degrees = 180 / M_PI;
  std::ostringstream s;
  s.precision(4);
  s << "no circle pattern with these intersection angles exists: vertex " << first << " (degree "
    << degree[first] << (mesh.is_boundary_vertex(first) ? ", boundary" : "")
    << ") needs an angle sum of " << first_needed * degrees
    << " deg, but its angles stay below the sum of (180 deg - Phi) over the edges of its link, "
    << bound[first] * degrees << " deg, the limit as its circle shrinks to a point (Thurston's "
    << "condition; " << count << " vertices fail it)";
  if (bound[first] >= degree[first] * M_PI - 1e-12) {
    // Phi = 0 on every edge of its link already (tangential packing).
    s << "; its circles already touch, so only more faces around it (a finer triangulation "
         "there) reach that angle sum";
  } else {
    s << "; lower the intersection angle (a degree-3 vertex needs Phi < 60 deg, degree 4 Phi < "
         "90 deg), or use the tangential scheme";
  }
  return s.str();
}

}  // namespace ricci
