#include "ricci/mesh_io.h"

#include <fstream>

#include <vcg/complex/algorithms/clean.h>
#include <wrap/io_trimesh/import.h>

#include "ricci/errors.h"

namespace ricci {

void read_mesh(const std::string& path, VcgMesh& mesh) {
  if (!std::ifstream(path).good()) {
    throw IoError("read_mesh: cannot open '" + path + "' (missing file or no permission)");
  }
  using Importer = vcg::tri::io::Importer<VcgMesh>;
  int mask = 0;
  const int error = Importer::Open(mesh, path.c_str(), mask);
  if (error != 0 && Importer::ErrorCritical(error)) {
    throw IoError("read_mesh: cannot read '" + path + "': " + Importer::ErrorMsg(error) +
                  " (formats: off, obj, ply, stl)");
  }
  if (Importer::FileExtension(path, "stl")) {
    // STL stores every triangle's corners separately.
    vcg::tri::Clean<VcgMesh>::RemoveDuplicateVertex(mesh);
    vcg::tri::Allocator<VcgMesh>::CompactEveryVector(mesh);
  }
}

}  // namespace ricci
