#!/usr/bin/env python3
"""The order in which the solver names its shared libraries.

Why: Debian's deal.II loads about 200 shared libraries (Trilinos, PETSc,
gmsh, OpenCASCADE, ...). At start the dynamic loader binds about 320 000
symbols; each binding searches the libraries in the order of the global
scope (the executable's DT_NEEDED list, then breadth first) until one
defines the symbol. C++ libraries are not linked with -Bsymbolic, so a
library that binds many of its own symbols but sits deep in the scope
costs a search past every library before it. In breadth-first order the
searches made about 11.7 million checks (4.9 million in this order), and
starting the solver took about 0.4 s of every run (0.3 s in this order).

  order PROBE OUTPUT
      Run PROBE (the solver linked in the default order) with
      LD_DEBUG=scopes,bindings, count the bindings each library receives,
      and write OUTPUT, a response file for the compiler driver:
      --no-as-needed, the libraries with the most bindings first, --as-needed.
      Two libraries that define a common strong symbol (global binding in
      .dynsym, nm -D types T, D, B, R, G or i: scotch and ptscotch, blas and
      gslcblas, Open MPI's Fortran sentinels) keep the order they had, so
      every strong symbol binds where it bound before; weak and unique
      symbols (C++ vague linkage) have one meaning wherever they bind. On any failure OUTPUT is empty (the default
      order) and one line on stderr says why.

  check PROBE SOLVER
      Exit 0 if SOLVER binds every strong symbol where PROBE binds it, and
      print both orders' search costs; otherwise name the first difference.
"""
import collections
import os
import re
import struct
import subprocess
import sys
import tempfile

# Marks the linker puts into some libraries' symbol tables; nothing binds to them.
LINKER_MARKS = {"__bss_start", "_edata", "_end", "_init", "_fini"}
BINDING = re.compile(r"binding file (\S+) \[\d+\] to (\S+) \[\d+\]: normal symbol `([^']+)'")


def loader_report(program):
    """The global scope (libraries only) and every binding of a start of program."""
    with tempfile.TemporaryDirectory() as work:
        log = os.path.join(work, "ld")
        env = dict(os.environ, LD_DEBUG="scopes,bindings", LD_DEBUG_OUTPUT=log)
        run = subprocess.run([os.path.abspath(program), "--version"], env=env,
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        if run.returncode != 0:
            raise RuntimeError("%s --version exited with %d" % (program, run.returncode))
        logs = [os.path.join(work, n) for n in os.listdir(work) if n.startswith("ld.")]
        if len(logs) != 1:
            raise RuntimeError("expected one loader log of %s, found %d" % (program, len(logs)))
        scope, bindings = None, []
        with open(logs[0]) as f:
            for line in f:
                if scope is None and "scope 0:" in line:
                    scope = line.split("scope 0:")[1].split()[1:]  # without the program
                    continue
                m = BINDING.search(line)
                if m:
                    bindings.append(m.groups())
    if not scope:
        raise RuntimeError("the loader reported no scope for " + program)
    return scope, bindings


def strong_symbols(lib):
    """The global (not weak, not unique) symbols lib defines, read from its
    .dynsym (what nm -D lists as T, D, B, R, G or i)."""
    with open(lib, "rb") as f:
        data = f.read()
    if data[:4] != b"\x7fELF" or data[4] != 2 or data[5] != 1:
        raise RuntimeError(lib + " is not a 64-bit little-endian ELF file")
    shoff, = struct.unpack_from("<Q", data, 0x28)
    shentsize, shnum = struct.unpack_from("<HH", data, 0x3A)
    sections = [struct.unpack_from("<IIQQQQIIQQ", data, shoff + i * shentsize)
                for i in range(shnum)]
    names = set()
    for _, kind, _, _, offset, size, link, _, _, entsize in sections:
        if kind != 11:  # SHT_DYNSYM
            continue
        strtab = sections[link][4]
        for at in range(offset, offset + size, entsize):
            name, info, _, shndx = struct.unpack_from("<IBBH", data, at)
            # Bound globally (STB_GLOBAL), defined, not absolute.
            if info >> 4 != 1 or shndx == 0 or shndx == 0xFFF1:
                continue
            symbol = data[strtab + name:data.index(b"\0", strtab + name)].decode()
            if symbol not in LINKER_MARKS:
                names.add(symbol)
    return names


def cost(sequence, received):
    return sum(received[l] * (i + 1) for i, l in enumerate(sequence))


def order(probe, output):
    scope, bindings = loader_report(probe)
    received = collections.Counter(target for _, target, _ in bindings)
    position = {lib: i for i, lib in enumerate(scope)}
    owners = collections.defaultdict(list)
    for lib in scope:
        for name in strong_symbols(lib):
            owners[name].append(lib)
    before = collections.defaultdict(set)  # lib -> libraries that must precede it
    for defined_by in owners.values():
        for a in defined_by:
            for b in defined_by:
                if position[a] < position[b]:
                    before[b].add(a)
    # Most bindings first, each library after those it must follow; ties
    # keep the scope's order.
    placed, result = set(), []
    remaining = sorted(scope, key=lambda l: (-received[l], position[l]))
    while remaining:
        for i, lib in enumerate(remaining):
            if before[lib] <= placed:
                result.append(lib)
                placed.add(lib)
                del remaining[i]
                break
        else:
            raise RuntimeError("no order keeps the libraries that share strong symbols")
    with open(output, "w") as f:
        f.write("-Wl,--no-as-needed\n")
        f.write("".join(l + "\n" for l in result))
        f.write("-Wl,--as-needed\n")
    print("load order: %d libraries, %d bindings, %.1f million library checks in the default "
          "order, %.1f in this one" % (len(result), len(bindings), cost(scope, received) / 1e6,
                                        cost(result, received) / 1e6))


def check(probe, solver):
    scope_a, bindings_a = loader_report(probe)
    scope_b, bindings_b = loader_report(solver)
    name_a, name_b = os.path.realpath(probe), os.path.realpath(solver)

    def table(bindings, program):
        real = {}  # one realpath() per file name, not per binding

        def named(path):
            if path not in real:
                real[path] = "<program>" if os.path.realpath(path) == program else path
            return real[path]

        return {(named(source), symbol): named(target) for source, target, symbol in bindings}

    a, b = table(bindings_a, name_a), table(bindings_b, name_b)
    strong = {}
    moved = 0
    for key in sorted(set(a) & set(b)):
        if a[key] == b[key]:
            continue
        moved += 1
        for target in (a[key], b[key]):
            if target == "<program>":
                continue
            if target not in strong:
                strong[target] = strong_symbols(target)
            if key[1].split("@")[0] in strong[target]:
                print("load order: %s binds the strong symbol %s to %s, not to %s as before"
                      % (key[0], key[1], b[key], a[key]))
                return 1
    missing = set(a) ^ set(b)
    if missing:
        print("load order: %d bindings are made by only one of the two programs, e.g. %s"
              % (len(missing), sorted(missing)[0]))
        return 1
    received = collections.Counter(target for _, target, _ in bindings_a)
    print("load order: %d bindings; %d weak or unique ones bind to another copy; %.1f million "
          "library checks in the default order, %.1f in the solver's"
          % (len(a), moved, cost(scope_a, received) / 1e6, cost(scope_b, received) / 1e6))
    return 0


def main():
    if len(sys.argv) != 4 or sys.argv[1] not in ("order", "check"):
        sys.stderr.write("usage: load_order.py order PROBE OUTPUT | check PROBE SOLVER\n")
        return 2
    if sys.argv[1] == "check":
        return check(sys.argv[2], sys.argv[3])
    try:
        order(sys.argv[2], sys.argv[3])
    except (OSError, RuntimeError) as e:
        with open(sys.argv[3], "w"):
            pass
        sys.stderr.write("load_order.py: the default library order stays: %s\n" % e)
    return 0


if __name__ == "__main__":
    sys.exit(main())
