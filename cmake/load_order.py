#!/usr/bin/env python3
"""The order in which the solver names its shared libraries.

Why: Debian's deal.II loads about 200 shared libraries (Trilinos, PETSc,
gmsh, OpenCASCADE, ...). At start the dynamic loader binds about 320 000
symbols; each binding searches the libraries in the order of the global
scope (the executable's DT_NEEDED list, then breadth first) until one
defines the symbol. C++ libraries are not linked with -Bsymbolic, so a
library that binds many of its own symbols but sits deep in the scope
costs a search past every library before it. Modelled as each binding
costing the position of its library, the default breadth-first order makes
13.4 million library checks and this order 6.6 million (every function
bound, LD_BIND_NOW); starting the solver took 23 % less (doc/performance.md).

  order PROBE OUTPUT
      Run PROBE (the solver linked in the default order) with
      LD_DEBUG=scopes,bindings and LD_BIND_NOW=1, count the bindings each
      library receives, and write OUTPUT (only if it changes), a response
      file for the compiler driver: the libraries with the most bindings
      first, within --push-state,--no-as-needed ... --pop-state. Libraries
      that define a common symbol that at least one of them defines as
      global (STB_GLOBAL in .dynsym; nm -D types T, D, B, R, G or i: scotch
      and ptscotch, blas and gslcblas, Open MPI's Fortran sentinels, the MD5
      functions weak in libbsd and global in libmd) keep the order they had,
      so each such symbol binds where it bound before. A symbol defined only
      weak or unique (C++ vague linkage) has one meaning wherever it binds.
      On any failure OUTPUT is empty (the default order) and one line on
      stderr says why.

  check PROBE SOLVER RESPONSE_FILE
      Exit 0 if RESPONSE_FILE names libraries, SOLVER's scope starts with
      them, and SOLVER binds every symbol some library defines as global
      where PROBE binds it (all bindings made at start with LD_BIND_NOW=1;
      the plug-ins Open MPI opens later are not seen), and every binding that
      moved is of a C++ symbol (mangled, _Z) defined only weak or unique.
      Otherwise print why and exit 1. Not seen either: dlsym(RTLD_NEXT, ...)
      look-ups, which depend on where the caller sits.

Library constructors run in a different order too (the loader still runs a
library's dependencies first): the test suite is what checks that no
library relies on more.
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
BINDING = re.compile(r"binding file (.+?) \[\d+\] to (.+?) \[\d+\]: (?:normal|protected) "
                     r"symbol `([^']+)'(?: \[([^\]]+)\])?")


def loader_report(program):
    """The global scope (libraries only) and every binding of a start of
    program, with every function bound at start (LD_BIND_NOW), not only those
    --version calls; LD_PRELOAD is not passed on (it would join the scope)."""
    program = os.path.abspath(program)
    with tempfile.TemporaryDirectory() as work:
        log = os.path.join(work, "ld")
        env = {k: v for k, v in os.environ.items() if k != "LD_PRELOAD"}
        env.update(LD_DEBUG="scopes,bindings", LD_DEBUG_OUTPUT=log, LD_BIND_NOW="1")
        run = subprocess.run([program, "--version"], env=env, timeout=300,
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
                    listed = line.split("scope 0:", 1)[1].strip()
                    if not listed.startswith(program):
                        raise RuntimeError("the loader's scope does not start with " + program)
                    scope = listed[len(program):].split()
                    continue
                m = BINDING.search(line)
                if m:
                    source, target, symbol, version = m.groups()
                    bindings.append((source, target, symbol + "@" + (version or "")))
    if not scope:
        raise RuntimeError("the loader reported no scope for " + program)
    return scope, bindings


def defined_symbols(lib):
    """The symbols lib defines, from its .dynsym: (global, other), global being
    STB_GLOBAL (what nm -D lists as T, D, B, R, G or i), other weak or unique."""
    with open(lib, "rb") as f:
        data = f.read()
    if data[:4] != b"\x7fELF" or data[4] != 2 or data[5] != 1:
        raise RuntimeError(lib + " is not a 64-bit little-endian ELF file")
    shoff, = struct.unpack_from("<Q", data, 0x28)
    shentsize, shnum = struct.unpack_from("<HH", data, 0x3A)
    sections = [struct.unpack_from("<IIQQQQIIQQ", data, shoff + i * shentsize)
                for i in range(shnum)]
    strong, other, found = set(), set(), False
    for _, kind, _, _, offset, size, link, _, _, entsize in sections:
        if kind != 11:  # SHT_DYNSYM
            continue
        found = True
        strtab = sections[link][4]
        for at in range(offset, offset + size, entsize):
            name, info, _, shndx = struct.unpack_from("<IBBH", data, at)
            if shndx == 0 or shndx == 0xFFF1:  # undefined, absolute
                continue
            symbol = data[strtab + name:data.index(b"\0", strtab + name)].decode()
            if symbol in LINKER_MARKS:
                continue
            if info >> 4 == 1:  # STB_GLOBAL
                strong.add(symbol)
            elif info >> 4 in (2, 10):  # STB_WEAK, STB_GNU_UNIQUE
                other.add(symbol)
    if not found:
        raise RuntimeError(lib + " has no dynamic symbol table")
    return strong, other


def fixed_symbols(scope):
    """Per library, the symbols whose binding the order must not move: those
    some library of the scope defines as global (a weak copy found first
    would win over it as well as a global one)."""
    defined = {lib: defined_symbols(lib) for lib in scope}
    strong = set().union(*(d[0] for d in defined.values()))
    return {lib: (d[0] | d[1]) & strong for lib, d in defined.items()}, strong


def cost(sequence, received):
    """Library checks of the loader's searches, modelled as each binding
    costing the position of its target in the scope."""
    return sum(received[l] * (i + 1) for i, l in enumerate(sequence))


def order(probe, output):
    scope, bindings = loader_report(probe)
    received = collections.Counter(target for _, target, _ in bindings)
    position = {lib: i for i, lib in enumerate(scope)}
    fixed, _ = fixed_symbols(scope)
    owners = collections.defaultdict(list)
    for lib in scope:
        for name in fixed[lib]:
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
            raise RuntimeError("no order keeps the libraries that share global symbols")
    text = ("-Wl,--push-state,--no-as-needed\n" + "".join(l + "\n" for l in result) +
            "-Wl,--pop-state\n")
    write_if_changed(output, text)
    print("load order: %d libraries, %d bindings, %.1f million library checks in the default "
          "order, %.1f in this one" % (len(result), len(bindings), cost(scope, received) / 1e6,
                                        cost(result, received) / 1e6))


def write_if_changed(path, text):
    try:
        with open(path) as f:
            if f.read() == text:
                return
    except OSError:
        pass
    with open(path, "w") as f:
        f.write(text)


def check(probe, solver, response_file):
    with open(response_file) as f:
        listed = [line.strip() for line in f if line.strip() and not line.startswith("-")]
    if not listed:
        print("load order: %s names no library: the build's ordering step failed (its message "
              "is in the build log), and the solver starts in the default order" % response_file)
        return 1
    scope_a, bindings_a = loader_report(probe)
    scope_b, bindings_b = loader_report(solver)
    if scope_b[:len(listed)] != listed:
        print("load order: the solver's libraries are not in the order of " + response_file)
        return 1
    name_a, name_b = os.path.abspath(probe), os.path.abspath(solver)

    def table(bindings, program):
        """(source, symbol@version) -> the targets of all its bindings, in order."""
        named = lambda path: "<program>" if path == program else path  # noqa: E731
        t = collections.defaultdict(list)
        for source, target, symbol in bindings:
            t[(named(source), symbol)].append(named(target))
        return t

    a, b = table(bindings_a, name_a), table(bindings_b, name_b)
    missing = set(a) ^ set(b)
    if missing:
        print("load order: %d symbols are bound by only one of the two programs, e.g. %s"
              % (len(missing), sorted(missing)[0]))
        return 1
    _, strong = fixed_symbols(scope_a)
    moved = 0
    for key in sorted(a):
        if a[key] == b[key]:
            continue
        moved += 1
        name = key[1].split("@")[0]
        if name in strong or len(a[key]) != len(b[key]):
            print("load order: %s binds %s, which a library defines as global, to %s, not to %s "
                  "as before" % (key[0], key[1], b[key], a[key]))
            return 1
        # Weak or unique only: C++ vague linkage (inline functions, template
        # instances, vtables, typeinfo), one meaning wherever it binds; a C
        # name would be a weak default that another library may redefine.
        if not name.startswith("_Z"):
            print("load order: %s binds %s, a weak symbol with a C name, to %s, not to %s as "
                  "before" % (key[0], key[1], b[key], a[key]))
            return 1
    received = collections.Counter(target for _, target, _ in bindings_a)
    print("load order: %d bindings of %d symbols by source (LD_BIND_NOW); %d of C++ symbols "
          "defined only weak or unique bind to another copy; %.1f million library checks in "
          "the default order, %.1f in the solver's"
          % (len(bindings_a), len(a), moved, cost(scope_a, received) / 1e6,
             cost(scope_b, received) / 1e6))
    return 0


def main():
    if not (len(sys.argv) == 4 and sys.argv[1] == "order" or
            len(sys.argv) == 5 and sys.argv[1] == "check"):
        sys.stderr.write("usage: load_order.py order PROBE OUTPUT | "
                         "check PROBE SOLVER RESPONSE_FILE\n")
        return 2
    if sys.argv[1] == "check":
        return check(*sys.argv[2:5])
    try:
        order(sys.argv[2], sys.argv[3])
    except Exception as e:  # any failure: the default order, and why
        write_if_changed(sys.argv[3], "")
        sys.stderr.write("load_order.py: the default library order stays: %s\n" % e)
    return 0


if __name__ == "__main__":
    sys.exit(main())
