"""The `ricci-flow` console script: the command line tool, run in this process."""
import sys

from . import _ricci_flow


def main():
    sys.stdout.flush()
    sys.exit(_ricci_flow.run_command_line(["ricci-flow"] + sys.argv[1:]))


if __name__ == "__main__":
    main()
