// Running ricci-flow from a test: its exit code and output, per-test temporary files, CGAL's
// meshes by name (shared by the command line tool's tests).
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "ply_reader.h"
#include "test_meshes.h"

namespace ricci::test::cli {

struct CliRun {
  int exit_code = -1;
  std::string out, err;
};

inline std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Per-test file names: ctest runs the tests of this file in parallel processes.
// Parameterized tests' names have slashes.
inline std::string temp(const std::string& name) {
  const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
  std::string stem = test->name();
  for (char& c : stem) {
    if (c == '/') c = '_';
  }
  return ::testing::TempDir() + "/ricci_cli_" + stem + "_" + name;
}

inline CliRun ricci_flow(const std::string& args) {
  const std::string out = temp("stdout.txt"), err = temp("stderr.txt");
  const std::string cmd =
      std::string(RICCI_CLI_PATH) + " " + args + " >" + out + " 2>" + err + " </dev/null";
  const int status = std::system(cmd.c_str());
  CliRun r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

inline std::string cgal(const std::string& name) {
  return ricci::test::cgal_mesh_path(name);
}

using ricci::test::read_ply;

inline void write_file(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}

}  // namespace ricci::test::cli
