// ricci-flow: the unified discrete surface Ricci flow on one mesh, from the command line.
#include <csignal>

#include "app.h"

int main(int argc, char** argv) {
  // Past a file size limit a write fails (and the run with it, leaving no output) instead of the
  // signal ending the process with a partial file on disk.
  std::signal(SIGXFSZ, SIG_IGN);
  const int code = ricci::cli::run_command_line(argc, argv);
#if defined(__SANITIZE_ADDRESS__)
  return code;  // the sanitizers' leak check is an exit handler
#else
  ricci::cli::end_process(code);
#endif
}
