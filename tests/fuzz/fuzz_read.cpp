// libFuzzer target: reading one format (RICCI_FUZZ_FORMAT: off, obj, ply, stl or gii) on arbitrary
// bytes, as read_mesh_file reads a file of that extension. A refusal (ricci::Error) is an answer;
// a crash, a hang, a leak, undefined behaviour or memory past the limit is a finding.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "io/text_reader.h"
#include "ricci/mesh/errors.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    ricci::io::read_mesh_bytes(std::string("fuzz.") + RICCI_FUZZ_FORMAT,
                               std::string_view(reinterpret_cast<const char*>(data), size),
                               RICCI_FUZZ_FORMAT);
  } catch (const ricci::Error&) {
  }
  return 0;
}
