// ricci-flow: the unified discrete surface Ricci flow on one mesh, from the command line.
#include <csignal>

#include "app.h"

int main(int argc, char** argv) {
  // Past a file size limit a write fails (and the run with it, leaving no output) instead of the
  // signal ending the process with a partial file on disk.
  std::signal(SIGXFSZ, SIG_IGN);
  bool out_of_memory = false;
  const int code = ricci::cli::run_command_line(argc, argv, &out_of_memory);
  if (out_of_memory) ricci::cli::end_out_of_memory(code);
  return code;
}
