#include "result_ply.h"

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <limits>

#include "ricci/mesh/errors.h"

namespace ricci::cli {

namespace {

class PlyOut {
 public:
  PlyOut(std::ofstream& out, bool ascii) : out_(out), ascii_(ascii) {
    out_.precision(std::numeric_limits<double>::max_digits10);
  }
  template <class T>
  void put(T value) {
    if (ascii_) {
      if (!first_) out_ << ' ';
      if constexpr (sizeof(T) == 1) {
        out_ << static_cast<int>(value);
      } else {
        out_ << value;
      }
    } else {
      out_.write(reinterpret_cast<const char*>(&value), sizeof(T));  // little endian host
    }
    first_ = false;
  }
  void end_row() {
    if (ascii_) out_ << '\n';
    first_ = true;
  }

 private:
  std::ofstream& out_;
  bool ascii_;
  bool first_ = true;
};

// The face property ricci_layout: the model a face's layout lives in.
std::uint8_t layout_model(LayoutKind kind) {
  switch (kind) {
    case LayoutKind::Plane:
    case LayoutKind::PlaneCut:
    case LayoutKind::Atlas:
      return 1;
    case LayoutKind::PoincareDisk:
      return 2;
    case LayoutKind::Sphere:
      return 3;
    default:
      return 0;
  }
}

}  // namespace

void write_result_ply(const std::string& path, const MeshUniformization& run, bool ascii) {
  std::ofstream out(path, std::ios::binary);
  if (!out) throw IoError("cannot write '" + path + "' (missing folder or no permission)");
  const std::vector<Eigen::Vector3d>& positions = run.positions;
  const bool subdivided = run.num_new_vertices() > 0;
  const bool has_layout = !run.position.empty();
  const bool has_texture = !run.texture.vertex.empty();
  const bool has_wedges = !run.texture.wedge.empty();
  const bool any_layout = std::any_of(run.face_layout.begin(), run.face_layout.end(),
                                      [](LayoutKind k) { return k != LayoutKind::None; });
  out << "ply\nformat " << (ascii ? "ascii" : "binary_little_endian") << " 1.0\n";
  out << "comment ricci-flow result: unified discrete surface Ricci flow\n";
  out << "element vertex " << positions.size() << "\n";
  for (const char* p :
       {"x", "y", "z", "ricci_u", "ricci_radius", "ricci_curvature", "ricci_target"}) {
    out << "property double " << p << "\n";
  }
  if (has_layout)
    out << "property double layout_x\nproperty double layout_y\nproperty double layout_z\n";
  if (has_texture) out << "property float texture_u\nproperty float texture_v\n";
  if (subdivided) {
    out << "property int ricci_input_face\nproperty double ricci_bary_0\n"
        << "property double ricci_bary_1\nproperty double ricci_bary_2\n";
  }
  out << "element face " << run.faces.size() << "\n";
  out << "property list uchar int vertex_indices\n";
  if (subdivided) out << "property int ricci_input_face\n";
  if (any_layout) out << "property uchar ricci_layout\n";
  if (has_wedges) {
    out << "property list uchar float texcoord\n";
    out << "property list uchar double texcoord_double\n";
    out << "property int ricci_chart\n";
    out << "property list uchar double layout_corners\n";
  }
  out << "end_header\n";
  PlyOut ply(out, ascii);
  for (size_t v = 0; v < positions.size(); ++v) {
    const Eigen::Vector3d& p = positions[v];
    const long i = static_cast<long>(v);
    for (double x :
         {p.x(), p.y(), p.z(), run.u[i], run.radius[i], run.curvature[i], run.target[i]}) {
      ply.put(x);
    }
    if (has_layout) {
      for (int c = 0; c < 3; ++c) ply.put(run.position[v][c]);
    }
    if (has_texture) {
      ply.put(static_cast<float>(run.texture.vertex[v].x()));
      ply.put(static_cast<float>(run.texture.vertex[v].y()));
    }
    if (subdivided) {
      ply.put(static_cast<std::int32_t>(run.vertex_input_face[v]));
      for (int c = 0; c < 3; ++c) ply.put(run.vertex_barycentric[v][c]);
    }
    ply.end_row();
  }
  for (size_t f = 0; f < run.faces.size(); ++f) {
    ply.put(std::uint8_t{3});
    for (int v : run.faces[f]) ply.put(static_cast<std::int32_t>(v));
    if (subdivided) ply.put(static_cast<std::int32_t>(run.input_face[f]));
    if (any_layout) ply.put(layout_model(run.face_layout[f]));
    if (has_wedges) {
      ply.put(std::uint8_t{6});
      for (const Eigen::Vector2d& uv : run.texture.wedge[f]) {
        ply.put(static_cast<float>(uv.x()));
        ply.put(static_cast<float>(uv.y()));
      }
      ply.put(std::uint8_t{6});
      for (const Eigen::Vector2d& uv : run.texture.wedge[f]) {
        ply.put(uv.x());
        ply.put(uv.y());
      }
      ply.put(static_cast<std::int32_t>(run.face_chart[f]));
      ply.put(std::uint8_t{6});
      const std::uint8_t model = layout_model(run.face_layout[f]);
      const double none = std::numeric_limits<double>::quiet_NaN();
      for (const Eigen::Vector3d& p : run.corners[f]) {
        ply.put(model == 1 || model == 2 ? p.x() : none);
        ply.put(model == 1 || model == 2 ? p.y() : none);
      }
    }
    ply.end_row();
  }
  out.close();
  if (!out) throw IoError("writing '" + path + "' failed (disk full?)");
}

}  // namespace ricci::cli
