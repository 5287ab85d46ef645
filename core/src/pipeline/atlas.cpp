#include "ricci/pipeline/atlas.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <exception>
#include <functional>
#include <limits>
#include <numeric>
#include <optional>
#include <system_error>
#include <thread>

#include "linear/blas_threads.h"
#include "pipeline/attempts.h"
#include "pipeline/texture_atlas.h"
#include "ricci/mesh/errors.h"

namespace ricci {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Where an input vertex is: its component and the component's vertex, or {-1, -1}.
std::vector<std::pair<int, int>> locate_inputs(const RepairedMesh& m) {
  std::vector<std::pair<int, int>> where(m.positions.size(), {-1, -1});
  for (size_t k = 0; k < m.components.size(); ++k) {
    const MeshComponent& c = m.components[k];
    for (size_t i = 0; i < c.vertex.size(); ++i) {
      where[c.vertex[i]] = {static_cast<int>(k), static_cast<int>(i)};
    }
  }
  for (size_t v = 0; v < m.positions.size(); ++v) {
    if (where[v].first < 0 && m.represented_by[v] >= 0) where[v] = where[m.represented_by[v]];
  }
  return where;
}

// A vertex option (centre, axis) given in the input's numbering, for component k.
int component_vertex(int input_vertex, const std::vector<std::pair<int, int>>& where,
                     int num_input_vertices, int k, const char* what) {
  if (input_vertex < 0) return -1;
  if (input_vertex >= num_input_vertices || where[input_vertex].first < 0) {
    throw InvalidArgumentError(std::string("the ") + what + " vertex " +
                               std::to_string(input_vertex) + " is in no face of the mesh");
  }
  return where[input_vertex].first == k ? where[input_vertex].second : -1;
}

UniformizationOptions component_options(const UniformizationOptions& o, const RepairedMesh& m,
                                        const std::vector<std::pair<int, int>>& where, int k) {
  UniformizationOptions c = o;
  const MeshComponent& component = m.components[k];
  if (o.preset == TargetPreset::Values && o.cones.empty()) {
    if (o.values.size() != m.num_input_vertices) {
      throw InvalidTargetError("target curvature: " + std::to_string(o.values.size()) +
                               " values for a mesh of " + std::to_string(m.num_input_vertices) +
                               " vertices; give one value per vertex, in vertex order");
    }
    c.values.resize(static_cast<long>(component.vertex.size()));
    for (size_t i = 0; i < component.vertex.size(); ++i) {
      c.values[static_cast<long>(i)] = o.values[m.original[component.vertex[i]]];
    }
  }
  if (!o.scheme.eps.empty()) {  // the mixed scheme's eps per input vertex
    if (static_cast<int>(o.scheme.eps.size()) != m.num_input_vertices) {
      throw InvalidArgumentError("mixed scheme: eps has " + std::to_string(o.scheme.eps.size()) +
                                 " values but the mesh has " +
                                 std::to_string(m.num_input_vertices) +
                                 " vertices; give one of +1, 0, -1 per vertex");
    }
    c.scheme.eps.clear();
    for (int v : component.vertex) c.scheme.eps.push_back(o.scheme.eps[m.original[v]]);
  }
  c.cones.clear();
  for (const Cone& cone : o.cones) {
    if (cone.vertex < 0 || cone.vertex >= m.num_input_vertices) {
      throw InvalidTargetError("cone at vertex " + std::to_string(cone.vertex) +
                               ": the mesh has vertices 0.." +
                               std::to_string(m.num_input_vertices - 1));
    }
    const int local = component_vertex(cone.vertex, where, m.num_input_vertices, k, "cone");
    if (local >= 0) c.cones.push_back({local, cone.angle});
  }
  if (!o.cones.empty() && c.cones.empty() && o.preset != TargetPreset::Atlas) {
    // no cone here: flat, and straight on the boundary
    c.preset = TargetPreset::Values;
    c.values = Eigen::VectorXd::Zero(static_cast<long>(component.vertex.size()));
  }
  c.input_vertex.clear();
  c.input_vertex.reserve(component.vertex.size());
  for (int v : component.vertex) c.input_vertex.push_back(m.original[v]);
  if (o.vertex_order.num_vertices() == m.num_input_vertices) {
    c.vertex_order = o.vertex_order.restricted(c.input_vertex);
  }
  c.center_vertex = component_vertex(o.center_vertex, where, m.num_input_vertices, k, "center");
  c.axis_vertex = component_vertex(o.axis_vertex, where, m.num_input_vertices, k, "axis");
  return c;
}

// === The atlas

// The delivered vertex of component k's vertex i (i past the component's vertices: a new vertex
// of its common subdivision).
int delivered_vertex(const MeshUniformization& out, size_t k, int i) {
  const std::vector<int>& vertex = out.mesh.components[k].vertex;
  if (i < static_cast<int>(vertex.size())) return vertex[static_cast<size_t>(i)];
  return out.new_vertex_base[k] + i - static_cast<int>(vertex.size());
}

using Triangle2 = std::array<Eigen::Vector2d, 3>;

double area_of(const std::vector<Triangle2>& triangles) {
  double a = 0;
  for (const Triangle2& t : triangles) {
    const Eigen::Vector2d u = t[1] - t[0], v = t[2] - t[0];
    a += 0.5 * std::abs(u.x() * v.y() - u.y() * v.x());
  }
  return a;
}

// A component of less than this share of the mesh's area has its long charts kept whole
// (UniformizationOptions::halve_long_charts).
constexpr double kHalvedShare = 1.0 / 32;

// The delivered vertices that take another's results, each with that vertex: a vertex that no
// delivered face holds (a collapsed needle's, or a joined vertex's whose faces went to a copy)
// takes those of the vertex the repair says holds its faces (RepairedMesh::represented_by); a
// vertex that faces hold keeps its own. (CGAL's diplodocus: a kept vertex holding a joined one's
// faces took its copy's position on the sphere, 4.4e-10 away, and four faces of 1e-10 around it
// turned over.)
std::vector<std::pair<int, int>> results_taken(const MeshUniformization& out) {
  std::vector<char> held(out.positions.size(), 0);
  for (const auto& t : out.faces) {
    for (int v : t) held[static_cast<size_t>(v)] = 1;
  }
  std::vector<std::pair<int, int>> taken;
  for (size_t v = 0; v < out.mesh.positions.size(); ++v) {
    const int r = out.mesh.represented_by[v];
    if (r >= 0 && r != static_cast<int>(v) && !held[v]) taken.emplace_back(static_cast<int>(v), r);
  }
  return taken;
}

// Several components: every piece packed at once (pack_charts) at one texel density, each
// component's layout scaled to its surface's area: an atlas component's charts each, any other
// planar layout as one piece.
void gather_texture(MeshUniformization& out, const PackingOptions& packing) {
  const size_t n = out.components.size();
  if (n == 1) {  // the component's own normalization, its vertex UVs on the repaired mesh's
    const TextureCoordinates t = texture_coordinates(out.components[0]);
    out.texture.wedge = t.wedge;
    if (t.vertex.empty()) return;
    out.texture.vertex.assign(out.positions.size(), Eigen::Vector2d::Zero());
    for (size_t i = 0; i < t.vertex.size(); ++i) {
      out.texture.vertex[delivered_vertex(out, 0, static_cast<int>(i))] = t.vertex[i];
    }
    for (const auto& [v, r] : results_taken(out)) out.texture.vertex[v] = out.texture.vertex[r];
    return;
  }
  std::vector<std::vector<Triangle2>> pieces;
  std::vector<std::vector<int>> piece_of_face(n);  // per component face; -1: not packed
  std::vector<std::vector<Triangle2>> drawn(n);
  std::vector<double> scale(n, 1);
  bool all_per_vertex = true;
  for (size_t k = 0; k < n; ++k) {
    const Uniformization& run = out.components[k];
    all_per_vertex = all_per_vertex && run.layout_kind == LayoutKind::Plane;
    if (run.layout_kind == LayoutKind::Atlas) {
      for (const auto& t : run.corners)
        drawn[k].push_back({t[0].head<2>(), t[1].head<2>(), t[2].head<2>()});
    } else {
      drawn[k] = drawn_corners(run);
    }
    piece_of_face[k].assign(run.corners.size(), -1);
    if (drawn[k].empty()) continue;
    const double area = area_of(drawn[k]);
    scale[k] = area > 0 ? std::sqrt(out.mesh.components[k].mesh.input_area() / area) : 1;
    const bool by_chart = run.layout_kind == LayoutKind::Atlas && !run.face_chart.empty();
    const int base = static_cast<int>(pieces.size());
    int count = 1;
    if (by_chart) count = *std::max_element(run.face_chart.begin(), run.face_chart.end()) + 1;
    pieces.resize(pieces.size() + static_cast<size_t>(count));
    for (size_t f = 0; f < drawn[k].size(); ++f) {
      const int piece = base + (by_chart ? run.face_chart[f] : 0);
      piece_of_face[k][f] = piece;
      Triangle2 t = drawn[k][f];
      for (auto& q : t) q *= scale[k];
      pieces[static_cast<size_t>(piece)].push_back(t);
    }
  }
  if (pieces.empty()) return;
  const Packing p = pack_charts(pieces, packing);
  out.packed.pieces = static_cast<int>(pieces.size());
  out.packed.utilization = p.utilization;
  out.packed.padding = p.padding;
  out.packed.padding_asked = packing.padding;
  out.packed.below_a_texel = p.below_a_texel;
  const auto to_atlas = [&](int piece, const Eigen::Vector2d& q) {
    const Eigen::Vector2d uv = p.scale * p.rotation[piece] * q + p.offset[piece];
    return Eigen::Vector2d(std::clamp(uv.x(), 0.0, 1.0), std::clamp(uv.y(), 0.0, 1.0));
  };
  if (all_per_vertex) {
    out.texture.vertex.assign(out.positions.size(), Eigen::Vector2d::Zero());
    for (size_t k = 0; k < n; ++k) {
      const auto& position = out.components[k].position;
      if (piece_of_face[k].empty() || piece_of_face[k][0] < 0) continue;  // not laid out
      for (size_t i = 0; i < position.size(); ++i) {
        out.texture.vertex[delivered_vertex(out, k, static_cast<int>(i))] =
            to_atlas(piece_of_face[k][0], scale[k] * position[i].head<2>());
      }
    }
    for (const auto& [v, r] : results_taken(out)) out.texture.vertex[v] = out.texture.vertex[r];
    return;
  }
  for (size_t k = 0; k < n; ++k) {
    // One entry per delivered face, laid out or not, so that later components stay aligned.
    const Uniformization& run = out.components[k];
    const size_t faces = run.subdivision
                             ? run.subdivision->faces.size()
                             : static_cast<size_t>(out.mesh.components[k].mesh.num_faces());
    for (size_t f = 0; f < faces; ++f) {
      Triangle2 uv = {Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
      if (f < piece_of_face[k].size() && piece_of_face[k][f] >= 0) {
        for (int c = 0; c < 3; ++c)
          uv[c] = to_atlas(piece_of_face[k][f], scale[k] * drawn[k][f][c]);
      }
      out.texture.wedge.push_back(uv);
    }
  }
  out.packed.distortion = detail::face_distortion(out.positions, out.faces, out.texture.wedge);
}

// Per-vertex results of every component, on the delivered vertices.
void gather_vertices(MeshUniformization& out) {
  out.positions = out.mesh.positions;
  for (size_t k = 0; k < out.components.size(); ++k) {
    out.new_vertex_base.push_back(static_cast<int>(out.positions.size()));
    if (const auto& sub = out.components[k].subdivision) {
      out.positions.insert(out.positions.end(), sub->positions.begin() + sub->num_input_vertices,
                           sub->positions.end());
    }
  }
  const size_t nv = out.positions.size();
  for (Eigen::VectorXd* x : {&out.u, &out.radius, &out.curvature, &out.target}) {
    *x = Eigen::VectorXd::Constant(static_cast<long>(nv), kNaN);
  }
  out.vertex_input_face.assign(nv, -1);
  out.vertex_barycentric.assign(nv, Eigen::Vector3d::Zero());
  bool any_position = false;
  for (const Uniformization& run : out.components) any_position |= !run.position.empty();
  if (any_position) out.position.assign(nv, Eigen::Vector3d::Constant(kNaN));
  for (size_t k = 0; k < out.components.size(); ++k) {
    const MeshComponent& c = out.mesh.components[k];
    const Uniformization& run = out.components[k];
    const FlowResult& r = run.result;
    for (size_t i = 0; i < c.vertex.size(); ++i) {
      const int v = c.vertex[i];
      const long l = static_cast<long>(i);
      out.u[v] = r.u.size() > l ? r.u[l] : kNaN;
      out.radius[v] = r.radius.size() > l ? r.radius[l] : kNaN;
      out.curvature[v] = r.curvature.size() > l ? r.curvature[l] : kNaN;
      out.target[v] = r.target.size() > l ? r.target[l] : kNaN;
      if (!run.position.empty()) out.position[v] = run.position[i];
    }
    if (!run.subdivision) {
      for (size_t f = 0; f < c.face.size(); ++f) {
        const auto& t = c.mesh.faces()[f];
        out.faces.push_back({c.vertex[t[0]], c.vertex[t[1]], c.vertex[t[2]]});
        out.input_face.push_back(c.face[f]);
      }
      continue;
    }
    const CommonSubdivision& sub = *run.subdivision;
    for (size_t i = c.vertex.size(); i < sub.positions.size(); ++i) {
      const int v = delivered_vertex(out, k, static_cast<int>(i));
      out.u[v] = sub.u[static_cast<long>(i)];
      out.radius[v] = radius_from_conformal_factor(run.geometry, out.u[v]);
      out.curvature[v] = 0;
      if (!run.position.empty()) out.position[v] = run.position[i];
      out.vertex_input_face[v] = c.face[sub.vertex_input_face[i]];
      out.vertex_barycentric[v] = sub.vertex_barycentric[i];
    }
    for (size_t f = 0; f < sub.faces.size(); ++f) {
      std::array<int, 3> t{};
      for (int j = 0; j < 3; ++j) t[j] = delivered_vertex(out, k, sub.faces[f][j]);
      out.faces.push_back(t);
      out.input_face.push_back(c.face[sub.input_face[f]]);
    }
  }
  for (const auto& [v, r] : results_taken(out)) {
    for (Eigen::VectorXd* x : {&out.u, &out.radius, &out.curvature, &out.target}) {
      (*x)[static_cast<long>(v)] = (*x)[r];
    }
    if (any_position) out.position[v] = out.position[r];
  }
}

// Per delivered face: its component's layout kind, model corners and chart (numbered on from the
// charts of the components before it, so that a chart names one piece of the whole file).
void gather_face_layouts(MeshUniformization& out) {
  const Eigen::Vector3d none = Eigen::Vector3d::Constant(kNaN);
  int charts_before = 0;
  for (size_t k = 0; k < out.components.size(); ++k) {
    const Uniformization& run = out.components[k];
    const size_t faces =
        run.subdivision ? run.subdivision->faces.size() : out.mesh.components[k].face.size();
    const bool laid = run.corners.size() == faces && run.layout_kind != LayoutKind::None;
    const auto& model = run.model_corners.empty() ? run.corners : run.model_corners;
    for (size_t f = 0; f < faces; ++f) {
      out.face_layout.push_back(laid ? run.layout_kind : LayoutKind::None);
      out.corners.push_back(laid ? model[f] : std::array<Eigen::Vector3d, 3>{none, none, none});
      out.face_chart.push_back(
          !laid ? -1 : charts_before + (run.face_chart.empty() ? 0 : run.face_chart[f]));
    }
    if (laid) {
      int charts = 1;
      for (int c : run.face_chart) charts = std::max(charts, c + 1);
      charts_before += charts;
    }
  }
}

}  // namespace

bool MeshUniformization::converged() const {
  return std::all_of(components.begin(), components.end(),
                     [](const Uniformization& run) { return run.converged(); });
}

bool MeshUniformization::valid() const {
  return std::all_of(components.begin(), components.end(),
                     [](const Uniformization& run) { return run.valid(); });
}

void MeshUniformization::require_valid(const std::string& subject) const {
  for (size_t k = 0; k < components.size(); ++k) {
    if (components.size() == 1) {
      components[k].require_valid(subject);
    } else {
      components[k].require_valid((subject.empty() ? "" : subject + ", ") + "component " +
                                  std::to_string(k));
    }
  }
}

std::vector<LayoutKind> planned_layouts(const RepairedMesh& mesh,
                                        const UniformizationOptions& options) {
  const std::vector<std::pair<int, int>> where = locate_inputs(mesh);
  std::vector<LayoutKind> kinds;
  for (size_t k = 0; k < mesh.components.size(); ++k) {
    const CompactMesh& m = mesh.components[k].mesh;
    const auto [preset, geometry] =
        resolve_request(m, component_options(options, mesh, where, static_cast<int>(k)));
    kinds.push_back(planned_layout(m, preset, geometry));
  }
  return kinds;
}

MeshUniformization uniformize_mesh(RepairedMesh mesh, const UniformizationOptions& options) {
  MeshUniformization out;
  out.mesh = std::move(mesh);
  const std::vector<std::pair<int, int>> where = locate_inputs(out.mesh);
  const size_t n = out.mesh.components.size();
  double area = 0;
  for (const auto& component : out.mesh.components) area += component.mesh.input_area();
  const auto run = [&](size_t k, const std::function<bool(const FlowProgress&)>& progress) {
    UniformizationOptions o = component_options(options, out.mesh, where, static_cast<int>(k));
    o.flow.progress = progress;
    // Gymnasium's Adroit forearm plate assembly, 218 parts of about 0.5 % each: their halvings
    // judged alone took 14 s of 38 s, and the texture of all, packed together, fills 0.385 of the
    // square with them, 0.413 without. Larger parts' strips matter (ALSTOM's test part of 6: 0.624
    // with its halvings, 0.204 without).
    if (out.mesh.components[k].mesh.input_area() < kHalvedShare * area) {
      o.halve_long_charts = false;
    }
    try {
      // Several components' charts are packed together (gather_texture), not each alone.
      const CompactMesh& m = out.mesh.components[k].mesh;
      return n == 1 ? uniformize(m, o) : detail::uniformize_unpacked(m, o);
    } catch (const InvalidTargetError& e) {
      if (n == 1) throw;
      throw InvalidTargetError("component " + std::to_string(k) + ": " + e.what());
    } catch (const InvalidArgumentError& e) {
      if (n == 1) throw;
      throw InvalidArgumentError("component " + std::to_string(k) + ": " + e.what());
    }
  };
  // The components two at a time, taken in order by whichever thread is free, each result in its
  // own slot: the outcome does not depend on the threads' timing. Only this thread calls the
  // caller's progress (a GUI's); the other's flows stop when it cancels. Every component before
  // the first that fails is run and none after it is begun, and that one's error is thrown, as
  // with one thread.
  std::vector<std::optional<Uniformization>> runs(n);
  std::vector<std::exception_ptr> errors(n);
  std::atomic<size_t> next{0}, first_failure{n};
  std::atomic<bool> cancelled{false};
  const auto work = [&](const std::function<bool(const FlowProgress&)>& progress) {
    for (size_t k = next++; k < first_failure; k = next++) {
      try {
        runs[k] = run(k, progress);
      } catch (...) {
        errors[k] = std::current_exception();
        size_t first = first_failure;
        while (k < first && !first_failure.compare_exchange_weak(first, k)) {
        }
      }
    }
  };
  std::function<bool(const FlowProgress&)> progress;
  if (options.flow.progress) {
    progress = [&](const FlowProgress& p) {
      if (!options.flow.progress(p)) cancelled = true;
      return !cancelled;
    };
  }
  std::optional<std::thread> other;
  // The two threads keep both cores busy: OpenBLAS's own threads would only spin.
  std::optional<detail::SingleThreadedBlas> one_blas_thread;
  if (n >= 2 && std::thread::hardware_concurrency() >= 2) {
    one_blas_thread.emplace();
    try {
      other.emplace(work, [&](const FlowProgress&) { return !cancelled.load(); });
    } catch (const std::system_error&) {  // no second thread here: this one runs them all
      one_blas_thread.reset();
    }
  }
  work(progress);
  if (other) other->join();
  one_blas_thread.reset();
  for (size_t k = 0; k < n; ++k) {
    if (errors[k]) std::rethrow_exception(errors[k]);
    out.components.push_back(std::move(*runs[k]));
  }
  gather_vertices(out);
  gather_face_layouts(out);
  // In quarter turns only where every atlas part's charts meet so (AtlasResult::quarter_turns).
  PackingOptions packing = options.packing;
  const auto& parts = out.components;
  const auto atlas = [](const Uniformization& c) { return c.layout_kind == LayoutKind::Atlas; };
  packing.quarter_turns_only =
      std::any_of(parts.begin(), parts.end(), atlas) &&
      std::all_of(parts.begin(), parts.end(),
                  [&](const Uniformization& c) { return !atlas(c) || c.atlas.quarter_turns; });
  gather_texture(out, packing);
  for (size_t k = 0; k < out.components.size(); ++k) {
    const AtlasResult& a = out.components[k].atlas;
    for (size_t i = 0; i < a.placement.cones.size(); ++i) {
      const int v = delivered_vertex(out, k, a.placement.cones[i].vertex);
      out.cones.push_back(
          {v, i < a.cone_angles.size() ? a.cone_angles[i] : a.placement.cones[i].angle});
    }
  }
  return out;
}

}  // namespace ricci
