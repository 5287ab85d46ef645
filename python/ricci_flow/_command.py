"""The `ricci-flow` console script: the command line tool, run in this process."""
import signal
import sys

from . import _ricci_flow


def main():
    # The run holds no Python frame to interrupt: Ctrl-C ends the process, as it ends the tool.
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    sys.stdout.flush()
    sys.exit(_ricci_flow.run_command_line(["ricci-flow"] + sys.argv[1:]))


if __name__ == "__main__":
    main()
