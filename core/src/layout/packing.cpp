#include "ricci/layout/packing.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numeric>
#include <string>

#include "mesh/plane.h"
#include "mesh/two_threads.h"
#include "ricci/mesh/errors.h"

namespace ricci {

namespace {

// A chart is tried in each of its four quarter turns: an L or a crescent fits some corners
// turned by a half (the cow: utilization 0.604 with upright and quarter turns only, 0.624).
constexpr int kTurns = 4;
// Packings at most, each with the margin the last one's extent asks for, while each brings the
// margin nearer to that by at least this share.
constexpr int kMaxPackings = 6;
constexpr double kNearer = 0.01;

using detail::cross;

using Triangle = std::array<Eigen::Vector2d, 3>;
using Triangles = std::vector<Triangle>;

// Andrew's monotone chain, counter-clockwise.
std::vector<Eigen::Vector2d> convex_hull(std::vector<Eigen::Vector2d> p) {
  // Points well inside the quadrilateral of the leftmost, lowest, rightmost and highest ones are
  // not on the hull: dropped before the sort (a chart's corners are mostly inside).
  if (p.size() > 8) {
    std::array<Eigen::Vector2d, 4> quad = {p[0], p[0], p[0], p[0]};  // counter-clockwise
    for (const auto& q : p) {
      if (q.x() < quad[0].x()) quad[0] = q;
      if (q.y() < quad[1].y()) quad[1] = q;
      if (q.x() > quad[2].x()) quad[2] = q;
      if (q.y() > quad[3].y()) quad[3] = q;
    }
    const double size = (quad[2].x() - quad[0].x()) + (quad[3].y() - quad[1].y());
    const double well = 1e-9 * size * size;
    const auto inside = [&](const Eigen::Vector2d& q) {
      for (int i = 0; i < 4; ++i) {
        if (!(cross(quad[(i + 1) % 4] - quad[i], q - quad[i]) > well)) return false;
      }
      return true;
    };
    p.erase(std::remove_if(p.begin(), p.end(), inside), p.end());
  }
  std::sort(p.begin(), p.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  if (p.size() < 3) return p;
  std::vector<Eigen::Vector2d> h(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 1] - h[k - 2], p[i] - h[k - 2]) <= 0) --k;
    h[k++] = p[i];
  }
  for (size_t i = p.size() - 1, t = k + 1; i > 0; --i) {
    while (k >= t && cross(h[k - 1] - h[k - 2], p[i - 1] - h[k - 2]) <= 0) --k;
    h[k++] = p[i - 1];
  }
  h.resize(k - 1);
  return h;
}

// The rotation that puts the chart's smallest bounding rectangle upright and wider than tall
// (the rectangle has a side on a hull edge).
Eigen::Matrix2d upright(const Triangles& chart) {
  std::vector<Eigen::Vector2d> points;
  for (const Triangle& t : chart) points.insert(points.end(), t.begin(), t.end());
  const std::vector<Eigen::Vector2d> hull = convex_hull(points);
  Eigen::Matrix2d best = Eigen::Matrix2d::Identity();
  double smallest = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < hull.size(); ++i) {
    const Eigen::Vector2d e = hull[(i + 1) % hull.size()] - hull[i];
    if (!(e.norm() > 0)) continue;
    const Eigen::Vector2d d = e.normalized();
    Eigen::Matrix2d r;
    r << d.x(), d.y(), -d.y(), d.x();  // turns d onto the x axis
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(INFINITY), hi = -lo;
    for (const auto& q : hull) lo = lo.cwiseMin(r * q), hi = hi.cwiseMax(r * q);
    const Eigen::Vector2d size = hi - lo;
    if (size.prod() < smallest) {
      smallest = size.prod();
      best = r;
      if (size.y() > size.x()) best = Eigen::Matrix2d{{0, 1}, {-1, 0}} * r;
    }
  }
  return best;
}

// A bit raster, row by row.
class Mask {
 public:
  Mask(int width, int height)
      : width_(width),
        height_(height),
        words_((width + 63) / 64 + 1),
        bits_(static_cast<size_t>(words_) * height, 0) {}
  int width() const { return width_; }
  int height() const { return height_; }
  bool get(int x, int y) const { return (row(y)[x / 64] >> (x % 64)) & 1; }
  void set(int x, int y) { row(y)[x / 64] |= std::uint64_t{1} << (x % 64); }
  // 64 bits of row y from column x on.
  std::uint64_t window(int y, int x) const {
    const std::uint64_t* r = row(y);
    const int w = x / 64, s = x % 64;
    const std::uint64_t low = r[w] >> s;
    return s == 0 || w + 1 >= words_ ? low : low | (r[w + 1] << (64 - s));
  }
  int words() const { return words_; }
  bool operator==(const Mask& o) const {
    return width_ == o.width_ && height_ == o.height_ && bits_ == o.bits_;
  }
  const std::uint64_t* row(int y) const { return bits_.data() + static_cast<size_t>(y) * words_; }
  std::uint64_t* row(int y) { return bits_.data() + static_cast<size_t>(y) * words_; }
  // Grown to at least width x height, the bits kept.
  void grow(int width, int height) {
    Mask bigger(std::max(width, width_), std::max(height, height_));
    for (int y = 0; y < height_; ++y) {
      std::copy(row(y), row(y) + words_, bigger.row(y));
    }
    *this = std::move(bigger);
  }

 private:
  int width_, height_, words_;
  std::vector<std::uint64_t> bits_;
};

// A chart turned by `rotation`, rasterized on cells of `cell` from `origin`, every cell set that
// the chart comes within `margin` of (in the maximum norm): two charts whose rasters share no cell
// are then at least twice the margin apart (a point nearer than that to both lies in a cell of
// both).
struct Raster {
  Eigen::Matrix2d rotation;
  Eigen::Vector2d origin;  // the lower-left corner of cell (0, 0), in the turned chart
  Mask mask{1, 1};
};

bool triangle_meets_box(const Triangle& t, const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
  Eigen::Vector2d a = t[0], b = t[0];
  for (const auto& q : t) a = a.cwiseMin(q), b = b.cwiseMax(q);
  if (a.x() > hi.x() || b.x() < lo.x() || a.y() > hi.y() || b.y() < lo.y()) return false;
  const double orientation = cross(t[1] - t[0], t[2] - t[0]) >= 0 ? 1 : -1;
  const std::array<Eigen::Vector2d, 4> box{lo, Eigen::Vector2d(hi.x(), lo.y()), hi,
                                           Eigen::Vector2d(lo.x(), hi.y())};
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector2d e = t[(i + 1) % 3] - t[i];
    bool all_outside = true;
    for (const auto& q : box) all_outside = all_outside && orientation * cross(e, q - t[i]) < 0;
    if (all_outside) return false;
  }
  return true;
}

Raster rasterize(const Triangles& chart, const Eigen::Matrix2d& rotation, double cell,
                 double margin) {
  Raster r;
  r.rotation = rotation;
  Triangles turned;
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(INFINITY), hi = -lo;
  for (const Triangle& t : chart) {
    Triangle u{rotation * t[0], rotation * t[1], rotation * t[2]};
    for (const auto& q : u) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
    turned.push_back(u);
  }
  r.origin = lo - Eigen::Vector2d::Constant(margin);
  const int width = static_cast<int>(std::ceil((hi.x() - lo.x() + 2 * margin) / cell)) + 1;
  const int height = static_cast<int>(std::ceil((hi.y() - lo.y() + 2 * margin) / cell)) + 1;
  r.mask = Mask(width, height);
  const Eigen::Vector2d grown = Eigen::Vector2d::Constant(margin);
  for (const Triangle& t : turned) {
    Eigen::Vector2d a = t[0], b = t[0];
    for (const auto& q : t) a = a.cwiseMin(q), b = b.cwiseMax(q);
    // The cells whose boxes, grown by the margin, meet the triangle's box.
    const Eigen::Vector2d from = (a - r.origin - grown) / cell, to = (b - r.origin + grown) / cell;
    const int x0 = std::max(0, static_cast<int>(std::floor(from.x()))),
              x1 = std::min(width - 1, static_cast<int>(to.x()));
    const int y0 = std::max(0, static_cast<int>(std::floor(from.y()))),
              y1 = std::min(height - 1, static_cast<int>(to.y()));
    // A cell's grown box meets the triangle where the cell's corner lies in the triangle grown by
    // the box (convex): along a row those cells are one run. The cells not yet set that it meets
    // lie between the first and the last of them, found from the row's two ends.
    const auto meets = [&](int x, int y) {
      if (r.mask.get(x, y)) return false;
      const Eigen::Vector2d c0 = r.origin + cell * Eigen::Vector2d(x, y);
      return triangle_meets_box(t, c0 - grown, c0 + Eigen::Vector2d::Constant(cell) + grown);
    };
    for (int y = y0; y <= y1; ++y) {
      int first = x0;
      while (first <= x1 && !meets(first, y)) ++first;
      if (first > x1) continue;
      int last = x1;
      while (last > first && !meets(last, y)) --last;
      for (int x = first; x <= last; ++x) r.mask.set(x, y);
    }
  }
  return r;
}

// A raster turned a quarter counter-clockwise, (x, y) to (-y, x): cell (i, j) of `r` becomes cell
// (height - 1 - j, i), each cell's box (grown by the margin, in the maximum norm) that of its turn,
// so the turn holds just the cells that the turned chart comes within the margin of: the raster of
// the turned chart, on a grid aligned to the turned one's.
Raster quarter_turned(const Raster& r, double cell) {
  const Eigen::Matrix2d quarter{{0, -1}, {1, 0}};
  const int width = r.mask.width(), height = r.mask.height();
  Raster t;
  t.rotation = quarter * r.rotation;
  t.origin = Eigen::Vector2d(-(r.origin.y() + cell * height), r.origin.x());
  t.mask = Mask(height, width);
  for (int j = 0; j < height; ++j) {
    for (int i = 0; i < width; ++i) {
      if (r.mask.get(i, j)) t.mask.set(height - 1 - j, i);
    }
  }
  return t;
}

// The raster cut to the rows and columns that hold a set cell (its grid rounds the chart's box up
// by a cell or two on one side, which a quarter turn moves to the low side, where it would keep
// the chart a cell off the atlas's sides).
Raster trimmed(const Raster& r, double cell) {
  const Mask& m = r.mask;
  int x0 = m.width(), x1 = -1, y0 = m.height(), y1 = -1;
  for (int y = 0; y < m.height(); ++y) {
    for (int x = 0; x < m.width(); ++x) {
      if (!m.get(x, y)) continue;
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
  }
  if (x1 < 0 || (x0 == 0 && y0 == 0 && x1 == m.width() - 1 && y1 == m.height() - 1)) return r;
  Raster t;
  t.rotation = r.rotation;
  t.origin = r.origin + cell * Eigen::Vector2d(x0, y0);
  t.mask = Mask(x1 - x0 + 1, y1 - y0 + 1);
  for (int y = y0; y <= y1; ++y) {
    for (int x = x0; x <= x1; ++x) {
      if (m.get(x, y)) t.mask.set(x - x0, y - y0);
    }
  }
  return t;
}

// Bits as a row of cells: bit i of word i / 64 is cell i.
using Bits = std::vector<std::uint64_t>;

// out[i] = in[i + s] (cells past the end read as 0).
void shift_down(const Bits& in, int s, Bits& out) {
  const int n = static_cast<int>(in.size()), w = s / 64, b = s % 64;
  for (int i = 0; i < n; ++i) {
    const std::uint64_t low = i + w < n ? in[i + w] : 0;
    const std::uint64_t high = i + w + 1 < n ? in[i + w + 1] : 0;
    out[i] = b == 0 ? low : (low >> b) | (high << (64 - b));
  }
}

// The runs of set cells of each row of a mask: (row, first cell, length), the longest first.
std::vector<std::array<int, 3>> runs_of(const Mask& m) {
  std::vector<std::array<int, 3>> runs;
  for (int r = 0; r < m.height(); ++r) {
    for (int c = 0; c < m.width();) {
      if (!m.get(c, r)) {
        ++c;
        continue;
      }
      int end = c;
      while (end < m.width() && m.get(end, r)) ++end;
      runs.push_back({r, c, end - c});
      c = end;
    }
  }
  // The longest first: they rule out the most places, and a row where the chart fits nowhere is
  // left after fewest runs.
  std::stable_sort(runs.begin(), runs.end(),
                   [](const auto& a, const auto& b) { return a[2] > b[2]; });
  return runs;
}

// Where a chart's mask fits in the atlas with its lower-left cell at row y: bit x of `valid` for
// every x at which no set cell of the chart meets a set cell of the atlas (x up to the atlas's
// width less the chart's). Every row of cells at once, a word at a time: for a run of `length`
// set cells from cell a of chart row r, the cells x at which atlas row y + r is free over
// [x + a, x + a + length) are the free cells' runs of that length (by doubling shifts), moved down
// by a. False when none fits.
class FitRows {
 public:
  explicit FitRows(int atlas_width) : words_((atlas_width + 63) / 64), width_(atlas_width) {
    free_.resize(words_), run_.resize(words_), shifted_.resize(words_), valid_.resize(words_);
  }
  const Bits& valid() const { return valid_; }
  bool at(const Mask& atlas, int width, const std::vector<std::array<int, 3>>& runs, int y) {
    const int last = width_ - width;  // the largest x
    if (last < 0) return false;
    std::fill(valid_.begin(), valid_.end(), ~std::uint64_t{0});
    keep_below(valid_, last + 1);
    int row = -1;
    for (const auto& [r, a, length] : runs) {
      if (r != row) {
        row = r;
        const std::uint64_t* bits = atlas.row(y + r);
        for (int i = 0; i < words_; ++i) free_[i] = ~bits[i];
        keep_below(free_, width_);
      }
      run_ = free_;
      for (int have = 1; have < length;) {
        const int step = std::min(have, length - have);
        shift_down(run_, step, shifted_);
        for (int i = 0; i < words_; ++i) run_[i] &= shifted_[i];
        have += step;
      }
      shift_down(run_, a, shifted_);
      std::uint64_t any = 0;
      for (int i = 0; i < words_; ++i) any |= valid_[i] &= shifted_[i];
      if (any == 0) return false;
    }
    return true;
  }

 private:
  // Clears the cells from `end` on.
  static void keep_below(Bits& bits, int end) {
    for (int i = 0; i < static_cast<int>(bits.size()); ++i) {
      const int first = 64 * i;
      if (first >= end) {
        bits[i] = 0;
      } else if (end - first < 64) {
        bits[i] &= (std::uint64_t{1} << (end - first)) - 1;
      }
    }
  }
  int words_, width_;
  Bits free_, run_, shifted_, valid_;
};

// The lowest set cell, or -1.
int lowest(const Bits& bits) {
  for (size_t i = 0; i < bits.size(); ++i) {
    if (bits[i]) return static_cast<int>(64 * i) + __builtin_ctzll(bits[i]);
  }
  return -1;
}

void place(Mask& atlas, const Mask& chart, int x, int y) {
  for (int r = 0; r < chart.height(); ++r) {
    for (int c = 0; c < chart.width(); ++c) {
      if (chart.get(c, r)) atlas.set(x + c, y + r);
    }
  }
}

// work(k) for every chart k; on two threads where the charts have kTwoThreadsFromIterations
// triangles or more (the many parts of an assembly packed together), split where each half has
// about half of them. Each chart's work writes its own slots only.
template <class Work>
void for_each_chart(const std::vector<Triangles>& charts, const Work& work) {
  size_t total = 0;
  for (const Triangles& c : charts) total += c.size();
  if (total < static_cast<size_t>(detail::kTwoThreadsFromIterations)) {
    for (size_t k = 0; k < charts.size(); ++k) work(k);
    return;
  }
  size_t middle = 0;
  for (size_t half = 0; middle < charts.size() && 2 * half < total;)
    half += charts[middle++].size();
  detail::both(
      [&] {
        for (size_t k = 0; k < middle; ++k) work(k);
      },
      [&] {
        for (size_t k = middle; k < charts.size(); ++k) work(k);
      },
      true);
}

double area_of(const Triangles& chart) {
  double a = 0;
  for (const Triangle& t : chart) a += 0.5 * std::abs(cross(t[1] - t[0], t[2] - t[0]));
  return a;
}

// One packing at a cell size and padding (in cells); returns the extent in cells.
struct Placed {
  std::vector<const Raster*> raster;
  std::vector<Eigen::Vector2i> at;
  Eigen::Vector2i extent = Eigen::Vector2i::Zero();
};

Placed pack_rasters(const std::vector<std::array<Raster, kTurns>>& rasters,
                    const std::vector<size_t>& order, long cells) {
  Placed p;
  p.raster.assign(rasters.size(), nullptr);
  p.at.assign(rasters.size(), Eigen::Vector2i::Zero());
  int side = static_cast<int>(std::ceil(std::sqrt(static_cast<double>(cells) / 0.7)));
  for (const auto& both : rasters) {
    side = std::max(side, std::min(both[0].mask.width(), both[0].mask.height()));
  }
  Mask atlas(side, side);
  // Per row of the atlas, its leftmost free cell (its width where it has none); per row of a
  // chart's turn, its leftmost set cell: a chart placed at row y lies at x no lower than any of
  // its rows' leftmost free cell less that row's leftmost set cell, and a row where that bound
  // already scores no better than the best place found is passed by without the fit's shifts.
  std::vector<int> first_free(atlas.height(), 0);
  const auto measure_row = [&](int y) {
    int x = 0;
    while (x < atlas.width() && atlas.get(x, y)) ++x;
    first_free[y] = x;
  };
  for (size_t k : order) {
    std::array<std::vector<std::array<int, 3>>, kTurns> runs;
    for (int t = 0; t < kTurns; ++t) runs[t] = runs_of(rasters[k][t].mask);
    std::array<std::vector<std::pair<int, int>>, kTurns> leftmost;  // (row, its first set cell)
    for (int t = 0; t < kTurns; ++t) {
      const Mask& m = rasters[k][t].mask;
      for (int r = 0; r < m.height(); ++r) {
        for (int c = 0; c < m.width(); ++c) {
          if (m.get(c, r)) {
            leftmost[t].push_back({r, c});
            break;
          }
        }
      }
    }
    // A turn whose cells are an earlier turn's fits where that one does, and ties go to the
    // earlier turn: not searched (most small charts' rasters are the same in every turn, or in
    // every other).
    std::array<bool, kTurns> repeated{};
    for (int t = 1; t < kTurns; ++t) {
      for (int u = 0; u < t && !repeated[t]; ++u) {
        repeated[t] = rasters[k][t].mask == rasters[k][u].mask;
      }
    }
    while (true) {
      // Least growth of the square's side, then of the used area, then bottom-left (ties to the
      // upright turn, then the lowest row, then the leftmost cell). At one row the score grows
      // with x, so the row's leftmost fit is its best; over the rows, the score of x = 0 grows
      // with y, and bounds the rows above from below.
      const auto score = [&](int x, int y, const Mask& m) {
        const int ex = std::max(p.extent.x(), x + m.width());
        const int ey = std::max(p.extent.y(), y + m.height());
        return (static_cast<std::int64_t>(std::max(ex, ey)) << 40) +
               (static_cast<std::int64_t>(ex) * ey << 8) + y;
      };
      std::int64_t best = std::numeric_limits<std::int64_t>::max();
      FitRows fit(atlas.width());
      for (int turn = 0; turn < kTurns; ++turn) {
        if (repeated[turn]) continue;
        const Mask& m = rasters[k][turn].mask;
        for (int y = 0; y + m.height() <= atlas.height(); ++y) {
          if (score(0, y, m) >= best) break;
          int from = 0;
          for (const auto& [r, c] : leftmost[turn]) from = std::max(from, first_free[y + r] - c);
          if (from + m.width() > atlas.width() || score(from, y, m) >= best) continue;
          if (!fit.at(atlas, m.width(), runs[turn], y)) continue;
          const int x = lowest(fit.valid());
          if (x < 0 || score(x, y, m) >= best) continue;
          best = score(x, y, m);
          p.raster[k] = &rasters[k][turn];
          p.at[k] = Eigen::Vector2i(x, y);
        }
      }
      if (best < std::numeric_limits<std::int64_t>::max()) break;
      atlas.grow(atlas.width() + atlas.width() / 4 + 1, atlas.height() + atlas.height() / 4 + 1);
      first_free.resize(atlas.height());
      for (int y = 0; y < atlas.height(); ++y) measure_row(y);
    }
    const Mask& m = p.raster[k]->mask;
    place(atlas, m, p.at[k].x(), p.at[k].y());
    for (int r = 0; r < m.height(); ++r) measure_row(p.at[k].y() + r);
    p.extent = p.extent.cwiseMax(p.at[k] + Eigen::Vector2i(m.width(), m.height()));
  }
  return p;
}

}  // namespace

void check_packing_options(const PackingOptions& o) {
  if (o.texture_size < kMinTextureSize || o.padding < 0) {
    throw InvalidArgumentError("packing: the texture size must be at least " +
                               std::to_string(kMinTextureSize) +
                               " texels and the padding non-negative");
  }
}

Packing pack_charts(const std::vector<Triangles>& charts, const PackingOptions& o,
                    double expected_utilization) {
  check_packing_options(o);
  Packing packing;
  const size_t n = charts.size();
  packing.rotation.assign(n, Eigen::Matrix2d::Identity());
  packing.offset.assign(n, Eigen::Vector2d::Zero());
  double total = 0;
  std::vector<double> area(n);
  for (size_t k = 0; k < n; ++k) total += area[k] = area_of(charts[k]);
  if (!(total > 0)) return packing;
  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return area[a] > area[b]; });
  std::vector<Eigen::Matrix2d> up(n);
  std::vector<Eigen::Vector2d> lo(n, Eigen::Vector2d::Zero()), hi = lo;  // upright boxes
  for_each_chart(charts, [&](size_t k) {
    up[k] = o.quarter_turns_only ? Eigen::Matrix2d::Identity() : upright(charts[k]);
    if (charts[k].empty()) return;
    lo[k] = Eigen::Vector2d::Constant(INFINITY), hi[k] = -lo[k];
    for (const Triangle& t : charts[k]) {
      for (const auto& q : t) lo[k] = lo[k].cwiseMin(up[k] * q), hi[k] = hi[k].cwiseMax(up[k] * q);
    }
  });
  // A hint outside (0, 1] is no utilization; below 0.1 it would pad far more than asked.
  const bool expected = expected_utilization > 0 && expected_utilization <= 1;
  double extent = std::sqrt(total / (expected ? std::max(expected_utilization, 0.1) : 0.6));
  const long charted =
      std::count_if(charts.begin(), charts.end(), [](const Triangles& c) { return !c.empty(); });
  const bool alone = charted == 1 && o.padding < o.texture_size;
  if (alone) {
    // One chart: its smallest box, upright, spans the square's width within half the padding,
    // with no raster (rasterizing each of a mesh's 3,728 one-chart parts at 20k cells in four
    // turns took 9 of its 13 s, when each part was packed alone too).
    const size_t k = order[0];  // the largest, the one with area (total > 0)
    extent = (hi[k] - lo[k]).maxCoeff() / (1 - static_cast<double>(o.padding) / o.texture_size);
    packing.rotation[k] = up[k];
    packing.offset[k] =
        Eigen::Vector2d::Constant(0.5 * o.padding * extent / o.texture_size) - lo[k];
  }
  // About 20k cells of chart area. Half the padding is the rasters' margin, in the charts' units
  // from the extent it gives (3 % wider, so that an extent a little larger than the guess needs
  // no second packing), again where the extent came out larger still: the margin then grows
  // towards the padding's, unless the charts are too many for the texture at that padding, and
  // the packing stops once an attempt brings it no nearer.
  // Each packing tried is kept where its padding is the widest yet (the last, where it meets the
  // padding asked), judged at its rasters' extent, which the charts' own box below can only
  // shrink (a margin met there is met after).
  Packing tried = packing;
  packing.padding = -1;
  double shortfall = INFINITY;  // the padding needed over the margin's, as last packed
  double packed_extent = extent, packed_margin = 0;
  for (int attempt = 0; attempt < kMaxPackings && !alone; ++attempt) {
    const double margin = 1.03 * 0.5 * o.padding * extent / o.texture_size;
    // At most about 80k cells over the rasters (the charts' upright boxes with their margins):
    // where those are over four times the charts' area (many small charts in a small texture,
    // or charts that fill little of their boxes), larger cells.
    double rastered = 0;
    for (size_t k = 0; k < n; ++k) {
      const Eigen::Vector2d side = hi[k] - lo[k] + Eigen::Vector2d::Constant(2 * margin);
      if (!charts[k].empty()) rastered += side.x() * side.y();
    }
    const double cell = std::max(std::sqrt(total / 20000), std::sqrt(rastered / 80000));
    std::vector<std::array<Raster, kTurns>> rasters(n);
    for_each_chart(charts, [&](size_t k) {
      if (charts[k].empty()) return;
      rasters[k][0] = trimmed(rasterize(charts[k], up[k], cell, margin), cell);
      for (int t = 1; t < kTurns; ++t) rasters[k][t] = quarter_turned(rasters[k][t - 1], cell);
    });
    std::vector<size_t> nonempty;
    long cells = 0;
    for (size_t k : order) {
      if (charts[k].empty()) continue;
      nonempty.push_back(k);
      cells += static_cast<long>(rasters[k][0].mask.width()) * rasters[k][0].mask.height();
    }
    const Placed placed = pack_rasters(rasters, nonempty, cells);
    extent = cell * placed.extent.maxCoeff();
    for (size_t k : nonempty) {
      const Raster& r = *placed.raster[k];
      tried.rotation[k] = r.rotation;
      tried.offset[k] = placed.at[k].cast<double>() * cell - r.origin;
    }
    // Rasters that share no cell are twice the margin apart: in texels of this extent's texture.
    const double needed = 0.5 * o.padding * extent / o.texture_size;
    tried.padding = needed <= margin ? o.padding : o.padding * margin / needed;
    if (tried.padding > packing.padding) {
      packing = tried, packed_extent = extent, packed_margin = margin;
    }
    if (needed <= margin || !(needed / margin < shortfall * (1 - kNearer))) break;
    shortfall = needed / margin;
  }
  if (alone) packing.padding = o.padding;
  extent = packed_extent;
  if (!alone) {
    // The rasters' cells round each chart's box up by a cell or two: the square is the placed
    // charts' own box instead, with half the padding at its sides, or, where the charts are nearer
    // than the padding (too many for the texture), half their distance, the rasters' margin.
    Eigen::Vector2d low = Eigen::Vector2d::Constant(INFINITY), high = -low;
    for (size_t k = 0; k < n; ++k) {
      for (const Triangle& t : charts[k]) {
        for (const auto& q : t) {
          const Eigen::Vector2d p = packing.rotation[k] * q + packing.offset[k];
          low = low.cwiseMin(p), high = high.cwiseMax(p);
        }
      }
    }
    const double span = (high - low).maxCoeff();
    const double padded = 1 - static_cast<double>(o.padding) / o.texture_size;
    const double tight = std::min(padded > 0 ? span / padded : INFINITY, span + 2 * packed_margin);
    if (tight < extent) {
      const Eigen::Vector2d from = low - Eigen::Vector2d::Constant(0.5 * (tight - span));
      for (size_t k = 0; k < n; ++k) {
        if (!charts[k].empty()) packing.offset[k] -= from;
      }
      extent = tight;
      // Rasters that share no cell are twice their margin apart: in texels of the tighter texture.
      packing.padding = std::min<double>(o.padding, 2 * packed_margin * o.texture_size / extent);
    }
  }
  packing.scale = 1 / extent;
  for (auto& b : packing.offset) b *= packing.scale;
  packing.utilization = total * packing.scale * packing.scale;
  const double texel = 1 / (static_cast<double>(o.texture_size) * o.texture_size);
  for (size_t k = 0; k < n; ++k) {
    packing.below_a_texel += !charts[k].empty() && area[k] * packing.scale * packing.scale < texel;
  }
  return packing;
}

}  // namespace ricci
