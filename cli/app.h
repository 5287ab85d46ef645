// The ricci-flow command as a function: the executable's main, and the Python package's console
// script (through its compiled module), run the same code.
#pragma once

#include "options.h"
#include "ricci/pipeline/uniformize.h"

namespace ricci::cli {

//! The request the options make for a mesh whose input has `num_input_vertices`: o.request with
//! the per-vertex target (--target FILE or cones:FILE) and eps (--eps FILE) read.
//! \throws IoError, InvalidArgumentError for a file that cannot be read or does not fit.
UniformizationOptions request_for(const Options& o, int num_input_vertices);

//! One run of parsed options: read, repair, uniformize, write the result (and report, picture),
//! print the summary unless quiet. \throws the run's error (the command's exit code 1).
void run(const Options& o);

//! Runs ricci-flow with argv (argv[0] the program's name); returns the exit code: 0 done, 1 the
//! run failed (message on stderr), 2 a usage error.
int run_command_line(int argc, const char* const* argv);

//! Ends the process with `code`, C stdio flushed, without its exit handlers: where the address
//! space is short (below about 350 MB), the worker thread of Debian 12's OpenBLAS (0.3.21) retries
//! its buffer's allocation without end from its start, and OpenBLAS's exit handler waits for it,
//! so that even `ricci-flow --version` would never end. The outputs are written or removed by then.
[[noreturn]] void end_process(int code);

}  // namespace ricci::cli
