#include "result_obj.h"

#include <cstdio>
#include <map>
#include <memory>
#include <utility>

#include "ricci/mesh/errors.h"

namespace ricci::cli {

void write_result_obj(const std::string& path, const MeshUniformization& run) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> out(std::fopen(path.c_str(), "wb"), &std::fclose);
  if (!out) throw IoError("cannot write '" + path + "' (missing folder or no permission)");
  std::FILE* f = out.get();
  std::fprintf(f, "# ricci-flow result: unified discrete surface Ricci flow\n");
  for (const Eigen::Vector3d& p : run.positions) {
    std::fprintf(f, "v %.17g %.17g %.17g\n", p.x(), p.y(), p.z());
  }
  const auto& faces = run.faces;
  if (!run.texture.vertex.empty()) {
    for (const Eigen::Vector2d& t : run.texture.vertex)
      std::fprintf(f, "vt %.17g %.17g\n", t.x(), t.y());
    for (const auto& t : faces) {
      std::fprintf(f, "f %d/%d %d/%d %d/%d\n", t[0] + 1, t[0] + 1, t[1] + 1, t[1] + 1, t[2] + 1,
                   t[2] + 1);
    }
  } else if (!run.texture.wedge.empty()) {
    // One texture vertex per vertex and distinct position: corners of a wedge share it.
    std::map<std::pair<int, std::pair<double, double>>, int> index;
    std::vector<std::array<int, 3>> corner(faces.size());
    for (size_t k = 0; k < faces.size(); ++k) {
      for (int c = 0; c < 3; ++c) {
        const Eigen::Vector2d& t = run.texture.wedge[k][c];
        const auto key = std::pair{faces[k][c], std::pair{t.x(), t.y()}};
        auto [at, added] = index.emplace(key, static_cast<int>(index.size()));
        if (added) std::fprintf(f, "vt %.17g %.17g\n", t.x(), t.y());
        corner[k][c] = at->second;
      }
    }
    for (size_t k = 0; k < faces.size(); ++k) {
      const auto& t = faces[k];
      std::fprintf(f, "f %d/%d %d/%d %d/%d\n", t[0] + 1, corner[k][0] + 1, t[1] + 1,
                   corner[k][1] + 1, t[2] + 1, corner[k][2] + 1);
    }
  } else {
    for (const auto& t : faces) std::fprintf(f, "f %d %d %d\n", t[0] + 1, t[1] + 1, t[2] + 1);
  }
  if (std::ferror(f)) throw IoError("cannot write '" + path + "' (disk full?)");
}

}  // namespace ricci::cli
