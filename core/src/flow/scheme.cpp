#include "ricci/flow/scheme.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "ricci/mesh/errors.h"

namespace ricci {

namespace {

double median(std::vector<double> values) {
  const size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<long>(mid), values.end());
  return values[mid];
}

// Incident edge lengths of every vertex.
std::vector<std::vector<double>> incident_lengths(const CompactMesh& mesh,
                                                  const std::vector<double>& length) {
  std::vector<std::vector<double>> incident(mesh.num_vertices());
  for (int e = 0; e < mesh.num_edges(); ++e) {
    for (int v : mesh.edge_vertices(e)) incident[v].push_back(length[e]);
  }
  return incident;
}

// Mean over incident faces of the tangent length s - l_i from corner i to the incircle:
// the radii of the tangential packing closest to the input triangles.
std::vector<double> incircle_tangent_radii(const CompactMesh& mesh,
                                           const std::vector<double>& length) {
  std::vector<double> sum(mesh.num_vertices(), 0.0);
  std::vector<int> count(mesh.num_vertices(), 0);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const double l0 = length[mesh.face_edge(f, 0)], l1 = length[mesh.face_edge(f, 1)],
                 l2 = length[mesh.face_edge(f, 2)];
    const double s = (l0 + l1 + l2) / 2;
    const double opposite[3] = {l0, l1, l2};
    for (int c = 0; c < 3; ++c) {
      sum[mesh.face_vertex(f, c)] += s - opposite[c];
      ++count[mesh.face_vertex(f, c)];
    }
  }
  for (int v = 0; v < mesh.num_vertices(); ++v) sum[v] /= count[v];
  return sum;
}

}  // namespace

std::string to_string(Scheme s) {
  switch (s) {
    case Scheme::Tangential:
      return "tangential";
    case Scheme::Thurston:
      return "thurston";
    case Scheme::InversiveDistance:
      return "inversive-distance";
    case Scheme::Yamabe:
      return "yamabe";
    case Scheme::VirtualRadius:
      return "virtual-radius";
    case Scheme::Mixed:
      return "mixed";
  }
  return "unknown";
}

Scheme scheme_from_string(const std::string& name) {
  for (Scheme s : {Scheme::Tangential, Scheme::Thurston, Scheme::InversiveDistance, Scheme::Yamabe,
                   Scheme::VirtualRadius, Scheme::Mixed}) {
    if (to_string(s) == name) return s;
  }
  throw InvalidArgumentError("scheme: unknown scheme '" + name +
                             "'; use tangential, thurston, inversive-distance, yamabe, "
                             "virtual-radius or mixed");
}

bool reproduces_input_lengths(Scheme s) {
  return s != Scheme::Tangential && s != Scheme::Thurston;
}

void check_scheme_options(const SchemeOptions& options) {
  if (options.scheme == Scheme::Thurston &&
      !(options.intersection_angle >= 0 && options.intersection_angle <= kPi / 2 + 1e-12)) {
    std::ostringstream s;
    s << "thurston scheme: intersection angle " << options.intersection_angle * 180 / kPi
      << " degrees is outside [0, 90]";
    throw InvalidArgumentError(s.str());
  }
  if (!(options.virtual_radius_fraction > 0)) {
    throw InvalidArgumentError("scheme options: virtual_radius_fraction must be positive");
  }
  for (size_t v = 0; v < options.eps.size(); ++v) {
    if (options.eps[v] < -1 || options.eps[v] > 1) {
      throw InvalidArgumentError("mixed scheme: eps of vertex " + std::to_string(v) + " is " +
                                 std::to_string(options.eps[v]) + "; it must be +1, 0 or -1");
    }
  }
}

bool is_yamabe(const ConformalStructure& structure) {
  return std::all_of(structure.eps.begin(), structure.eps.end(), [](int e) { return e == 0; });
}

ConformalStructure initialize_scheme(const CompactMesh& mesh, Geometry geometry,
                                     const SchemeOptions& options, double length_scale) {
  check_scheme_options(options);
  const int nv = mesh.num_vertices();
  if (!(length_scale > 0) || !std::isfinite(length_scale)) {
    throw InvalidArgumentError("initialize_scheme: length scale must be positive and finite");
  }
  ConformalStructure cs;
  cs.geometry = geometry;
  cs.length_scale = length_scale;
  std::vector<double> length = mesh.input_lengths();
  for (double& l : length) l *= length_scale;

  // --- eps per vertex
  const Scheme scheme = options.scheme;
  switch (scheme) {
    case Scheme::Tangential:
    case Scheme::Thurston:
    case Scheme::InversiveDistance:
      cs.eps.assign(nv, 1);
      break;
    case Scheme::Yamabe:
      cs.eps.assign(nv, 0);
      break;
    case Scheme::VirtualRadius:
      cs.eps.assign(nv, -1);
      break;
    case Scheme::Mixed: {
      if (static_cast<int>(options.eps.size()) != nv) {
        throw InvalidArgumentError("mixed scheme: eps has " + std::to_string(options.eps.size()) +
                                   " values but the mesh has " + std::to_string(nv) +
                                   " vertices; give one of +1, 0, -1 per vertex");
      }
      cs.eps = options.eps;
      break;
    }
  }

  // --- initial radii, hence u0 (Yamabe's is 0: no radii)
  std::vector<double> radius(nv);
  const double cos_phi = std::cos(options.intersection_angle);
  if (scheme == Scheme::Tangential || scheme == Scheme::Thurston) {
    // l^2 = r_i^2 + r_j^2 + 2 r_i r_j cos(Phi): equal radii give l = r sqrt(2 + 2 cos Phi).
    const double factor = scheme == Scheme::Thurston ? 2 / std::sqrt(2 + 2 * cos_phi) : 1;
    radius = incircle_tangent_radii(mesh, length);
    for (double& r : radius) r *= factor;
  } else if (scheme != Scheme::Yamabe) {
    const auto incident = incident_lengths(mesh, length);
    for (int v = 0; v < nv; ++v) {
      if (cs.eps[v] == 1) {
        radius[v] = *std::min_element(incident[v].begin(), incident[v].end()) / 3;
      } else {
        radius[v] = options.virtual_radius_fraction * median(incident[v]);
      }
    }
  }
  cs.u0.resize(nv);
  for (int v = 0; v < nv; ++v) {
    cs.u0[v] = (scheme == Scheme::Yamabe) ? 0.0 : conformal_factor_from_radius(geometry, radius[v]);
  }

  // --- eta per edge
  cs.eta.resize(mesh.num_edges());
  for (int e = 0; e < mesh.num_edges(); ++e) {
    const auto [i, j] = mesh.edge_vertices(e);
    if (scheme == Scheme::Tangential) {
      cs.eta[e] = 1;
    } else if (scheme == Scheme::Thurston) {
      cs.eta[e] = cos_phi;
    } else {
      cs.eta[e] = conformal_structure_from_length(geometry, length[e], cs.u0[i], cs.u0[j],
                                                  cs.eps[i], cs.eps[j]);
    }
  }
  return cs;
}

}  // namespace ricci
