"""The `ricci-flow` console script: the command line tool, run in this process."""
import os
import signal
import sys

from . import _ricci_flow


def main():
    # The run holds no Python frame to interrupt: Ctrl-C ends the process, as it ends the tool.
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    sys.stdout.flush()
    code = _ricci_flow.run_command_line(["ricci-flow"] + sys.argv[1:])
    # Ended as the executable ends, without the exit handlers: where the address space is short,
    # OpenBLAS's worker thread retries its buffer's allocation without end and OpenBLAS's exit
    # handler waits for it (the module's run_command_line has flushed C's stdio).
    sys.stdout.flush()
    sys.stderr.flush()
    os._exit(code)


if __name__ == "__main__":
    main()
