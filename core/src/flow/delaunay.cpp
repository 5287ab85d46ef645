#include "flow/delaunay.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "flow/hessian.h"

namespace ricci {

namespace {

// lambda-length of a Yamabe edge: l = lambda e^((ui+uj)/2) in E2, and the same with sinh(l/2)
// or sin(l/2) for l/2 in H2 and S2.
double lambda(const ConformalStructure& s, int e) {
  return std::sqrt(2 * s.eta[e]);
}

// The chord of a geodesic of length l: l (E2), 2 sinh(l/2) (H2), 2 sin(l/2) (S2).
double chord(Geometry g, double l) {
  switch (g) {
    case Geometry::Hyperbolic:
      return 2 * std::sinh(l / 2);
    case Geometry::Spherical:
      return 2 * std::sin(l / 2);
    default:
      return l;
  }
}

// Twice the cosine of the angle opposite side c in the triangle of sides a, b, c: defined for any
// positive lengths, also where they violate the triangle inequality (then beyond [-2, 2]).
double twice_cosine(double a, double b, double c) {
  return a / b + b / a - (c / a) * (c / b);
}

// Angle between sides x and y of the triangle with third side z.
double angle_between_sides(double x, double y, double z) {
  return std::acos(std::clamp((x * x + y * y - z * z) / (2 * x * y), -1.0, 1.0));
}

}  // namespace

double isometric_flip_diagonal(const std::array<double, 5>& l) {
  const double at_a = angle_between_sides(l[0], l[4], l[3]) + angle_between_sides(l[1], l[4], l[2]);
  return third_side(Geometry::Euclidean, l[0], l[1], at_a);
}

bool all_ptolemy(const ConformalStructure& structure) {
  return structure.geometry != Geometry::Spherical && is_yamabe(structure);
}

bool is_ptolemy_delaunay(const Triangulation& mesh, Geometry geometry, const MetricState& state,
                         int e, double tolerance) {
  if (mesh.is_boundary_edge(e)) return true;
  const auto length = [&](int f, int c) {
    return chord(geometry, state.edges[mesh.face_edge(f, c)].length);
  };
  double sum = 0;
  for (int h : {mesh.edge_halfedge(e), mesh.twin(mesh.edge_halfedge(e))}) {
    const int f = h / 3, c = h % 3;  // c: the corner opposite e in f
    sum += twice_cosine(length(f, (c + 1) % 3), length(f, (c + 2) % 3), length(f, c));
  }
  return sum >= -tolerance;
}

namespace {

// A face's share of is_delaunay's sums for its edge opposite corner c, from the face's angle
// Jacobian j: dK_a/du_b = -d theta_a/d u_b, and the size of the two ends' own derivatives.
struct DelaunayShare {
  double off_diagonal, scale;
};

DelaunayShare delaunay_share(const std::array<std::array<double, 3>, 3>& j, int c) {
  const int a = (c + 1) % 3, b = (c + 2) % 3;
  return {0.5 * (j[a][b] + j[b][a]), std::abs(j[a][a]) + std::abs(j[b][b])};
}

// is_delaunay from its faces' shares, summed in edge_faces' order.
bool delaunay_from_shares(const DelaunayShare& first, const DelaunayShare& second,
                          double tolerance) {
  double off_diagonal = 0, scale = 0;
  off_diagonal -= first.off_diagonal;
  scale += first.scale;
  off_diagonal -= second.off_diagonal;
  scale += second.scale;
  return off_diagonal <= tolerance * scale;
}

int corner_of_edge(const Triangulation& mesh, int f, int e) {
  const auto& edges = mesh.face_edges(f);
  return edges[0] == e ? 0 : edges[1] == e ? 1 : 2;
}

// The interior edges that are not Delaunay, in decreasing index: each face's angle Jacobian
// computed once for its three edges, not once per edge (the walks of the atlas at 8 cones scan
// every edge at each of their steps).
std::vector<int> non_delaunay_edges(const Triangulation& mesh, const MetricState& state,
                                    double tolerance) {
  std::vector<DelaunayShare> share(static_cast<size_t>(mesh.num_halfedges()));
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const auto j = face_angle_jacobian(mesh, state, f);
    for (int c = 0; c < 3; ++c) share[3 * f + c] = delaunay_share(j, c);
  }
  std::vector<int> edges;
  for (int e = mesh.num_edges() - 1; e >= 0; --e) {
    if (mesh.is_boundary_edge(e)) continue;
    const auto [f, g] = mesh.edge_faces(e);
    if (!delaunay_from_shares(share[3 * f + corner_of_edge(mesh, f, e)],
                              share[3 * g + corner_of_edge(mesh, g, e)], tolerance)) {
      edges.push_back(e);
    }
  }
  return edges;
}

}  // namespace

bool is_delaunay(const Triangulation& mesh, const MetricState& state, int e, double tolerance) {
  if (mesh.is_boundary_edge(e)) return true;
  const auto [f, g] = mesh.edge_faces(e);
  return delaunay_from_shares(
      delaunay_share(face_angle_jacobian(mesh, state, f), corner_of_edge(mesh, f, e)),
      delaunay_share(face_angle_jacobian(mesh, state, g), corner_of_edge(mesh, g, e)), tolerance);
}

namespace {

// What the common subdivision needs to follow the input's edges through a flip of edge e.
EdgeFlip flip_record(const Triangulation& mesh, const ConformalStructure& structure,
                     const MetricState& state, int e) {
  const int h = mesh.edge_halfedge(e), t = mesh.twin(h);
  const int f = h / 3, c = h % 3, fg = t / 3, d = t % 3;
  const int k = mesh.face_vertex(f, c), a = mesh.face_vertex(f, (c + 1) % 3),
            b = mesh.face_vertex(f, (c + 2) % 3), l = mesh.face_vertex(fg, d);
  const std::array<int, 5> quad_edges = {
      mesh.face_edge(f, (c + 2) % 3), mesh.face_edge(fg, (d + 1) % 3),
      mesh.face_edge(fg, (d + 2) % 3), mesh.face_edge(f, (c + 1) % 3), e};
  EdgeFlip record;
  record.edge = e;
  for (int i = 0; i < 5; ++i) {
    record.lambda[i] = lambda(structure, quad_edges[i]);
    record.chord[i] = chord(structure.geometry, state.edges[quad_edges[i]].length);
  }
  const auto& eps = structure.eps;
  record.ptolemy = eps[k] == 0 && eps[a] == 0 && eps[b] == 0 && eps[l] == 0;
  return record;
}

}  // namespace

FlipReport make_input_delaunay(IntrinsicTriangulation& mesh, ConformalStructure& structure) {
  FlipReport report;
  const auto length = [&](int e) { return lambda(structure, e); };
  // The quadrilateral k, a, l, b of interior edge e = a-b, and its sides k-a, a-l, l-b, b-k.
  struct Quad {
    int k, a, l, b;
    std::array<int, 4> sides;
  };
  const auto quad = [&](int e) {
    const int h = mesh.edge_halfedge(e), t = mesh.twin(h);
    const int f = h / 3, c = h % 3, g = t / 3, d = t % 3;
    return Quad{mesh.face_vertex(f, c),
                mesh.face_vertex(f, (c + 1) % 3),
                mesh.face_vertex(g, d),
                mesh.face_vertex(f, (c + 2) % 3),
                {mesh.face_edge(f, (c + 2) % 3), mesh.face_edge(g, (d + 1) % 3),
                 mesh.face_edge(g, (d + 2) % 3), mesh.face_edge(f, (c + 1) % 3)}};
  };
  std::vector<int> stack;
  std::vector<char> queued(mesh.num_edges(), 0);
  for (int e = 0; e < mesh.num_edges(); ++e) {
    if (!mesh.is_boundary_edge(e)) stack.push_back(e), queued[e] = 1;
  }
  const int max_flips = 10 * mesh.num_edges();
  while (!stack.empty() && report.flips < max_flips) {
    const int e = stack.back();
    stack.pop_back();
    queued[e] = 0;
    const Quad q = quad(e);
    const double ka = length(q.sides[0]), al = length(q.sides[1]), lb = length(q.sides[2]),
                 bk = length(q.sides[3]), ab = length(e);
    // Delaunay: the angles at k and l opposite a-b sum to at most pi. No loop (k = l): the
    // common subdivision finds the corners of this triangulation's faces by their vertices.
    if (angle_between_sides(ka, bk, ab) + angle_between_sides(al, lb, ab) <= kPi + 1e-12 ||
        q.k == q.l) {
      continue;
    }
    const double kl = isometric_flip_diagonal({ka, al, lb, bk, ab});
    // S2's lambda is sin(l / 2) at u = 0: a new diagonal of 1 or more has no spherical length.
    if (structure.geometry == Geometry::Spherical && !(kl < 1)) {
      ++report.blocked;
      continue;
    }
    EdgeFlip record;
    record.edge = e;
    record.isometric = true;
    for (int i = 0; i < 4; ++i) record.lambda[i] = length(q.sides[i]);
    record.lambda[4] = ab;
    record.chord = record.lambda;
    if (!mesh.flip(e)) {
      ++report.blocked;
      continue;
    }
    structure.eta[e] = kl * kl / 2;
    report.sequence.push_back(record);
    ++report.flips;
    for (int side : q.sides) {
      if (!mesh.is_boundary_edge(side) && !queued[side]) stack.push_back(side), queued[side] = 1;
    }
  }
  return report;
}

FlipReport make_delaunay(IntrinsicTriangulation& mesh, ConformalStructure& structure,
                         const Eigen::VectorXd& u, MetricState& state, int max_flips, bool loops) {
  FlipReport report;
  // Triangles that violate the triangle inequality have no angles: only Ptolemy flips (Euclidean
  // and hyperbolic Yamabe) can be decided and made from the lengths alone, and they end in valid
  // triangles.
  const bool from_lengths = !state.valid();
  if (from_lengths && !all_ptolemy(structure)) return report;
  const auto delaunay = [&](int e) {
    return from_lengths ? is_ptolemy_delaunay(mesh, structure.geometry, state, e)
                        : is_delaunay(mesh, state, e);
  };
  // Only the edges that are not Delaunay now start the queue (usually few after the first
  // round).
  std::vector<int> stack;
  if (from_lengths) {
    for (int e = mesh.num_edges() - 1; e >= 0; --e) {
      if (!delaunay(e)) stack.push_back(e);
    }
  } else {
    stack = non_delaunay_edges(mesh, state, 1e-10);
  }
  if (stack.empty()) return report;
  std::vector<char> queued(mesh.num_edges(), 0);
  for (int e : stack) queued[e] = 1;
  const Geometry g = structure.geometry;
  while (!stack.empty() && report.flips < max_flips) {
    const int e = stack.back();
    stack.pop_back();
    queued[e] = 0;
    if (delaunay(e)) continue;
    const int h = mesh.edge_halfedge(e), t = mesh.twin(h);
    const int f = h / 3, c = h % 3, fg = t / 3, d = t % 3;
    const int k = mesh.face_vertex(f, c), l = mesh.face_vertex(fg, d);
    // The quadrilateral k, a, l, b must be convex at a and b for the new diagonal k-l.
    const double angle_a = state.faces[f].angle[(c + 1) % 3] + state.faces[fg].angle[(d + 2) % 3];
    const double angle_b = state.faces[f].angle[(c + 2) % 3] + state.faces[fg].angle[(d + 1) % 3];
    // k-l may already be an edge: intrinsic Delaunay triangulations can need two edges between
    // one pair of vertices (both sides of a thin ear), and an edge from a vertex to itself (k = l,
    // a loop): without it a triangle can violate the triangle inequality with no flip left to
    // mend it, and the flow stalls (CAD plates of genus 2 with their cones did). Loops only where
    // asked, by Ptolemy flips (FlowOptions::loops); never a quadrilateral two of whose sides are
    // one edge (around a vertex of degree 1).
    // (A quadrilateral whose Ptolemy diagonal is not Delaunay is convex.)
    const int e_bk = mesh.face_edge(f, (c + 1) % 3), e_ka = mesh.face_edge(f, (c + 2) % 3);
    const int e_al = mesh.face_edge(fg, (d + 1) % 3), e_lb = mesh.face_edge(fg, (d + 2) % 3);
    const EdgeFlip record = flip_record(mesh, structure, state, e);
    const bool to_triangles = mesh.flips_to_triangles(e);
    const bool loop_refused = k == l && !(loops && record.ptolemy && to_triangles);
    if (loop_refused || !to_triangles || (!from_lengths && !(angle_a < kPi && angle_b < kPi))) {
      ++report.blocked;
      report.loops_refused += loop_refused;
      continue;
    }
    const double old_eta = structure.eta[e];
    double new_eta;
    const auto& eps = structure.eps;
    if (record.ptolemy) {
      // Ptolemy: lambda_kl lambda_ab = lambda_ka lambda_lb + lambda_al lambda_bk.
      const double lam = (lambda(structure, e_ka) * lambda(structure, e_lb) +
                          lambda(structure, e_al) * lambda(structure, e_bk)) /
                         lambda(structure, e);
      new_eta = lam * lam / 2;
    } else {
      const double diagonal =
          third_side(g, state.edges[e_ka].length, state.edges[e_al].length, angle_a);
      new_eta = conformal_structure_from_length(g, diagonal, u[k], u[l], eps[k], eps[l]);
    }
    // eta <= 0 leaves the range where the Ricci energy is convex (the paper's schemes ask eta > 0).
    if (!(new_eta > 0) || !std::isfinite(new_eta)) {
      ++report.blocked;
      continue;
    }
    mesh.flip(e);
    structure.eta[e] = new_eta;
    update_metric_at_edge(mesh, structure, u, e, state);
    // The other diagonal must be Delaunay: otherwise both are not (no proper weighted Delaunay
    // triangulation exists for this quad) and flipping would only cycle.
    if ((!from_lengths && !state.valid()) || !delaunay(e)) {
      // Back to a-b. Flipping twice gives the same triangles in other face slots, so both flips
      // are recorded: a replay of the sequence ends in the same arrays.
      report.sequence.push_back(record);
      report.sequence.push_back(flip_record(mesh, structure, state, e));
      mesh.flip(e);
      structure.eta[e] = old_eta;
      update_metric_at_edge(mesh, structure, u, e, state);
      ++report.blocked;
      continue;
    }
    ++report.flips;
    report.sequence.push_back(record);
    for (int side : {e_bk, e_ka, e_al, e_lb}) {
      if (!mesh.is_boundary_edge(side) && !queued[side]) {
        stack.push_back(side);
        queued[side] = 1;
      }
    }
  }
  return report;
}

}  // namespace ricci
