#include "ricci/flow/flow_result.h"

#include <string>

#include "ricci/mesh/errors.h"

namespace ricci {

std::string to_string(EdgeFlips f) {
  switch (f) {
    case EdgeFlips::WhenNeeded:
      return "when-needed";
    case EdgeFlips::Always:
      return "always";
    case EdgeFlips::Never:
      return "never";
  }
  return "?";
}

EdgeFlips edge_flips_from_string(const std::string& name) {
  for (EdgeFlips f : {EdgeFlips::WhenNeeded, EdgeFlips::Always, EdgeFlips::Never}) {
    if (to_string(f) == name) return f;
  }
  throw InvalidArgumentError("unknown edge flip choice '" + name +
                             "'; choose when-needed, always or never");
}

}  // namespace ricci
