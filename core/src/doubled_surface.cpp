#include "doubled_surface.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdint>
#include <sstream>
#include <unordered_map>
#include <utility>

#include "circle_domain.h"
#include "layout_methods.h"
#include "ricci/errors.h"
#include "ricci/geometry.h"
#include "ricci/presets.h"
#include "ricci/scheme.h"

namespace ricci::detail {

bool may_flow_on_double(const CompactMesh& half, const UniformizationOptions& options,
                        const TargetCurvature& target, const Uniformization& run) {
  const LayoutKind kind = planned_layout(half, run.preset, run.geometry);
  // With u held fixed (free boundary) the boundary lengths are part of the request, and on the
  // double a flipped boundary edge no longer has its length: not for such targets.
  return !run.result.converged && run.result.stalled_at_boundary && !half.is_closed() &&
         target.num_fixed() == 0 && options.flow.edge_flips != EdgeFlips::Never &&
         is_yamabe(run.structure) &&
         ((run.geometry == Geometry::Euclidean && kind == LayoutKind::Plane) ||
          (run.geometry == Geometry::Hyperbolic && kind == LayoutKind::PoincareDisk));
}

TargetCurvature doubled_target(const CompactMesh& half, const CompactMesh& twice,
                               const TargetCurvature& target) {
  const int n = half.num_vertices();
  TargetCurvature t;
  t.curvature = Eigen::VectorXd::Zero(twice.num_vertices());
  t.fixed.assign(twice.num_vertices(), 0);
  int copy = n;
  for (int v = 0; v < n; ++v) {
    const bool boundary = half.is_boundary_vertex(v);
    const double k = (boundary ? 2.0 : 1.0) * target.curvature[v];
    t.curvature[v] = k;
    t.fixed[v] = target.fixed[v];
    if (boundary) continue;
    t.curvature[copy] = k;
    t.fixed[copy] = target.fixed[v];
    ++copy;
  }
  return t;
}

FlowResult half_result(const CompactMesh& half, const FlowResult& twice) {
  FlowResult r = twice;
  const int n = half.num_vertices();
  for (Eigen::VectorXd* x : {&r.u, &r.radius, &r.curvature, &r.target}) {
    if (x->size() == 0) continue;
    x->conservativeResize(n);
    for (int v = 0; v < n; ++v) {
      if (half.is_boundary_vertex(v) && (x == &r.curvature || x == &r.target)) (*x)[v] /= 2;
    }
  }
  r.edge_lengths.clear();
  r.triangulation.reset();
  r.flip_sequence.clear();
  r.area = twice.area / 2;
  return r;
}

Layout face_by_face_layout(const Triangulation& mesh, Geometry geometry,
                           const std::vector<double>& lengths) {
  Layout layout;
  layout.geometry = geometry;
  layout.corners.resize(mesh.num_faces());
  for (int f = 0; f < mesh.num_faces(); ++f) {
    // Sides: corner 0 to 1 is the edge opposite corner 2, and so on.
    const double a = lengths[mesh.face_edge(f, 2)], b = lengths[mesh.face_edge(f, 1)],
                 c = lengths[mesh.face_edge(f, 0)];
    if (geometry == Geometry::Hyperbolic) {
      // Corner 0 at the centre of the Poincare disk, where a geodesic of length d from it ends
      // at radius tanh(d / 2).
      const double angle = corner_angles(geometry, {c, b, a}).angle[0];
      const std::complex<double> z = std::polar(std::tanh(b / 2), angle);
      layout.corners[f] = {Eigen::Vector3d::Zero(), Eigen::Vector3d(std::tanh(a / 2), 0, 0),
                           Eigen::Vector3d(z.real(), z.imag(), 0)};
      continue;
    }
    const double x = (a * a + b * b - c * c) / (2 * a);
    layout.corners[f] = {Eigen::Vector3d::Zero(), Eigen::Vector3d(a, 0, 0),
                         Eigen::Vector3d(x, std::sqrt(std::max(0.0, b * b - x * x)), 0)};
  }
  return layout;
}

namespace {

std::complex<double> complex_of(const Eigen::Vector3d& p) {
  return {p.x(), p.y()};
}

// The sides of the pieces by vertex pair: the (one or two) pieces and the side's index in each.
struct PieceSides {
  struct Side {
    int piece[2] = {-1, -1};
    int corner[2] = {-1, -1};  // the side opposite this corner of the piece
    int count = 0;
  };
  std::unordered_map<uint64_t, Side> sides;

  static uint64_t key(int a, int b) {
    return (static_cast<uint64_t>(std::min(a, b)) << 32) | static_cast<uint32_t>(std::max(a, b));
  }
  explicit PieceSides(const std::vector<std::array<int, 3>>& faces) {
    sides.reserve(2 * faces.size());
    for (size_t f = 0; f < faces.size(); ++f) {
      for (int c = 0; c < 3; ++c) {
        Side& s = sides[key(faces[f][(c + 1) % 3], faces[f][(c + 2) % 3])];
        if (s.count < 2) {
          s.piece[s.count] = static_cast<int>(f);
          s.corner[s.count] = c;
        }
        ++s.count;
      }
    }
  }
};

// Breadth-first order of the pieces from `start` across shared sides, with each piece's parent.
std::pair<std::vector<int>, std::vector<int>> sweep(const std::vector<std::array<int, 3>>& faces,
                                                    const PieceSides& sides, int start) {
  std::vector<int> order = {start}, parent(faces.size(), -2);
  parent[start] = -1;
  for (size_t head = 0; head < order.size(); ++head) {
    const int p = order[head];
    for (int c = 0; c < 3; ++c) {
      const PieceSides::Side& s =
          sides.sides.at(PieceSides::key(faces[p][(c + 1) % 3], faces[p][(c + 2) % 3]));
      if (s.count != 2) continue;
      const int q = s.piece[s.piece[0] == p ? 1 : 0];
      if (parent[q] != -2) continue;
      parent[q] = p;
      order.push_back(q);
    }
  }
  return {order, parent};
}

// The Poincare disk draws a final face's sides straight in its coordinates, so a thin piece with
// corners on a side's geodesic arc can come out turned over: each new vertex is moved from the arc
// onto the straight side of its final face as developed (where the common subdivision puts it in
// a layout of the final faces), the same place from both faces of the side where the development
// crossed it.
void draw_sides_straight(const CommonSubdivision& twice, const std::vector<int>& pieces,
                         const Layout& frames, const std::vector<DiskIsometry>& motion,
                         int num_input_vertices, const std::vector<std::array<int, 3>>& faces,
                         std::vector<std::array<Eigen::Vector3d, 3>>& placed) {
  const auto klein = [](const std::complex<double>& z) { return 2.0 * z / (1.0 + std::norm(z)); };
  for (size_t q = 0; q < pieces.size(); ++q) {
    const auto& frame = frames.corners[twice.final_face[pieces[q]]];
    std::array<std::complex<double>, 3> corner, corner_klein;
    for (int i = 0; i < 3; ++i) {
      corner[i] = motion[q](complex_of(frame[i]));
      corner_klein[i] = klein(complex_of(frame[i]));
    }
    for (int c = 0; c < 3; ++c) {
      if (faces[q][c] < num_input_vertices) continue;
      // The side whose geodesic holds the point: straight through it in the Klein model.
      const std::complex<double> k = klein(complex_of(twice.corners[pieces[q]][c]));
      int side = 0;
      double best = INFINITY;
      for (int i = 0; i < 3; ++i) {
        const std::complex<double> d = corner_klein[(i + 1) % 3] - corner_klein[i];
        const double off = std::abs(std::imag(std::conj(d) * (k - corner_klein[i]))) / std::abs(d);
        if (off < best) best = off, side = i;
      }
      const auto point = [](std::complex<double> z) {
        return Eigen::Vector3d(z.real(), z.imag(), 0);
      };
      placed[q][c] =
          onto_drawn_side(point(corner[side]), point(corner[(side + 1) % 3]), placed[q][c]);
    }
  }
}

}  // namespace

HalfSubdivision half_subdivision(const CompactMesh& half, const CommonSubdivision& twice,
                                 const Layout& frames) {
  const Geometry geometry = frames.geometry;
  const int n = half.num_vertices(), nf = half.num_faces();
  HalfSubdivision out;
  CommonSubdivision& sub = out.subdivision;
  sub.num_input_vertices = n;
  sub.num_flips = twice.num_flips;
  sub.seconds = twice.seconds;

  // The pieces in the half's faces, and the vertices they use: the half's, then new ones.
  std::vector<int> pieces;
  std::vector<int> index(twice.positions.size(), -1);
  for (int v = 0; v < n; ++v) index[v] = v;
  for (size_t f = 0; f < twice.faces.size(); ++f) {
    if (twice.input_face[f] >= nf) continue;
    pieces.push_back(static_cast<int>(f));
    for (int v : twice.faces[f]) {
      if (index[v] < 0) index[v] = -2;
    }
  }
  const int twice_n = twice.num_input_vertices;
  std::vector<int> vertices(n);
  for (int v = 0; v < n; ++v) vertices[v] = v;
  for (size_t v = twice_n; v < twice.positions.size(); ++v) {
    if (index[v] == -2) {
      index[v] = static_cast<int>(vertices.size());
      vertices.push_back(static_cast<int>(v));
    }
  }
  const int nv = static_cast<int>(vertices.size());
  sub.u.resize(nv);
  for (int i = 0; i < nv; ++i) {
    const int v = vertices[i];
    sub.positions.push_back(twice.positions[v]);
    sub.vertex_input_face.push_back(twice.vertex_input_face[v]);
    sub.vertex_barycentric.push_back(twice.vertex_barycentric[v]);
    sub.u[i] = twice.u[v];
    if (i >= n) {
      sub.vertex_input_edge.push_back(twice.vertex_input_edge[v - twice_n]);
      sub.vertex_edge_parameter.push_back(twice.vertex_edge_parameter[v - twice_n]);
    }
  }
  for (int f : pieces) {
    const auto& t = twice.faces[f];
    sub.faces.push_back({index[t[0]], index[t[1]], index[t[2]]});
    sub.input_face.push_back(twice.input_face[f]);
    sub.final_face.push_back(twice.final_face[f]);
  }
  for (int v = 0; v < n; ++v) {
    if (sub.vertex_input_face[v] >= nf) {
      throw LayoutError("doubled surface: vertex " + std::to_string(v) +
                        " is placed in a face of the mirror copy");
    }
  }

  // Development: each piece placed by the isometry that puts the side it shares with a placed
  // piece onto that piece's side (its own corners are an isometric copy, in its final face's
  // frame), breadth-first from a central piece (the middle of the longest of two sweeps), so that
  // in the Poincare disk no piece lies farther out than the surface's radius.
  const int np = static_cast<int>(pieces.size());
  if (np == 0) throw LayoutError("doubled surface: no piece lies in the surface's faces");
  const PieceSides sides(sub.faces);
  int start = 0;
  if (geometry == Geometry::Hyperbolic) {
    const int far = sweep(sub.faces, sides, 0).first.back();
    const auto [order, parent] = sweep(sub.faces, sides, far);
    std::vector<int> path = {order.back()};
    while (parent[path.back()] >= 0) path.push_back(parent[path.back()]);
    start = path[path.size() / 2];
  }
  const auto [order, parent] = sweep(sub.faces, sides, start);
  if (static_cast<int>(order.size()) != np) {
    throw LayoutError("doubled surface: the pieces in the surface's faces are not connected");
  }
  std::vector<std::array<Eigen::Vector3d, 3>> placed(np);
  placed[start] = twice.corners[pieces[start]];
  std::vector<DiskIsometry> motion(np, DiskIsometry{geometry});  // own frame -> developed
  for (size_t i = 1; i < order.size(); ++i) {
    const int q = order[i], p = parent[q];
    int qc = -1, pa = -1, pb = -1;  // q's corner off the shared side; p's corners on it
    for (int c = 0; c < 3; ++c) {
      bool shared = false;
      for (int d = 0; d < 3; ++d) shared = shared || sub.faces[p][d] == sub.faces[q][c];
      if (!shared) qc = c;
    }
    if (qc < 0) throw LayoutError("doubled surface: two pieces on the same three vertices");
    const int qa = (qc + 1) % 3, qb = (qc + 2) % 3;
    for (int d = 0; d < 3; ++d) {
      if (sub.faces[p][d] == sub.faces[q][qa]) pa = d;
      if (sub.faces[p][d] == sub.faces[q][qb]) pb = d;
    }
    if (pa < 0 || pb < 0) throw LayoutError("doubled surface: two pieces share no side");
    const auto& own = twice.corners[pieces[q]];
    const DiskIsometry move =
        DiskIsometry::mapping(geometry, complex_of(own[qa]), complex_of(own[qb]),
                              complex_of(placed[p][pa]), complex_of(placed[p][pb]));
    const std::complex<double> z = move(complex_of(own[qc]));
    placed[q][qc] = Eigen::Vector3d(z.real(), z.imag(), 0);
    placed[q][qa] = placed[p][pa];
    placed[q][qb] = placed[p][pb];
    motion[q] = move;
  }

  // Plane: per vertex the mean of its corners, whose spread is the closure error. Poincare disk:
  // the surface is cut open where the development did not cross, so positions are per corner
  // (vertex_layout: the first corner's).
  if (geometry != Geometry::Euclidean) {
    draw_sides_straight(twice, pieces, frames, motion, sub.num_input_vertices, sub.faces, placed);
  }
  std::vector<Eigen::Vector3d> sum(nv, Eigen::Vector3d::Zero());
  std::vector<int> count(nv, 0);
  for (int p = 0; p < np; ++p) {
    for (int c = 0; c < 3; ++c) {
      const int v = sub.faces[p][c];
      if (geometry == Geometry::Euclidean || count[v] == 0) sum[v] += placed[p][c], ++count[v];
    }
  }
  sub.vertex_layout.resize(nv);
  for (int v = 0; v < nv; ++v) {
    if (count[v] == 0) throw LayoutError("doubled surface: a vertex lies in no piece");
    sub.vertex_layout[v] = sum[v] / count[v];
  }
  if (geometry != Geometry::Euclidean) {
    sub.corners = std::move(placed);
    out.closure_error = std::nan("");
    return out;
  }
  sub.corners.resize(np);
  for (int p = 0; p < np; ++p) {
    for (int c = 0; c < 3; ++c) {
      sub.corners[p][c] = sub.vertex_layout[sub.faces[p][c]];
      out.closure_error = std::max(out.closure_error, (placed[p][c] - sub.corners[p][c]).norm());
    }
  }

  // The boundary: sides of one piece only, each on one boundary edge of the half (the one its new
  // vertex lies on, or the one joining its two ends), measured in the piece's own frame.
  out.boundary_lengths.assign(half.num_edges(), 0.0);
  std::unordered_map<uint64_t, int> boundary_edge;
  for (int e = 0; e < half.num_edges(); ++e) {
    if (half.is_boundary_edge(e)) {
      const auto [a, b] = half.edge_vertices(e);
      boundary_edge[PieceSides::key(a, b)] = e;
    }
  }
  for (const auto& [key, s] : sides.sides) {
    if (s.count != 1) continue;
    const int p = s.piece[0], c = s.corner[0];
    const int a = sub.faces[p][(c + 1) % 3], b = sub.faces[p][(c + 2) % 3];
    int e = -1;
    for (int v : {a, b}) {
      if (v >= n) e = sub.vertex_input_edge[v - n];
    }
    if (e < 0) {
      const auto it = boundary_edge.find(key);
      if (it != boundary_edge.end()) e = it->second;
    }
    if (e < 0 || !half.is_boundary_edge(e)) {
      throw LayoutError("doubled surface: a side of the pieces' boundary lies on no boundary edge");
    }
    const auto& own = twice.corners[pieces[p]];
    out.boundary_lengths[e] += (own[(c + 1) % 3] - own[(c + 2) % 3]).norm();
  }
  return out;
}

namespace {

// The double's common subdivision cut down to the half.
HalfSubdivision subdivide_half(const CompactMesh& half, const CompactMesh& twice,
                               const ConformalStructure& structure, const FlowResult& result) {
  const Geometry g = structure.geometry;
  const Triangulation& flowed = result_triangulation(twice, result);
  const Layout frames = face_by_face_layout(flowed, g, result.edge_lengths);
  return half_subdivision(
      half, common_subdivision(twice, structure, result, frames, DiskSidePoints::OnGeodesic),
      frames);
}

}  // namespace

void flow_on_double(const CompactMesh& half, const UniformizationOptions& o, int outer,
                    const TargetCurvature& target, Uniformization& run) {
  const CompactMesh twice = CompactMesh::doubled(half);
  const TargetCurvature twice_target = doubled_target(half, twice, target);
  const ConformalStructure structure = prepare_flow(twice, run.geometry, o.scheme, twice_target);
  FlowOptions flow = o.flow;
  flow.edge_flips = EdgeFlips::Always;  // the half's flow has shown that flips are needed
  RicciFlowSolver solver(twice, structure, flow);

  Uniformization on_double;  // its totals are the double's flows only
  std::optional<HalfSubdivision> last;
  try {
    if (run.preset == TargetPreset::UnitDisk) {
      const BoundaryRefit refit = [&](const FlowResult& r) {
        last = subdivide_half(half, twice, structure, r);
        return doubled_target(half, twice,
                              circle_boundary_target(half, last->boundary_lengths, outer));
      };
      fit_boundary_to_circles(solver, twice, refit, twice_target, o, on_double);
    } else {
      on_double.result = solver.solve(twice_target);
      on_double.totals.add(on_double.result);
    }
    if (on_double.result.converged && !last) {
      last = subdivide_half(half, twice, structure, on_double.result);
    }
  } catch (const LayoutError& e) {
    run.result.failure += "; on the surface doubled along its boundary the flow converged, but " +
                          std::string(e.what());
    return;
  }
  run.totals.add(on_double.totals);
  if (!on_double.result.converged) {
    std::ostringstream s;
    s << "; on the surface doubled along its boundary, where boundary edges flip too, the flow "
         "stopped as well: "
      << on_double.result.failure;
    const Eigen::VectorXd& u = on_double.result.u;
    const double squeeze = u.size() ? std::exp(-(u.maxCoeff() - u.minCoeff()) / 2) : 1;
    if (squeeze < 1e-6) {
      s << " (by then lengths in one part were " << squeeze
        << " times those in another: the map squeezes part of the surface below what double "
           "precision resolves, as a long protrusion mapped onto a disk is"
        << (run.geometry == Geometry::Euclidean
                ? "; --target free-boundary keeps the boundary's lengths)"
                : ")");
    }
    run.result.failure += s.str();
    return;
  }

  run.doubled = true;
  run.doubled_because = run.result.failure;
  run.result = half_result(half, on_double.result);
  run.boundary_change = on_double.boundary_change;
  // u of the half is measured from the double's scaled input (H2 scales to the area of the
  // double's hyperbolic metric): the half's structure at that scale.
  run.structure = initialize_scheme(half, run.geometry, o.scheme, structure.length_scale);
  run.layout = Layout{};
  run.layout.geometry = run.geometry;
  run.layout.closure_error = last->closure_error;
  run.layout.max_relative_length_error = std::nan("");  // of the flow's triangles: not laid out
  CommonSubdivision& sub = last->subdivision;
  if (run.geometry == Geometry::Hyperbolic) {
    // Cut open where the development did not cross: the subdivision, with positions per corner
    // (the cut's deck transformations and relation error are not computed for it).
    run.layout_kind = LayoutKind::PoincareDisk;
    run.layout.relation_error = std::nan("");
    run.layout.corners = sub.corners;
    run.subdivision = std::move(sub);
    return;
  }
  run.layout_kind = LayoutKind::Plane;
  // The half's own faces drawn by their corners: delivered instead when none turns over.
  for (const auto& t : half.faces()) {
    std::array<Eigen::Vector3d, 3> p;
    for (int c = 0; c < 3; ++c) p[c] = sub.vertex_layout[t[c]];
    run.input_faces_turned_over += !(orientation(Geometry::Euclidean, p) > 0);
  }
  if (run.input_faces_turned_over == 0 || o.keep_input_triangulation) {
    run.position.assign(sub.vertex_layout.begin(), sub.vertex_layout.begin() + half.num_vertices());
  } else {
    run.position = sub.vertex_layout;
    run.layout.corners = sub.corners;
    run.subdivision = std::move(sub);
  }
}

}  // namespace ricci::detail
