// ricci-flow: the unified discrete surface Ricci flow on one mesh, from the command line.
#include "app.h"

int main(int argc, char** argv) {
  return ricci::cli::run_command_line(argc, argv);
}
