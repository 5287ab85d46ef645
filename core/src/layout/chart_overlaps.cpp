// Overlaps within a chart: which faces of a chart overlap others (a hierarchy of bounding boxes
// over the whole chart, not only neighbours), which charts are embedded for certain without that
// test, and the split of an overlapping chart between its two sheets (ricci/layout/charts.h).
#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <limits>
#include <queue>

#include "mesh/plane.h"
#include "mesh/two_threads.h"
#include "ricci/layout/charts.h"
#include "ricci/mesh/errors.h"
#include "ricci/mesh/geometry.h"

namespace ricci {

using detail::cross;

namespace {

// A chart of this many faces has its overlap test on two threads (a face's query and tests cost
// about a microsecond, a thread some 0.1 ms).
constexpr int kTwoThreadsFromFaces = 4000;

// How far the interiors of two counter-clockwise triangles reach past the line of side i of
// triangle t towards the other, o (<= 0: that side separates them; infinite: a side of no
// length).
double reach_past(const std::array<Eigen::Vector2d, 3>& t, int i,
                  const std::array<Eigen::Vector2d, 3>& o) {
  const Eigen::Vector2d e = t[(i + 1) % 3] - t[i];
  const double length = e.norm();
  if (!(length > 0)) return std::numeric_limits<double>::infinity();
  const Eigen::Vector2d n(e.y() / length, -e.x() / length);  // outward for a ccw triangle
  double nearest = std::numeric_limits<double>::infinity();
  for (const auto& q : o) nearest = std::min(nearest, n.dot(q));
  return n.dot(t[i]) - nearest;
}

// How far the interiors of two counter-clockwise triangles reach into each other: the least, over
// the sides of both, of how far the other triangle reaches past the side's line.
double penetration(const std::array<Eigen::Vector2d, 3>& a,
                   const std::array<Eigen::Vector2d, 3>& b) {
  double least = std::numeric_limits<double>::infinity();
  for (int i = 0; i < 3; ++i) least = std::min(least, reach_past(a, i, b));
  for (int i = 0; i < 3; ++i) least = std::min(least, reach_past(b, i, a));
  return least;
}

// The interiors of two counter-clockwise triangles overlap: no side of either separates them by
// more than `tolerance` (penetration above it, ending at the first side that does: most pairs
// tested are neighbours, which the first sides part).
bool interiors_overlap(const std::array<Eigen::Vector2d, 3>& a,
                       const std::array<Eigen::Vector2d, 3>& b, double tolerance) {
  // (A side whose reach is NaN separates nothing, as in penetration's minimum.)
  for (int i = 0; i < 3; ++i) {
    if (reach_past(a, i, b) <= tolerance) return false;
  }
  for (int i = 0; i < 3; ++i) {
    if (reach_past(b, i, a) <= tolerance) return false;
  }
  return true;
}

struct Box {
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  void add(const Eigen::Vector2d& q) { lo = lo.cwiseMin(q), hi = hi.cwiseMax(q); }
  void add(const Box& b) { lo = lo.cwiseMin(b.lo), hi = hi.cwiseMax(b.hi); }
  bool meets(const Box& b) const {
    return (lo.array() <= b.hi.array()).all() && (b.lo.array() <= hi.array()).all();
  }
};

// A bounding-box hierarchy over some faces, split at the median of the longer axis: the faces
// whose boxes meet a box, in time about the log of the count plus the faces found, whatever the
// spread of the faces' sizes (a chart of a high-distortion metric spans area ratios of e^20).
class BoxTree {
 public:
  BoxTree(const std::vector<Box>& box, std::vector<int>& faces) : box_(box), faces_(faces) {
    build(0, static_cast<int>(faces.size()));
  }
  template <class Visit>
  void visit(const Box& b, Visit&& found) const {
    int stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes_[stack[--top]];
      if (!n.box.meets(b)) continue;
      if (n.left < 0) {
        for (int i = n.begin; i < n.end; ++i) {
          if (box_[faces_[i]].meets(b)) found(faces_[i]);
        }
      } else {
        stack[top++] = n.left, stack[top++] = n.right;
      }
    }
  }

 private:
  struct Node {
    Box box;
    int begin = 0, end = 0, left = -1, right = -1;  // a leaf: no children
  };
  int build(int begin, int end) {
    const int at = static_cast<int>(nodes_.size());
    nodes_.push_back({});
    Box b;
    for (int i = begin; i < end; ++i) b.add(box_[faces_[i]]);
    nodes_[at].box = b, nodes_[at].begin = begin, nodes_[at].end = end;
    if (end - begin <= kLeaf) return at;
    const int axis = b.hi.x() - b.lo.x() >= b.hi.y() - b.lo.y() ? 0 : 1;
    const int mid = (begin + end) / 2;
    std::nth_element(
        faces_.begin() + begin, faces_.begin() + mid, faces_.begin() + end, [&](int f, int g) {
          return box_[f].lo[axis] + box_[f].hi[axis] < box_[g].lo[axis] + box_[g].hi[axis];
        });
    const int left = build(begin, mid);
    const int right = build(mid, end);
    nodes_[at].left = left, nodes_[at].right = right;
    return at;
  }
  static constexpr int kLeaf = 8;
  const std::vector<Box>& box_;
  std::vector<int>& faces_;
  std::vector<Node> nodes_;
};

}  // namespace

std::vector<std::pair<int, int>> overlapping_faces(const Charts& charts, size_t max_pairs,
                                                   const std::vector<char>& known_clean,
                                                   size_t per_chart) {
  std::vector<std::pair<int, int>> pairs;
  const int nf = static_cast<int>(charts.corners.size());
  std::vector<std::vector<int>> by_chart(charts.num_charts);
  for (int f = 0; f < nf; ++f) by_chart[charts.chart[f]].push_back(f);
  std::vector<Box> box(nf);
  for (int f = 0; f < nf; ++f) {
    for (const auto& q : charts.corners[f]) box[f].add(q);
  }
  for (int c = 0; c < charts.num_charts; ++c) {
    std::vector<int>& faces = by_chart[c];
    if (faces.size() < 2 || (!known_clean.empty() && known_clean[c])) continue;
    Box whole;
    for (int f : faces) whole.add(box[f]);
    const double size = (whole.hi - whole.lo).maxCoeff();
    if (!(size > 0)) continue;
    const double tolerance = 1e-9 * size;
    const std::vector<int> in_order = faces;  // the tree reorders `faces`
    const BoxTree tree(box, faces);
    // Each half of the faces in order with the pairs it finds, up to per_chart; then the first
    // half's, and the second's while the first found fewer, a face's pairs all or none: the pairs
    // one pass in order finds before it stops.
    std::array<std::vector<std::pair<int, int>>, 2> half;
    detail::in_two_halves(
        static_cast<int>(in_order.size()),
        [&](int part, int begin, int end) {
          std::vector<std::pair<int, int>>& found = half[part];
          for (int i = begin; i < end; ++i) {
            const int f = in_order[i];
            tree.visit(box[f], [&](int g) {
              if (g > f && interiors_overlap(charts.corners[f], charts.corners[g], tolerance)) {
                found.emplace_back(f, g);
              }
            });
            if (per_chart > 0 && found.size() >= per_chart) break;
          }
        },
        kTwoThreadsFromFaces);
    std::vector<std::pair<int, int>> found = std::move(half[0]);
    for (size_t i = 0; i < half[1].size(); ++i) {
      const bool same_face = i > 0 && half[1][i].first == half[1][i - 1].first;
      if (per_chart > 0 && found.size() >= per_chart && !same_face) break;
      found.push_back(half[1][i]);
    }
    std::sort(found.begin(), found.end());
    pairs.insert(pairs.end(), found.begin(), found.end());
    if (max_pairs > 0 && pairs.size() >= max_pairs) {
      pairs.resize(max_pairs);
      break;
    }
  }
  return pairs;
}

namespace {

// The distance between segments a-b and c-d (0 where they cross or touch).
double segment_distance(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                        const Eigen::Vector2d& c, const Eigen::Vector2d& d) {
  const double abc = cross(b - a, c - a), abd = cross(b - a, d - a);
  const double cda = cross(d - c, a - c), cdb = cross(d - c, b - c);
  if (((abc > 0 && abd < 0) || (abc < 0 && abd > 0)) &&
      ((cda > 0 && cdb < 0) || (cda < 0 && cdb > 0))) {
    return 0;
  }
  const auto to_segment = [](const Eigen::Vector2d& q, const Eigen::Vector2d& p0,
                             const Eigen::Vector2d& p1) {
    const Eigen::Vector2d e = p1 - p0;
    const double length2 = e.squaredNorm();
    const double t = length2 > 0 ? std::clamp((q - p0).dot(e) / length2, 0.0, 1.0) : 0.0;
    return (q - (p0 + t * e)).norm();
  };
  return std::min(
      {to_segment(a, c, d), to_segment(b, c, d), to_segment(c, a, b), to_segment(d, a, b)});
}

}  // namespace

std::vector<char> embedded_charts(const Triangulation& mesh, const std::vector<char>& cut,
                                  const Charts& charts) {
  const int nf = mesh.num_faces();
  const int nc = charts.num_charts;
  const auto& p = charts.corners;
  // A chart with a face turned over is not embedded, and its faces are not read further (where
  // every chart has one, as in a drawing about to be refused, nothing is).
  std::vector<char> embedded(nc, 1);
  for (int f = 0; f < nf; ++f) {
    if (!(signed_area(p[f]) > 0)) embedded[charts.chart[f]] = 0;
  }
  if (std::none_of(embedded.begin(), embedded.end(), [](char e) { return e != 0; })) {
    return embedded;
  }
  const std::vector<int> wedge = chart_wedges(mesh, cut);
  // Per wedge: its angle sum, and its border halfedges out and in; per chart, its counts.
  std::vector<double> angle_sum(3 * nf, 0.0);
  std::vector<int> out_of(3 * nf, -1), ins(3 * nf, 0), outs(3 * nf, 0);
  std::vector<long> faces(nc, 0), wedges(nc, 0), border(nc, 0);
  for (int f = 0; f < nf; ++f) {
    const int k = charts.chart[f];
    if (!embedded[k]) continue;
    ++faces[k];
    for (int c = 0; c < 3; ++c) {
      const Eigen::Vector2d u = p[f][(c + 1) % 3] - p[f][c], v = p[f][(c + 2) % 3] - p[f][c];
      angle_sum[wedge[3 * f + c]] += std::atan2(std::abs(cross(u, v)), u.dot(v));
      if (wedge[3 * f + c] == 3 * f + c) ++wedges[k];
      const int t = mesh.twin(3 * f + c);
      if (t >= 0 && !cut[mesh.face_edge(f, c)]) continue;
      // Halfedge 3 f + c runs from corner c + 1 to corner c + 2: a border halfedge.
      ++border[k];
      const int tail = wedge[3 * f + (c + 1) % 3], head = wedge[3 * f + (c + 2) % 3];
      ++outs[tail], ++ins[head];
      out_of[tail] = 3 * f + c;
    }
  }
  // A disk (Euler characteristic 1) whose wedges each have one border halfedge out and one in
  // where they have any, and whose inner wedges turn once.
  std::vector<char> on_border(3 * nf, 0);
  for (int f = 0; f < nf; ++f) {
    const int k = charts.chart[f];
    if (!embedded[k]) continue;
    for (int c = 0; c < 3; ++c) {
      const int w = wedge[3 * f + c];
      if (w != 3 * f + c) continue;
      if (outs[w] != ins[w] || outs[w] > 1) {
        embedded[k] = 0;
      } else if (outs[w] == 0 && std::abs(angle_sum[w] - 2 * kPi) > 0.5) {
        embedded[k] = 0;
      }
      on_border[w] = outs[w] == 1;
    }
  }
  for (int k = 0; k < nc; ++k) {
    const long edges = (3 * faces[k] + border[k]) / 2;
    if (wedges[k] - edges + faces[k] != 1 || border[k] < 3) embedded[k] = 0;
  }
  // The border, one loop, as a simple polygon: no two sides that do not follow one another come
  // within a margin far above the overlap test's tolerance (a chart near that is tested whole).
  std::vector<char> visited(3 * nf, 0);
  std::vector<int> first_of(nc, -1);
  for (int w = 0; w < 3 * nf; ++w) {
    if (on_border[w] && first_of[charts.chart[out_of[w] / 3]] < 0) {
      first_of[charts.chart[out_of[w] / 3]] = w;
    }
  }
  const auto tail_position = [&](int h) { return p[h / 3][(h % 3 + 1) % 3]; };
  const auto head_position = [&](int h) { return p[h / 3][(h % 3 + 2) % 3]; };
  for (int k = 0; k < nc; ++k) {
    if (!embedded[k] || first_of[k] < 0) continue;
    std::vector<int> loop;  // border halfedges in order
    for (int w = first_of[k]; !visited[w];) {
      visited[w] = 1;
      const int h = out_of[w];
      loop.push_back(h);
      w = wedge[3 * (h / 3) + (h % 3 + 2) % 3];
    }
    if (static_cast<long>(loop.size()) != border[k]) {  // more than one loop
      embedded[k] = 0;
      continue;
    }
    Box whole;
    for (int h : loop) whole.add(tail_position(h));
    const double margin = 1e-7 * (whole.hi - whole.lo).maxCoeff();
    const int n = static_cast<int>(loop.size());
    std::vector<Box> box(n);
    std::vector<int> sides(n);
    for (int i = 0; i < n; ++i) {
      box[i].add(tail_position(loop[i]));
      box[i].add(head_position(loop[i]));
      box[i].lo.array() -= margin, box[i].hi.array() += margin;
      sides[i] = i;
    }
    const BoxTree tree(box, sides);
    for (int i = 0; i < n && embedded[k]; ++i) {
      tree.visit(box[i], [&](int j) {
        if (j <= i || j == i + 1 || (i == 0 && j == n - 1)) return;
        const int a = loop[i], b = loop[j];
        if (segment_distance(tail_position(a), head_position(a), tail_position(b),
                             head_position(b)) <= margin) {
          embedded[k] = 0;
        }
      });
    }
  }
  return embedded;
}

std::vector<std::pair<int, int>> overlapping_faces(const Triangulation& mesh,
                                                   const std::vector<char>& cut,
                                                   const Charts& charts,
                                                   std::vector<char> known_clean,
                                                   size_t per_chart) {
  const std::vector<char> embedded = embedded_charts(mesh, cut, charts);
  if (known_clean.empty()) known_clean.assign(embedded.size(), 0);
  for (size_t k = 0; k < known_clean.size(); ++k) known_clean[k] = known_clean[k] || embedded[k];
  return overlapping_faces(charts, 0, known_clean, per_chart);
}

double overlap_depth(const Charts& charts, int f, int g) {
  const auto longest = [&](int face) {
    const auto& q = charts.corners[face];
    return std::max({(q[1] - q[0]).norm(), (q[2] - q[1]).norm(), (q[0] - q[2]).norm()});
  };
  const double size = std::min(longest(f), longest(g));
  return size > 0 ? penetration(charts.corners[f], charts.corners[g]) / size : 0;
}

// === Separating the sheets of an overlapping chart

int separate_sheets(const Triangulation& mesh, std::vector<int>& part, int new_part, int f, int g,
                    const std::vector<int>& group, const std::vector<Eigen::Vector3d>& centroid,
                    std::vector<char>& cut) {
  return SheetSeparator(mesh, part).separate(new_part, f, g, group, centroid, cut);
}

SheetSeparator::SheetSeparator(const Triangulation& mesh, std::vector<int>& part)
    : mesh_(mesh), part_(part) {
  for (int h = 0; h < mesh.num_faces(); ++h) {
    const int p = part[h];
    if (p < 0) continue;
    if (p >= static_cast<int>(faces_.size())) faces_.resize(p + 1);
    faces_[p].push_back(h);
  }
}

SheetSeparator::SheetSeparator(const Triangulation& mesh, std::vector<int>& part,
                               const std::vector<double>& lengths)
    : SheetSeparator(mesh, part) {
  if (static_cast<int>(lengths.size()) != mesh.num_edges()) {
    throw InvalidArgumentError("sheet separator: a length per edge of the mesh is needed");
  }
  lengths_ = &lengths;
}

int SheetSeparator::separate(int new_part, int f, int g, const std::vector<int>& group,
                             const std::vector<Eigen::Vector3d>& centroid, std::vector<char>& cut) {
  const Triangulation& mesh = mesh_;
  std::vector<int>& part = part_;
  const auto group_of = [&](int face) { return group.empty() ? face : group[face]; };
  const int chart = part[f];
  if (chart < 0 || part[g] != chart) return 0;
  // The part's faces by group, the groups numbered locally: the Dijkstra and the marking run over
  // the part alone.
  const size_t num_groups = group.empty() ? mesh.num_faces() : centroid.size();
  if (local_.size() < num_groups) local_.resize(num_groups, -1);
  std::vector<int>& local = local_;
  const std::vector<int>& faces = faces_[chart];
  std::vector<int> first{0};
  for (int h : faces) {
    if (local[group_of(h)] < 0)
      local[group_of(h)] = static_cast<int>(first.size()) - 1, first.push_back(0);
    ++first[local[group_of(h)] + 1];
  }
  const int groups = static_cast<int>(first.size()) - 1;
  for (int k = 0; k < groups; ++k) first[k + 1] += first[k];
  std::vector<int> member(faces.size()), fill(first.begin(), first.end() - 1);
  for (int h : faces) member[fill[local[group_of(h)]]++] = h;
  std::vector<int> share(groups, -1);
  const int seeds[2] = {group_of(f), group_of(g)};
  if (lengths_) {
    // The nearest share and the neck both from the distances to each seed.
    shares_by_distances(chart, member, first, group, centroid, seeds, cut, share);
  } else {
    nearest_share(chart, member, first, group, centroid, seeds, cut, share);
  }
  const auto share_of = [&](int face) {
    const int k = local[group_of(face)];
    return k >= 0 ? share[k] : -1;
  };
  int marked = 0;
  for (int h : faces) {
    for (int c = 0; c < 3; ++c) {
      const int t = mesh.twin(3 * h + c), e = mesh.face_edge(h, c);
      if (t < 0 || cut[e]) continue;
      const int a = share_of(h), b = share_of(t / 3);
      if (a >= 0 && b >= 0 && a != b) cut[e] = 1, ++marked;
    }
  }
  std::vector<int> kept, moved;
  if (marked > 0) {
    for (int h : faces) (share_of(h) == 1 ? moved : kept).push_back(h);
  }
  for (int h : faces) local[group_of(h)] = -1;
  if (marked > 0) {
    for (int h : moved) part[h] = new_part;
    if (new_part >= static_cast<int>(faces_.size())) faces_.resize(new_part + 1);
    faces_[chart] = std::move(kept);
    faces_[new_part] = std::move(moved);
  }
  return marked;
}

// Nearest of the two seeds' groups, over the part's groups (ties to the first reached).
void SheetSeparator::nearest_share(int chart, const std::vector<int>& member,
                                   const std::vector<int>& first, const std::vector<int>& group,
                                   const std::vector<Eigen::Vector3d>& centroid, const int seeds[2],
                                   const std::vector<char>& cut, std::vector<int>& share) const {
  const Triangulation& mesh = mesh_;
  const std::vector<int>& local = local_;
  const auto group_of = [&](int face) { return group.empty() ? face : group[face]; };
  std::vector<double> distance(share.size(), std::numeric_limits<double>::infinity());
  using Item = std::pair<double, int>;  // a group by its own number: ties as the mesh orders them
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  for (int s = 0; s < 2; ++s) {
    distance[local[seeds[s]]] = 0, share[local[seeds[s]]] = s;
    queue.push({0, seeds[s]});
  }
  while (!queue.empty()) {
    const auto [d, a] = queue.top();
    queue.pop();
    const int la = local[a];
    if (d > distance[la]) continue;
    for (int i = first[la]; i < first[la + 1]; ++i) {
      const int h = member[i];
      for (int c = 0; c < 3; ++c) {
        const int t = mesh.twin(3 * h + c);
        if (t < 0 || cut[mesh.face_edge(h, c)]) continue;
        const int b = group_of(t / 3);
        if (b == a || part_[t / 3] != chart) continue;
        const double via = d + (centroid[a] - centroid[b]).norm();
        if (via < distance[local[b]]) {
          distance[local[b]] = via, share[local[b]] = share[la];
          queue.push({via, b});
        }
      }
    }
  }
}

// A level set's seam replaces the nearest share's where it is at most this share of its length:
// a narrower place, not the same width a little to one side (on a uniform strip a level near the
// band's edge can be a few percent shorter by the zigzag of its edges alone, and would part the
// strip a quarter from its end).
constexpr double kClearlyShorter = 0.8;

// From this many groups a part's two distance searches run on two threads.
constexpr int kTwoSearchesFromGroups = 10000;

void SheetSeparator::shares_by_distances(int chart, const std::vector<int>& member,
                                         const std::vector<int>& first,
                                         const std::vector<int>& group,
                                         const std::vector<Eigen::Vector3d>& centroid,
                                         const int seeds[2], const std::vector<char>& cut,
                                         std::vector<int>& share) const {
  const Triangulation& mesh = mesh_;
  const std::vector<int>& local = local_;
  const auto group_of = [&](int face) { return group.empty() ? face : group[face]; };
  const int groups = static_cast<int>(first.size()) - 1;
  constexpr double kFar = std::numeric_limits<double>::infinity();
  // The part's uncut inner edges between groups: (a, b, the edge's length), each edge once.
  struct Side {
    int a, b;
    double length;
  };
  std::vector<Side> sides;
  std::vector<int> rep(groups, -1);  // a group by its global number
  for (int la = 0; la < groups; ++la) {
    for (int i = first[la]; i < first[la + 1]; ++i) {
      const int h = member[i];
      rep[la] = group_of(h);
      for (int c = 0; c < 3; ++c) {
        const int t = mesh.twin(3 * h + c);
        if (t < 0 || t / 3 < h || cut[mesh.face_edge(h, c)] || part_[t / 3] != chart) continue;
        const int lb = local[group_of(t / 3)];
        if (lb != la) sides.push_back({la, lb, (*lengths_)[mesh.face_edge(h, c)]});
      }
    }
  }
  // Each group's neighbours across those sides, in their order, with the step between them (the
  // distance of their centroids): compressed rows.
  std::vector<int> start(groups + 1, 0);
  for (const Side& e : sides) ++start[e.a + 1], ++start[e.b + 1];
  for (int a = 0; a < groups; ++a) start[a + 1] += start[a];
  std::vector<std::pair<int, double>> next(start.back());
  std::vector<int> fill(start.begin(), start.end() - 1);
  for (const Side& e : sides) {
    const double step = (centroid[rep[e.a]] - centroid[rep[e.b]]).norm();
    next[fill[e.a]++] = {e.b, step}, next[fill[e.b]++] = {e.a, step};
  }
  const auto distances = [&](int seed) {
    std::vector<double> d(groups, kFar);
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    d[seed] = 0;
    queue.push({0, seed});
    while (!queue.empty()) {
      const auto [dist, a] = queue.top();
      queue.pop();
      if (dist > d[a]) continue;
      for (int k = start[a]; k < start[a + 1]; ++k) {
        const auto [b, step] = next[k];
        if (dist + step < d[b]) d[b] = dist + step, queue.push({d[b], b});
      }
    }
    return d;
  };
  const int from = local[seeds[0]], to = local[seeds[1]];
  // The two searches on two threads where the part is large (a scan's chart of 100k faces: 9
  // separations of some 30 ms each).
  std::vector<double> df, dg;
  detail::both([&] { df = distances(from); }, [&] { dg = distances(to); },
               groups >= kTwoSearchesFromGroups);
  // The nearest share: each group reached to the nearer seed, at equal distances to f's (the one
  // search from both seeds, nearest_share, gives such a group to the first that reaches it).
  for (int a = 0; a < groups; ++a) {
    if (df[a] < kFar || dg[a] < kFar) share[a] = dg[a] < df[a] ? 1 : 0;
  }
  if (from != to) share[from] = 0, share[to] = 1;  // each seed its own, at no distance apart too
  const double apart = df[to];
  if (!(apart > 0) || !(apart < kFar)) return;
  std::vector<double> level(groups, kFar);
  for (int a = 0; a < groups; ++a) {
    if (df[a] < kFar && dg[a] < kFar) level[a] = df[a] - dg[a];
  }
  // The seam of a level t parts the groups below t from the others: sum of the lengths of the
  // sides whose two levels straddle it.
  std::vector<std::pair<double, double>> events;  // (level, +-length)
  for (const Side& e : sides) {
    const double lo = std::min(level[e.a], level[e.b]), hi = std::max(level[e.a], level[e.b]);
    if (!(hi < kFar) || lo == hi) continue;
    events.push_back({lo, e.length}), events.push_back({hi, -e.length});
  }
  std::sort(events.begin(), events.end());
  const double lowest = -kSeparationBand * apart, highest = kSeparationBand * apart;
  // The least sum; among sums equal to rounding, the level nearest the middle (a uniform strip
  // parts in its middle, as the nearest share parts it).
  double running = 0, best = kFar, best_t = 0, best_off = kFar;
  for (size_t i = 0; i < events.size(); ++i) {
    running += events[i].second;
    // For t just above this level (up to the next): the sides counted so far straddle it.
    if (i + 1 < events.size() && events[i + 1].first == events[i].first) continue;
    const double t_next = i + 1 < events.size() ? events[i + 1].first : kFar;
    const double t = std::min(t_next, highest);
    if (t <= events[i].first || t < lowest || events[i].first >= highest) continue;
    // How far the levels of (events[i], t] come to the middle.
    const double off = events[i].first >= 0 ? events[i].first : (t < 0 ? -t : 0);
    const bool tie = std::abs(running - best) <= 1e-12 * best;
    if ((running < best && !tie) || (tie && off < best_off)) {
      best = running, best_t = t, best_off = off;
    }
  }
  if (!(best < kFar)) return;
  // f's side: the groups below the level connected to f; g's: those connected to g among the
  // others; the rest (enclosed by f's side) joins f's.
  std::vector<int> side(groups, -1);
  const auto flood = [&](int seed, int label, const auto& may) {
    std::vector<int> stack{seed};
    side[seed] = label;
    while (!stack.empty()) {
      const int a = stack.back();
      stack.pop_back();
      for (int k = start[a]; k < start[a + 1]; ++k) {
        const int b = next[k].first;
        if (side[b] < 0 && may(b)) side[b] = label, stack.push_back(b);
      }
    }
  };
  flood(from, 0, [&](int a) { return level[a] < best_t; });
  if (side[to] >= 0) return;
  flood(to, 1, [](int) { return true; });
  for (int a = 0; a < groups; ++a) {
    if (side[a] < 0 && level[a] < kFar) side[a] = 0;
  }
  double shorter = 0, nearest = 0;
  for (const Side& e : sides) {
    if (side[e.a] >= 0 && side[e.b] >= 0 && side[e.a] != side[e.b]) shorter += e.length;
    if (share[e.a] >= 0 && share[e.b] >= 0 && share[e.a] != share[e.b]) nearest += e.length;
  }
  if (!(shorter < kClearlyShorter * nearest)) return;
  for (int a = 0; a < groups; ++a) {
    if (side[a] >= 0) share[a] = side[a];
  }
}

std::vector<char> unchanged_clean_charts(const Charts& now, const Charts& before,
                                         const std::vector<std::pair<int, int>>& before_overlaps) {
  std::vector<char> dirty_before(before.num_charts, 0);
  for (const auto& [f, g] : before_overlaps) dirty_before[before.chart[f]] = 1;
  std::vector<int> size_now(now.num_charts, 0), size_before(before.num_charts, 0);
  for (int c : now.chart) ++size_now[c];
  for (int c : before.chart) ++size_before[c];
  // The chart of `before` each chart of `now` came from (-1: from several, or laid out anew).
  std::vector<int> origin(now.num_charts, -2);
  for (size_t f = 0; f < now.chart.size(); ++f) {
    int& o = origin[now.chart[f]];
    const int b = before.chart[f];
    const bool same = now.corners[f] == before.corners[f];
    if (o == -2) o = b;
    if (o != b || !same) o = -1;
  }
  std::vector<char> clean(now.num_charts, 0);
  for (int c = 0; c < now.num_charts; ++c) {
    const int o = origin[c];
    clean[c] = o >= 0 && !dirty_before[o] && size_before[o] == size_now[c];
  }
  return clean;
}

}  // namespace ricci
