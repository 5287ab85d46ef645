// The charts of an atlas turned to meet by quarter turns (charts.h).
#include <algorithm>
#include <cmath>
#include <map>
#include <queue>
#include <utility>
#include <vector>

#include "ricci/layout/charts.h"

namespace ricci {

namespace {

// A side of a face drawn in one chart whose edge the face across it draws in another.
struct ChartSide {
  int f, c;  // the side from corner c to corner c + 1 of face f
  int g, d;  // the same edge, from corner d + 1 to corner d of face g
  double length;
};

}  // namespace

void turn_charts_to_quarter_turns(const std::vector<std::array<int, 3>>& faces, Charts& charts) {
  std::map<std::pair<int, int>, std::pair<int, int>> side_of;  // (from, to) vertex: face, corner
  for (size_t f = 0; f < faces.size(); ++f) {
    for (int c = 0; c < 3; ++c) {
      side_of[{faces[f][c], faces[f][(c + 1) % 3]}] = {static_cast<int>(f), c};
    }
  }
  // Per chart, its sides on seams to other charts, the longest first.
  std::vector<std::vector<ChartSide>> sides(static_cast<size_t>(charts.num_charts));
  for (size_t f = 0; f < faces.size(); ++f) {
    for (int c = 0; c < 3; ++c) {
      const auto twin = side_of.find({faces[f][(c + 1) % 3], faces[f][c]});
      if (twin == side_of.end()) continue;
      const auto [g, d] = twin->second;
      if (charts.chart[f] == charts.chart[static_cast<size_t>(g)]) continue;
      const double length = (charts.corners[f][(c + 1) % 3] - charts.corners[f][c]).norm();
      sides[static_cast<size_t>(charts.chart[f])].push_back({static_cast<int>(f), c, g, d, length});
    }
  }
  for (auto& s : sides) {
    std::stable_sort(s.begin(), s.end(),
                     [](const ChartSide& a, const ChartSide& b) { return a.length > b.length; });
  }
  std::vector<std::vector<int>> faces_of(static_cast<size_t>(charts.num_charts));
  for (size_t f = 0; f < faces.size(); ++f) {
    faces_of[static_cast<size_t>(charts.chart[f])].push_back(static_cast<int>(f));
  }
  // From each chart not yet reached (chart 0 first), outwards: a chart reached is turned so that
  // its drawing of the longest side it shares with the chart it is reached from runs along that
  // chart's.
  std::vector<char> reached(static_cast<size_t>(charts.num_charts), 0);
  for (int root = 0; root < charts.num_charts; ++root) {
    if (reached[static_cast<size_t>(root)]) continue;
    reached[static_cast<size_t>(root)] = 1;
    std::queue<int> todo;
    todo.push(root);
    while (!todo.empty()) {
      const int a = todo.front();
      todo.pop();
      for (const ChartSide& s : sides[static_cast<size_t>(a)]) {
        const int b = charts.chart[static_cast<size_t>(s.g)];
        if (reached[static_cast<size_t>(b)]) continue;
        reached[static_cast<size_t>(b)] = 1;
        const auto& p = charts.corners[static_cast<size_t>(s.f)];
        const auto& q = charts.corners[static_cast<size_t>(s.g)];
        const Eigen::Vector2d along_a = p[(s.c + 1) % 3] - p[s.c];
        const Eigen::Vector2d along_b = q[s.d] - q[(s.d + 1) % 3];
        const double turn =
            std::atan2(along_a.y(), along_a.x()) - std::atan2(along_b.y(), along_b.x());
        Eigen::Matrix2d r;
        r << std::cos(turn), -std::sin(turn), std::sin(turn), std::cos(turn);
        for (int f : faces_of[static_cast<size_t>(b)]) {
          for (Eigen::Vector2d& x : charts.corners[static_cast<size_t>(f)]) x = r * x;
        }
        todo.push(b);
      }
    }
  }
}

}  // namespace ricci
