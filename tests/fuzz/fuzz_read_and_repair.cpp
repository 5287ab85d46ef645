// libFuzzer target: reading and repair, as ricci-flow does them, on arbitrary bytes: the format by
// the file's first bytes, then every repair and the split into checked components. A refusal
// (ricci::Error) is an answer; a crash, a hang, a leak, undefined behaviour or memory past the
// limit is a finding.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "io/text_reader.h"
#include "ricci/mesh/errors.h"
#include "ricci/repair/repair.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const ricci::MeshFile file = ricci::io::read_mesh_bytes(
        "fuzz", std::string_view(reinterpret_cast<const char*>(data), size), "");
    ricci::repair_mesh(file.positions, file.triangles);
  } catch (const ricci::Error&) {
  }
  return 0;
}
