#!/usr/bin/env python3
"""Checks that the core's includes go one way: from a stage to itself or an earlier one.

Usage: check_stages.py [CORE_DIR]

The core (core/src/STAGE/ and core/include/ricci/STAGE/) is in folders by stage, in the order of
STAGES below. A module is one name in one stage: its public header, its private header and its
source (ricci/flow/flow_solver.h and src/flow/flow_solver.cpp are module flow/flow_solver). Fails,
naming each offending include, when a file includes a later stage's header, when a file of the
core lies outside every stage's folder, or when modules include each other (a cycle, of any
length, in the graph of modules and the modules their files include).
"""
import os
import re
import sys

# Earlier stages never include later ones. The layout of a metric needs only its edge lengths, so
# it comes before the flow, whose spherical start lays out a punctured flat metric.
STAGES = ["mesh", "io", "repair", "linear", "layout", "flow", "subdivision", "pipeline", "report"]
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def module_of(path, core):
    """(stage, name) of a file under core/, or None when it is in no stage's folder."""
    rel = os.path.relpath(path, core).split(os.sep)
    if rel[:2] == ["include", "ricci"]:
        rel = rel[2:]
    elif rel[:1] == ["src"]:
        rel = rel[1:]
    else:
        return None
    if len(rel) != 2 or rel[0] not in STAGES:
        return None
    return rel[0], os.path.splitext(rel[1])[0]


def included_module(name, including_file, core):
    """The module a quoted include names, resolved as the compiler does; None for other files."""
    for base in (os.path.dirname(including_file), os.path.join(core, "include"),
                 os.path.join(core, "src")):
        candidate = os.path.normpath(os.path.join(base, name))
        if os.path.isfile(candidate):
            return module_of(candidate, core), candidate
    return None, None


def main():
    core = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                           os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "core"))
    problems, uses = [], {}
    for folder, _dirs, names in os.walk(core):
        for name in sorted(names):
            if not name.endswith((".h", ".cpp")):
                continue
            path = os.path.join(folder, name)
            here = module_of(path, core)
            if here is None:
                problems.append("%s: not in a stage's folder (%s)" %
                                (os.path.relpath(path, core), ", ".join(STAGES)))
                continue
            uses.setdefault(here, set())
            text = open(path, encoding="utf-8").read()
            for line_no, included in ((text.count("\n", 0, m.start()) + 1, m.group(1))
                                      for m in INCLUDE.finditer(text)):
                there, _file = included_module(included, path, core)
                if there is None:
                    continue
                if STAGES.index(there[0]) > STAGES.index(here[0]):
                    problems.append("%s:%d: includes \"%s\" of the later stage %s" %
                                    (os.path.relpath(path, core), line_no, included, there[0]))
                if there != here:
                    uses[here].add(there)
    # Cycles among modules: a depth-first search that reports each back edge's cycle once.
    state, stack, seen_cycles = {}, [], set()

    def visit(m):
        state[m] = "open"
        stack.append(m)
        for n in sorted(uses.get(m, ())):
            if state.get(n) == "open":
                cycle = stack[stack.index(n):]
                key = frozenset(cycle)
                if key not in seen_cycles:
                    seen_cycles.add(key)
                    problems.append("modules include each other: " +
                                    " -> ".join("%s/%s" % c for c in cycle + [n]))
            elif n not in state:
                visit(n)
        stack.pop()
        state[m] = "done"

    for m in sorted(uses):
        if m not in state:
            visit(m)
    for p in problems:
        print("check_stages: " + p)
    if problems:
        return 1
    print("check_stages: %d modules in %d stages, every include to the same or an earlier stage, "
          "no modules that include each other" % (len(uses), len({m[0] for m in uses})))
    return 0


if __name__ == "__main__":
    sys.exit(main())
