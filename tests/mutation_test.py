#!/usr/bin/python3
"""Mutation test of the project's own scene files.

Issue "Reliability: no silent NaN, no crash, no endless run": every mutation of a
scene below (a deleted line, a value of the wrong type, a non-finite or
out-of-range number, a function that is broken or turns non-finite in space or
later in time, a garbage mesh, an unwritable output, a huge refinement, a time
step below the resolution of t, ...) must either

  * be refused: exit code 1 or 2, exactly one non-empty line on stderr without
    control bytes that names the cause, no signal, no "terminate called", no
    stack trace, no half-written output (statistics lines complete, every
    .vtu/.pvtu/.pvd file closed by </VTKFile>); or
  * run: exit code 0, empty stderr (or only 'contact-stefan: warning: ...'
    lines: a mesh whose cells are far from square), and every number in stdout (RESULT lines,
    step lines), in the statistics table and in the VTU files is finite; or
  * run with warnings: exit code 3, every stderr line a 'contact-stefan:
    warning: ...' of a failed self-check, output finite as for a run;

anything else (a signal, a hang beyond --timeout, a silent NaN, a multi-line
error, ...) is a failure. Each case runs the binary serially in its own fresh
work directory. The set of mutations is fixed (no randomness); --list prints it.

  mutation_test.py --binary build/contact-stefan --source-dir . [--jobs 2]
                   [--timeout 30] [--list] [--keep DIR] [--filter REGEX] [--verbose]

Invalid inputs (a NaN, a directory as parameter file, a bow-tie cell, ...) are
marked 'refuse' in --list: for them a clean exit 0 is a failure as well. Each case
is limited to --memory-limit MiB of address space, 1 GiB files and no core file.
It prints one FAIL line per failure, then
  mutations: N  refused: R  ran: A  ran with warnings (exit 0 or 3): W  clean: C  failed: F
  C passed, F failed
and exits 1 if F > 0. In ctest (tests/cmake/guards.cmake):
  add_test(NAME mutation COMMAND /usr/bin/python3 ${T}/mutation_test.py
           --binary ${BIN} --source-dir ${CMAKE_SOURCE_DIR} --cmake ${CMAKE_COMMAND}
           --sample 2)
(--sample N runs every N-th case, rotating with the UTC day; --sample-offset K
repeats a given day's choice.)
  set_tests_properties(mutation PROPERTIES PROCESSORS 2 TIMEOUT 900)

Only the Python standard library is used (Debian's /usr/bin/python3).
"""

import argparse
import array
import base64
import concurrent.futures
import math
import os
import re
import resource
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import zlib

# --------------------------------------------------------------------------------
# The scenes that are mutated (all run in about a second).

BASES = {
    "patch": "prm/benchmarks/patch_C2.prm",
    "hertz": "prm/benchmarks/hertz_C1.prm",
    "neu": "prm/benchmarks/neumann_A.prm",
    "block": "tests/scenes/block_on_obstacle.prm",
    "manu": "tests/scenes/manufactured_flux.prm",
    "equi": "tests/scenes/two_body_equilibrium.prm",
    "kink": "tests/scenes/kinked_roller.prm",
    "gmsh": "tests/scenes/two_blocks_gmsh.prm",
    "cond": "tests/scenes/conductance_gap.prm",
    "mort": "tests/scenes/mortar_patch.prm",
}
# Generated meshes the Gmsh scenes need: tests/make_two_blocks_msh.cmake (with
# the kink or not), or for "mortar" tests/make_mortar_msh.py (two blocks meshed
# independently, 2 and 7 cells along the interface).
MESHES = {"kink": ("kink.msh", True), "gmsh": ("two_blocks.msh", False),
          "mort": ("mortar_patch.msh", "mortar")}

SCENE_NAME = "scene.prm"


# --------------------------------------------------------------------------------
# A parameter file as lines, with the entries found by subsection path.

class Scene:
    def __init__(self, text):
        self.lines = text.splitlines()

    def entries(self):
        """(path, line index, value) of every 'set' line, in file order."""
        stack, found = [], []
        for i, raw in enumerate(self.lines):
            line = raw.split("#", 1)[0].strip()
            if line.startswith("subsection "):
                stack.append(line[len("subsection "):].strip())
            elif line == "end":
                if stack:
                    stack.pop()
            elif line.startswith("set ") and "=" in line:
                key, value = line[4:].split("=", 1)
                found.append(("/".join(stack + [key.strip()]), i, value.strip()))
        return found

    def get(self, path, default=None):
        value = default
        for p, _, v in self.entries():
            if p == path:
                value = v
        return value

    def set(self, path, value):
        """Replace every line that sets path; append the entry if there is none."""
        hits = [i for p, i, _ in self.entries() if p == path]
        if hits:
            key = path.rsplit("/", 1)[-1]
            for i in hits:
                raw = self.lines[i]
                indent = raw[: len(raw) - len(raw.lstrip())]
                self.lines[i] = "%sset %s = %s" % (indent, key, value)
        else:
            levels = path.split("/")
            for level in levels[:-1]:
                self.lines.append("subsection " + level)
            self.lines.append("set %s = %s" % (levels[-1], value))
            self.lines.extend(["end"] * (len(levels) - 1))

    def delete(self, index):
        del self.lines[index]

    def text(self):
        return "\n".join(self.lines) + "\n"


# --------------------------------------------------------------------------------
# Mutations.

class Mutation:
    """One mutated case. base: key of BASES or None (then prm_bytes is the file).
    sets: [(path, value)] applied in order; delete: a line index of the base;
    append: text added at the end; prm_bytes: the whole parameter file (bytes);
    prm_kind: 'file', 'dir' (the parameter file is a directory) or 'missing';
    prm_name: its name; mesh: None (the generated mesh of a Gmsh scene) or
    f(mesh text) -> the bytes to write instead, 'dir' (a directory in its place) or
    'missing'; setup: f(work_dir) preparing more of the work dir;
    slow: expected to run into the timeout (scheduled first); refuse: the input is
    invalid, so a run that ends with exit code 0 is a failure too."""

    def __init__(self, mid, desc, base=None, sets=(), delete=None, append="",
                 prm_bytes=None, prm_kind="file", prm_name=SCENE_NAME, mesh=None,
                 setup=None, slow=False, refuse=False):
        self.id, self.desc, self.base = mid, desc, base
        self.sets, self.delete, self.append = list(sets), delete, append
        self.prm_bytes, self.prm_kind, self.prm_name = prm_bytes, prm_kind, prm_name
        self.mesh, self.setup, self.slow, self.refuse = mesh, setup, slow, refuse


def slug(path):
    key = path.rsplit("/", 1)[-1].lower()
    return re.sub(r"[^a-z0-9]+", "-", key).strip("-")


# Values for entries that must be positive and finite.
BAD_NUMBERS = [
    ("nan", "nan"), ("inf", "inf"), ("minf", "-inf"), ("big", "1e308"),
    ("mbig", "-1e308"), ("ovf", "1e309"), ("denorm", "1e-320"), ("zero", "0"),
    ("neg", "-1"), ("text", "abc"),
]
# Valid numbers (a run may go on, it must stay finite); every other bad value
# must be refused.
MAY_RUN_NUMBERS = {"big", "denorm"}
SHORT_BAD_NUMBERS = [("nan", "nan"), ("inf", "inf"), ("big", "1e308"), ("neg", "-1"),
                     ("text", "abc")]

# Broken functions and functions that turn non-finite in space or later in time.
BAD_FUNCTIONS = [
    ("syntax", "x +* 2", "syntax error"),
    ("unknown", "x + q", "unknown variable q"),
    ("zerodiv", "0/0", "NaN everywhere, at all times"),
    ("sqrt", "sqrt(-1-t)", "NaN at all times"),
    ("log", "log(0.5-t)", "finite for t < 0.5, -inf at 0.5, NaN after"),
    ("floor", "1/floor(1.5-t)", "finite for t < 0.5, inf from t = 0.5 on"),
    ("pole", "1/(x-0.5)", "infinite on the line x = 0.5"),
    ("ovf", "1e308*10", "overflows to inf"),
]

# Function entries of each scene: (base, path, number of components, the variants
# that may stay finite where the scene evaluates them, so that a run may go on).
# Every scene runs past t = 0.5 except the initial conditions (evaluated at the
# start time only) and two_blocks_gmsh (t = 0, 100, ..., where floor(1.5-t) != 0);
# 1/(x-0.5) is finite at quadrature points and on boundaries without x = 0.5.
MAY_RUN = {"pole"}
AT_START = {"pole", "log", "floor"}
FUNCTION_ENTRIES = [
    ("manu", "Materials/Body 0/Heat source", 1, MAY_RUN),
    ("manu", "Boundary conditions/Thermal boundary 0/Value", 1, MAY_RUN),
    ("manu", "Boundary conditions/Thermal boundary 1/Value", 1, MAY_RUN),
    ("manu", "Initial conditions/Function", 1, AT_START),
    ("manu", "Exact solution/Function", 1, MAY_RUN),
    ("neu", "Boundary conditions/Thermal boundary 0/Value", 1, MAY_RUN),
    ("neu", "Initial conditions/Function", 1, AT_START),
    ("equi", "Initial conditions/Function", 1, AT_START),
    ("gmsh", "Boundary conditions/Thermal boundary 11/Value", 1, {"pole", "floor"}),
    ("patch", "Boundary conditions/Mechanical boundary 3/Value", 2, MAY_RUN),
    ("patch", "Contact/Interface gap", 1, MAY_RUN),
    ("mort", "Contact/Interface gap", 1, MAY_RUN),
    ("hertz", "Boundary conditions/Mechanical boundary 3/Gap", 1, MAY_RUN),
    ("block", "Materials/Body 0/Body force", 2, MAY_RUN),
    ("block", "Boundary conditions/Mechanical boundary 3/Value", 2, MAY_RUN),
    ("block", "Boundary conditions/Mechanical boundary 2/Gap", 1, MAY_RUN),
    ("kink", "Boundary conditions/Mechanical boundary 12/Gap", 1, MAY_RUN),
]

# Entries that need a positive (finite, representable) number.
POSITIVE_ENTRIES = [
    ("neu", "Materials/Body 0/Density", BAD_NUMBERS),
    ("neu", "Materials/Body 0/Conductivities", BAD_NUMBERS),
    ("neu", "Materials/Body 0/Phase change/Heat capacities", BAD_NUMBERS),
    ("neu", "Time stepping/Time step", BAD_NUMBERS),
    ("neu", "Time stepping/End time", BAD_NUMBERS),
    ("patch", "Materials/Body 0/Youngs modulus", BAD_NUMBERS),
    ("hertz", "Exact solution/Cylinder radius", BAD_NUMBERS),
    ("neu", "Materials/Body 0/Phase change/Latent heats", SHORT_BAD_NUMBERS),
    ("equi", "Materials/Body 1/Phase change/Transition temperatures",
     [("nan", "0.2, nan"), ("inf", "0.2, inf"), ("big", "0.2, 1e308"),
      ("ovf", "0.2, 1e309"), ("text", "0.2, abc")]),
    ("equi", "Materials/Body 1/Conductivities",
     [("nan", "3, nan, 1"), ("inf", "3, inf, 1"), ("zero", "3, 0, 1"),
      ("denorm", "3, 1e-320, 1")]),
    ("patch", "Materials/Body 0/Poisson ratio",
     [("nan", "nan"), ("inf", "inf"), ("half", "0.5"), ("minus1", "-1"), ("text", "abc")]),
    ("patch", "Exact solution/Patch displacement", [("nan", "nan"), ("inf", "inf")]),
    ("block", "Materials/Body 0/Youngs modulus",
     [("big", "1e308"), ("denorm", "1e-320"), ("nan", "nan")]),
    ("manu", "Materials/Body 0/Density", [("big", "1e308"), ("denorm", "1e-320")]),
    ("manu", "Materials/Body 0/Conductivity anisotropy",
     [("nan", "2, nan, 1"), ("inf", "inf, 0.5, 1"), ("zero", "0, 0, 0"),
      ("big", "1e308, 0, 1e308")]),
    ("manu", "Time stepping/Start time", [("nan", "nan"), ("minf", "-inf")]),
    ("hertz", "Mesh refinement/Pre-refinement radius",
     [("nan", "nan"), ("inf", "inf"), ("neg", "-1")]),
    ("hertz", "Mesh refinement/Pre-refinement center", [("nan", "nan, 0"), ("inf", "0, inf")]),
    ("hertz", "Geometry/Upper right corner", [("nan", "2, nan"), ("inf", "inf, 0"),
                                             ("flat", "-2, 0")]),
    ("patch", "Geometry/Layer interfaces", [("nan", "nan"), ("outside", "5")]),
    # A mortar interface (doc/contact.md).
    ("mort", "Contact/Interface 1-2/Mortar boundaries",
     [("same", "14, 14"), ("absent", "14, 99"), ("swapped", "15, 14"), ("one", "14"),
      ("text", "abc"), ("nan", "nan, 15"), ("three", "14, 15, 16")]),
    ("mort", "Contact/Interface 1-2/Mortar search distance",
     [("nan", "nan"), ("neg", "-1"), ("text", "abc"), ("inf", "inf")]),
    ("mort", "Contact/Interface 1-2/Mortar slave", [("text", "coarser")]),
    # The conductance of an interface (doc/interface_heat.md).
    ("cond", "Contact/Interface 0-1/Conductance/Gap roughness", SHORT_BAD_NUMBERS),
    ("cond", "Contact/Interface 0-1/Conductance/Emissivity k",
     [("nan", "nan"), ("zero", "0"), ("above", "1.5"), ("neg", "-0.5")]),
    ("cond", "Contact/Interface 0-1/Conductance/Constant",
     [("nan", "nan"), ("inf", "inf"), ("neg", "-1"), ("text", "abc")]),
    ("cond", "Contact/Interface 0-1/Conductance/Gas conductivity",
     [("neg", "-0.05"), ("negT", "0.05 - 1e-3 * T"), ("text", "abc"), ("nan", "nan")]),
    ("cond", "Contact/Interface 0-1/Conductance/Function",
     [("neg", "-1"), ("negT", "T2 - T1"), ("pole", "1 / (T1 - T2)")]),
    ("neu", "Exact solution/Hot temperature", [("nan", "nan"), ("inf", "inf")]),
    ("block", "Contact/Complementarity constant", [("nan", "nan"), ("zero", "0")]),
    ("block", "Contact/Tolerance", [("nan", "nan"), ("neg", "-1")]),
    ("block", "Contact/Roller corner angle", [("nan", "nan")]),
    ("neu", "Solver/Relaxation parameter", [("nan", "nan"), ("zero", "0")]),
    ("manu", "Mesh refinement/Initial global refinements",
     [("neg", "-1"), ("frac", "1.5"), ("text", "abc"), ("huge-int", "1e308")]),
    ("manu", "Output/VTU interval", [("neg", "-1")]),
]
SUBDIVISION_VALUES = [
    ("nan", "nan, 4"), ("inf", "4, inf"), ("zero", "0, 4"), ("neg", "-1, 4"),
    ("big", "1e308, 4"), ("denorm", "1e-320, 4"), ("text", "abc, 4"), ("one", "4"),
    ("three", "4, 4, 4"), ("ovf", "4294967297, 4"),
]

# A number where a selection, boolean or list is expected (or text for an integer).
WRONG_TYPES = [
    ("patch", "Geometry/Mesh", "3"),
    ("patch", "Boundary conditions/Mechanical boundary 0/Type", "1"),
    ("patch", "Boundary conditions/Mechanical boundary 2/Components", "2"),
    ("patch", "Contact/Interfaces", "1"),
    ("patch", "Physics/Mechanics", "2"),
    ("patch", "Bodies/Body ids", "abc"),
    ("patch", "Bodies/Body ids", "0.5, 1"),
    ("manu", "Boundary conditions/Thermal boundary 1/Type", "0"),
    ("manu", "Boundary conditions/Thermal boundaries", "x, y"),
    ("manu", "Initial conditions/Variable", "1"),
    ("manu", "Exact solution/Type", "2"),
    ("manu", "Output/Verbosity", "abc"),
    ("neu", "Solver/Linear solver", "0"),
    ("neu", "Solver/Enthalpy solver", "1"),
    ("neu", "Physics/Thermal", "maybe"),
    ("hertz", "Contact/Max iterations", "nan"),
    ("hertz", "Mesh refinement/Pre-refinement steps", "abc"),
    ("block", "Boundary conditions/Mechanical boundaries", "0, 1, 2, 3, abc"),
    ("block", "Materials/Body 0/Elasticity", "7"),
]


def fn_slug(path):
    parent, key = path.rsplit("/", 1)
    if key in ("Value", "Gap", "Function"):
        return slug(parent) + "-" + slug(key)
    return slug(key)


def bad_function_value(original, ncomp, expression):
    if ncomp == 1:
        return expression
    parts = [p.strip() for p in original.split(";")]
    while len(parts) < ncomp:
        parts.append("0")
    parts[-1] = expression
    return "; ".join(parts)


# ------------------------------- meshes --------------------------------------------

def mesh_lines(text):
    return text.splitlines()


def elements_start(lines):
    return lines.index("$Elements")


def edit_first_quad(text, edit):
    lines = mesh_lines(text)
    e = elements_start(lines)
    fields = lines[e + 2].split()
    edit(fields)
    lines[e + 2] = " ".join(fields)
    return ("\n".join(lines) + "\n").encode()


def swap_nodes(i, j):
    def edit(fields):
        # id type ntags tag tag n0 n1 n2 n3
        fields[5 + i], fields[5 + j] = fields[5 + j], fields[5 + i]
    return edit


def all_clockwise(text):
    lines = mesh_lines(text)
    e = elements_start(lines)
    n = int(lines[e + 1])
    for k in range(e + 2, e + 2 + n):
        f = lines[k].split()
        if f[1] == "3":
            f[6], f[8] = f[8], f[6]
            lines[k] = " ".join(f)
    return ("\n".join(lines) + "\n").encode()


def edit_node(text, number, new_xyz):
    lines = mesh_lines(text)
    start = lines.index("$Nodes")
    for k in range(start + 2, lines.index("$EndNodes")):
        f = lines[k].split()
        if f[0] == str(number):
            lines[k] = " ".join([f[0]] + new_xyz(f[1:]))
    return ("\n".join(lines) + "\n").encode()


def collapse_node(text):
    # First quad a b c d: move c onto b (a zero-length edge, cells of zero area).
    lines = mesh_lines(text)
    f = lines[elements_start(lines) + 2].split()
    b, c = f[6], f[7]
    start = lines.index("$Nodes")
    xyz = {}
    for k in range(start + 2, lines.index("$EndNodes")):
        g = lines[k].split()
        xyz[g[0]] = g[1:]
    return edit_node(text, c, lambda _: list(xyz[b]))


def edit_count(text, marker, delta):
    lines = mesh_lines(text)
    k = lines.index(marker) + 1
    lines[k] = str(int(lines[k]) + delta)
    return ("\n".join(lines) + "\n").encode()


def duplicate_first_quad(text):
    lines = mesh_lines(text)
    e = elements_start(lines)
    n = int(lines[e + 1])
    f = lines[e + 2].split()
    f[0] = str(n + 1)
    lines.insert(e + 2 + n, " ".join(f))
    lines[e + 1] = str(n + 1)
    return ("\n".join(lines) + "\n").encode()


def merge_quads(first, second):
    """Two neighbouring quads (0-based, in the order of $Elements) made one: the
    nodes on their common edge hang on the merged cell's edges (a T-junction,
    or a non-matching interface where one of them is a node of another body)."""
    def edit(text):
        lines = mesh_lines(text)
        e = elements_start(lines)
        f1, f2 = lines[e + 2 + first].split(), lines[e + 2 + second].split()
        n1, n2 = f1[5:9], f2[5:9]
        if n2[0] == n1[1] and n2[3] == n1[2]:    # side by side
            f1[5:9] = [n1[0], n2[1], n2[2], n1[3]]
        elif n2[0] == n1[3] and n2[1] == n1[2]:  # one above the other
            f1[5:9] = [n1[0], n1[1], n2[2], n2[3]]
        else:
            raise SystemExit("merge_quads: quads %d and %d are not neighbours" % (first, second))
        lines[e + 2 + first] = " ".join(f1)
        del lines[e + 2 + second]
        lines[e + 1] = str(int(lines[e + 1]) - 1)
        return ("\n".join(lines) + "\n").encode()
    return edit


def truncate_in_elements(text):
    e = text.index("$Elements")
    cut = e + (len(text) - e) // 2
    return text[:cut].encode()


BINARY_BYTES = bytes(range(256)) * 8 + b"\x00\xff\x1b[2J\r\n\x07" * 4


MESH_MUTATIONS = [
    # (short id, description, function(text) -> bytes | 'dir' | 'missing', bases)
    ("inverted", "one quad inverted (two node indices swapped: a d c b)",
     lambda t: edit_first_quad(t, swap_nodes(1, 3)), ("gmsh", "kink")),
    ("bowtie", "one self-overlapping bow-tie quad (a c b d)",
     lambda t: edit_first_quad(t, swap_nodes(1, 2)), ("gmsh", "kink", "mort")),
    ("repeated-node", "one quad with a repeated node (a b c c)",
     lambda t: edit_first_quad(t, lambda f: f.__setitem__(8, f[7])), ("gmsh", "kink")),
    ("collapsed", "a node moved onto its neighbour (cells of zero area)",
     collapse_node, ("gmsh", "kink", "mort")),
    ("nan-coord", "node 1 at (nan, 0)",
     lambda t: edit_node(t, 1, lambda xyz: ["nan"] + xyz[1:]), ("gmsh", "kink")),
    ("inf-coord", "node 2 at (inf, 0)",
     lambda t: edit_node(t, 2, lambda xyz: ["inf"] + xyz[1:]), ("gmsh",)),
    ("huge-coord", "node 2 at (1e308, 0)",
     lambda t: edit_node(t, 2, lambda xyz: ["1e308"] + xyz[1:]), ("kink",)),
    ("clockwise", "every quad numbered clockwise", all_clockwise, ("gmsh", "kink")),
    ("missing-node", "a quad refers to node 9999 that does not exist",
     lambda t: edit_first_quad(t, lambda f: f.__setitem__(6, "9999")), ("gmsh",)),
    ("node-index-ovf", "a quad refers to node 4294967298",
     lambda t: edit_first_quad(t, lambda f: f.__setitem__(6, "4294967298")), ("gmsh",)),
    ("node-index-neg", "a quad refers to node -1",
     lambda t: edit_first_quad(t, lambda f: f.__setitem__(6, "-1")), ("gmsh",)),
    ("elem-type", "a quad of unknown element type 99",
     lambda t: edit_first_quad(t, lambda f: f.__setitem__(1, "99")), ("gmsh",)),
    ("body-tag", "a quad of physical surface 7 (no such body)",
     lambda t: edit_first_quad(t, lambda f: f.__setitem__(3, "7")), ("gmsh",)),
    ("duplicate", "the first quad twice (overlapping cells)", duplicate_first_quad,
     ("gmsh", "kink", "mort")),
    ("nodes-count", "$Nodes announces 5 nodes more than it lists",
     lambda t: edit_count(t, "$Nodes", 5), ("gmsh",)),
    ("elements-count", "$Elements announces 3 elements more than it lists",
     lambda t: edit_count(t, "$Elements", 3), ("gmsh",)),
    ("version", "$MeshFormat 4.1 with a 2.2 body",
     lambda t: t.replace("2.2 0 8", "4.1 0 8", 1).encode(), ("gmsh",)),
    ("truncated", "truncated in the middle of a line (first half of the file)",
     lambda t: t.encode()[: len(t) // 2], ("gmsh", "kink")),
    ("truncated-elements", "truncated inside the $Elements block", truncate_in_elements,
     ("gmsh",)),
    ("binary", "binary garbage", lambda t: BINARY_BYTES, ("gmsh", "kink")),
    ("empty", "an empty file", lambda t: b"", ("gmsh", "kink")),
    ("directory", "a directory", lambda t: "dir", ("gmsh", "kink")),
    ("missing", "no such file", lambda t: "missing", ("gmsh",)),
    # 8 x 4 unit quads, row by row: quads 9 and 10 are (1..2, 1) and (2..3, 1);
    # 12 and 20 are (4..5, 1) and (4..5, 2), body 2 next to the interface x = 4.
    ("tjunction", "two quads of a row merged (T-junctions: nodes hang on its edges)",
     merge_quads(9, 10), ("gmsh", "kink")),
    ("nonmatching", "two quads of body 2 at the interface merged (a node of body 1 hangs "
     "on body 2's edge)", merge_quads(12, 20), ("gmsh",)),
]


# ------------------------------- file system set-ups --------------------------------

def make_readonly_dir(work):
    os.mkdir(os.path.join(work, "ro"))
    os.chmod(os.path.join(work, "ro"), 0o555)


def make_blocker_file(work):
    with open(os.path.join(work, "blocker"), "w") as f:
        f.write("a regular file where the output directory should be\n")


def make_output_entry(name, kind):
    def setup(work):
        out = os.path.join(work, "output")
        os.makedirs(out, exist_ok=True)
        path = os.path.join(out, name)
        if kind == "dir":
            os.mkdir(path)
        elif kind == "full":
            os.symlink("/dev/full", path)
    return setup


# The default time step 0.1 instead of 100 makes two_blocks_gmsh take 10000 steps.
SKIP_DELETIONS = {("gmsh", "Time stepping/Time step")}

# Valid meshes, or meshes deal.II may repair (reorient); all others must be refused.
MAY_RUN_MESHES = {"inverted", "clockwise", "huge-coord"}


def normalized_path(path):
    return re.sub(r"(Body|Mechanical boundary|Thermal boundary) \d+", r"\1 0", path)


def same_value(a, b):
    return re.sub(r"\s+", "", a) == re.sub(r"\s+", "", b)


def build_mutations(base_texts, defaults):
    """defaults: {normalized path: default value} (doc/parameters.prm); deleting a
    line that sets the default would leave the scene unchanged, so it is skipped."""
    muts = []
    add = muts.append

    # 1. Delete a line: every 'set' line, the first 'subsection' and the last 'end'.
    for base, text in base_texts.items():
        scene = Scene(text)
        for path, i, value in scene.entries():
            if (base, path) in SKIP_DELETIONS:
                continue
            default = defaults.get(normalized_path(path))
            if default is not None and same_value(default, value):
                continue
            add(Mutation("%s.del.L%d" % (base, i + 1),
                         "delete line %d 'set %s = %s'" % (i + 1, path.rsplit("/", 1)[-1],
                                                          value),
                         base, delete=i))
        lines = scene.lines
        first_sub = next(i for i, l in enumerate(lines) if l.strip().startswith("subsection "))
        last_end = max(i for i, l in enumerate(lines) if l.split("#")[0].strip() == "end")
        add(Mutation("%s.del.L%d" % (base, first_sub + 1),
                     "delete line %d '%s'" % (first_sub + 1, lines[first_sub].strip()),
                     base, delete=first_sub))
        add(Mutation("%s.del.L%d" % (base, last_end + 1),
                     "delete line %d (the last 'end')" % (last_end + 1), base,
                     delete=last_end))

    # 2. Non-finite, out-of-range and non-numeric values of positive quantities.
    for base, path, values in POSITIVE_ENTRIES:
        for short, value in values:
            add(Mutation("%s.num.%s.%s" % (base, slug(path), short),
                         "%s = %s" % (path, value), base, sets=[(path, value)],
                         refuse=short not in MAY_RUN_NUMBERS,
                         slow=path.endswith("End time") and short == "big"))
    for short, value in SUBDIVISION_VALUES:
        add(Mutation("manu.num.subdivisions.%s" % short, "Geometry/Subdivisions = %s" % value,
                     "manu", sets=[("Geometry/Subdivisions", value)], refuse=True))

    # Overflowing materials.
    add(Mutation("manu.ovf.rho-c", "Density = 1e308 and Heat capacities = 1e308 (rho c = inf)",
                 "manu", sets=[("Materials/Body 0/Density", "1e308"),
                               ("Materials/Body 0/Phase change/Heat capacities", "1e308")]))
    add(Mutation("neu.ovf.latent", "Density = 1e308 and Latent heats = 1e308 (rho L = inf)",
                 "neu", sets=[("Materials/Body 0/Density", "1e308"),
                              ("Materials/Body 0/Phase change/Latent heats", "1e308")]))
    add(Mutation("patch.ovf.lame", "Lame lambda = Lame mu = 1e308",
                 "patch", sets=[("Materials/Body 0/Elasticity", "lame"),
                                ("Materials/Body 0/Lame lambda", "1e308"),
                                ("Materials/Body 0/Lame mu", "1e308")]))
    add(Mutation("patch.ovf.voigt", "Elasticity tensor = 1e308, 0, 0, 1e308, 0, 1e308",
                 "patch", sets=[("Materials/Body 0/Elasticity", "anisotropic"),
                                ("Materials/Body 0/Elasticity tensor",
                                 "1e308, 0, 0, 1e308, 0, 1e308")]))
    add(Mutation("patch.num.voigt-nan", "Elasticity tensor with a nan",
                 "patch", sets=[("Materials/Body 0/Elasticity", "anisotropic"),
                                ("Materials/Body 0/Elasticity tensor",
                                 "1, 0, 0, nan, 0, 1")], refuse=True))
    add(Mutation("hertz.ovf.youngs", "Youngs modulus = 1e308 (obstacle contact)",
                 "hertz", sets=[("Materials/Body 0/Youngs modulus", "1e308")]))
    add(Mutation("neu.ovf.conductivity", "Conductivities = 1e308",
                 "neu", sets=[("Materials/Body 0/Conductivities", "1e308")]))

    # 3. Wrong types.
    for k, (base, path, value) in enumerate(WRONG_TYPES):
        add(Mutation("%s.type.%s.%d" % (base, slug(path), k),
                     "%s = %s (wrong type)" % (path, value), base, sets=[(path, value)],
                     refuse=True))

    # 4. Broken functions and functions that turn non-finite.
    for base, path, ncomp, may_run in FUNCTION_ENTRIES:
        original = Scene(base_texts[base]).get(path, "0; 0" if ncomp == 2 else "0")
        for short, expression, what in BAD_FUNCTIONS:
            value = bad_function_value(original, ncomp, expression)
            add(Mutation("%s.fn.%s.%s" % (base, fn_slug(path), short),
                         "%s = %s (%s)" % (path, value, what), base, sets=[(path, value)],
                         refuse=short not in may_run))
        if ncomp == 2:
            add(Mutation("%s.fn.%s.ncomp1" % (base, fn_slug(path)),
                         "%s = 0 (one component instead of two)" % path, base,
                         sets=[(path, "0")], refuse=True))
            add(Mutation("%s.fn.%s.ncomp3" % (base, fn_slug(path)),
                         "%s = 0; 0; 0 (three components)" % path, base,
                         sets=[(path, "0; 0; 0")], refuse=True))
    # NaN that only the VTU files would show.
    add(Mutation("manu.fn.heat-source.vtu-sqrt",
                 "Heat source = sqrt(-1-t) with VTU output every step", "manu",
                 sets=[("Materials/Body 0/Heat source", "sqrt(-1-t)"),
                       ("Output/VTU interval", "1")], refuse=True))
    add(Mutation("block.fn.body-force.vtu-pole",
                 "Body force = 0; 1/(x-0.5) with VTU output", "block",
                 sets=[("Materials/Body 0/Body force", "0; 1/(x-0.5)"),
                       ("Output/VTU interval", "1")]))
    add(Mutation("equi.fn.initial.exact-missing",
                 "Initial conditions/Function = exact with an exact solution that has none",
                 "equi", sets=[("Initial conditions/Function", "exact")], refuse=True))

    # 5. Garbage meshes.
    for short, desc, make, bases in MESH_MUTATIONS:
        for base in bases:
            add(Mutation("%s.mesh.%s" % (base, short), "Mesh file: %s" % desc, base,
                         mesh=make, refuse=short not in MAY_RUN_MESHES))

    # 6. The parameter file itself, and the output.
    manu = base_texts["manu"]
    R = dict(refuse=True)
    add(Mutation("prm.directory", "the parameter file is a directory (scene.prm/)",
                 prm_kind="dir", **R))
    add(Mutation("prm.missing", "the parameter file does not exist", prm_kind="missing", **R))
    add(Mutation("prm.binary", "the parameter file is binary garbage (with NUL bytes)",
                 prm_bytes=BINARY_BYTES, **R))
    add(Mutation("prm.binary-nonul", "the parameter file is binary garbage without NUL bytes",
                 prm_bytes=BINARY_BYTES.replace(b"\x00", b""), **R))
    add(Mutation("prm.binary-tail", "a valid scene followed by binary garbage",
                 prm_bytes=manu.encode() + BINARY_BYTES.replace(b"\x00", b""), **R))
    add(Mutation("prm.empty", "an empty parameter file (all defaults)", prm_bytes=b""))
    add(Mutation("prm.nul", "a NUL byte inside a value",
                 prm_bytes=manu.replace("set Density                 = 2",
                                        "set Density                 = 2\x001").encode(), **R))
    add(Mutation("prm.escape", "an ANSI escape sequence in an entry name",
                 prm_bytes=(manu + "subsection Geometry\nset Sub\x1b[31mdivisions = 4, 4\nend\n"
                            ).encode(), **R))
    add(Mutation("prm.latin1", "a Latin-1 (not UTF-8) byte in an unknown entry",
                 prm_bytes=manu.encode() + b"subsection Geometry\nset Gr\xf6\xdfe = 1\nend\n",
                 **R))
    add(Mutation("prm.crlf", "CRLF line endings",
                 prm_bytes=manu.replace("\n", "\r\n").encode()))
    add(Mutation("prm.json", "a .prm text in a file named scene.json",
                 prm_bytes=manu.encode(), prm_name="scene.json", **R))
    add(Mutation("prm.xml", "a .prm text in a file named scene.xml",
                 prm_bytes=manu.encode(), prm_name="scene.xml", **R))
    add(Mutation("prm.no-extension", "a parameter file without extension",
                 prm_bytes=manu.encode(), prm_name="scene"))
    add(Mutation("manu.prm.long-line", "a 1 MB value (Materials/Body 0/Name)", "manu",
                 sets=[("Materials/Body 0/Name", "x" * 1000000)]))
    add(Mutation("manu.prm.unknown-subsection", "an unknown subsection", "manu",
                 append="subsection Frobnication\n  set Speed = 1\nend\n", **R))
    add(Mutation("manu.prm.unknown-entry", "an unknown entry in Geometry", "manu",
                 append="subsection Geometry\n  set Colour = red\nend\n", **R))
    add(Mutation("manu.prm.unterminated", "a subsection without 'end'", "manu",
                 append="subsection Geometry\n", **R))
    add(Mutation("manu.prm.extra-end", "one 'end' too many", "manu", append="end\n", **R))
    add(Mutation("manu.prm.no-equals", "a 'set' line without '='", "manu",
                 append="subsection Geometry\n  set Subdivisions 4, 4\nend\n", **R))
    add(Mutation("patch.prm.body-undeclared", "Body ids = 0, 1, 5 (no body 5 in the mesh)",
                 "patch", sets=[("Bodies/Body ids", "0, 1, 5")], **R))

    # 'include' lines (expanded by contact-stefan, every included file checked
    # like the main one), encodings, line ends, entries set twice.
    def files(**contents):
        def setup(work):
            for name, data in contents.items():
                path = os.path.join(work, name.replace("_", "."))
                if data == "dir":
                    os.mkdir(path)
                elif data == "fifo":
                    os.mkfifo(path)
                else:
                    with open(path, "wb") as f:
                        f.write(data)
        return setup
    inc = lambda name: ("include %s\n" % name).encode()
    add(Mutation("prm.include-self", "the parameter file includes itself",
                 prm_bytes=manu.encode() + inc(SCENE_NAME), **R))
    add(Mutation("prm.include-loop", "scene.prm includes b.prm, which includes scene.prm",
                 prm_bytes=manu.encode() + inc("b.prm"), setup=files(b_prm=inc(SCENE_NAME)),
                 **R))
    add(Mutation("prm.include-directory", "include of a directory",
                 prm_bytes=manu.encode() + inc("sub"), setup=files(sub="dir"), **R))
    add(Mutation("prm.include-dev-zero", "include /dev/zero",
                 prm_bytes=manu.encode() + inc("/dev/zero"), **R))
    add(Mutation("prm.include-fifo", "include of a FIFO no one writes to",
                 prm_bytes=manu.encode() + inc("fifo.prm"), setup=files(fifo_prm="fifo"), **R))
    add(Mutation("prm.include-missing", "include of a file that does not exist",
                 prm_bytes=manu.encode() + inc("no-such-file.prm"), **R))
    add(Mutation("prm.include-empty-name", "'include' without a file name",
                 prm_bytes=manu.encode() + b"include   \n", **R))
    add(Mutation("prm.include-binary", "include of binary garbage",
                 prm_bytes=manu.encode() + inc("bin.prm"), setup=files(bin_prm=BINARY_BYTES),
                 **R))
    add(Mutation("prm.include-cr-only", "include of a file with CR-only line ends",
                 prm_bytes=inc("cr.prm"), setup=files(cr_prm=manu.replace("\n", "\r").encode()),
                 **R))
    add(Mutation("prm.include-utf16", "include of a UTF-16 file",
                 prm_bytes=inc("u16.prm"), setup=files(u16_prm=manu.encode("utf-16")), **R))
    add(Mutation("prm.include-unclosed", "an included file opens a subsection it does not close",
                 prm_bytes=manu.encode() + inc("open.prm"),
                 setup=files(open_prm=b"subsection Output\n"), **R))
    add(Mutation("prm.include-diamond", "includes doubling 40 levels deep (2^40 reads)",
                 prm_bytes=inc("d0.prm"),
                 setup=files(**{"d%d_prm" % k: inc("d%d.prm" % (k + 1)) * 2 for k in range(40)},
                             d40_prm=b"# empty\n"), **R))
    add(Mutation("prm.include-valid", "the whole scene in an included file",
                 prm_bytes=inc("base.prm"), setup=files(base_prm=manu.encode())))
    add(Mutation("prm.cr-only", "CR-only line ends (the scene starts with a comment)",
                 prm_bytes=manu.replace("\n", "\r").encode(), **R))
    add(Mutation("prm.utf8-bom", "a UTF-8 byte-order mark",
                 prm_bytes=b"\xef\xbb\xbf" + manu.encode()))
    add(Mutation("prm.utf16", "UTF-16 with a byte-order mark", prm_bytes=manu.encode("utf-16"),
                 **R))
    add(Mutation("prm.utf16be", "UTF-16BE without a byte-order mark",
                 prm_bytes=manu.encode("utf-16-be"), **R))
    add(Mutation("prm.utf32", "UTF-32 with a byte-order mark", prm_bytes=manu.encode("utf-32"),
                 **R))
    density = "set Density                 = 2"
    assert density in manu
    add(Mutation("prm.duplicate", "an entry set twice in one subsection (the same value)",
                 prm_bytes=manu.replace(density, density + "\n    set Density = 2").encode(), **R))
    add(Mutation("manu.prm.duplicate-block", "an entry set again in a second block of its "
                 "subsection", "manu",
                 append="subsection Materials\n  subsection Body 0\n    set Density = 3\n"
                        "  end\nend\n", **R))
    add(Mutation("prm.duplicate-include", "an entry set in the scene and in an included file",
                 prm_bytes=manu.encode() + inc("density.prm"),
                 setup=files(density_prm=b"subsection Materials\nsubsection Body 0\n"
                                         b"set Density = 3\nend\nend\n"), **R))

    # Root writes into a 555 directory: then the run may go on.
    add(Mutation("manu.out.readonly", "Output/Directory under a read-only (555) directory",
                 "manu", sets=[("Output/Directory", "ro/out")], setup=make_readonly_dir,
                 refuse=os.geteuid() != 0))
    add(Mutation("manu.out.file", "Output/Directory is an existing regular file",
                 "manu", sets=[("Output/Directory", "blocker")], setup=make_blocker_file, **R))
    add(Mutation("manu.out.file-parent", "Output/Directory below a regular file",
                 "manu", sets=[("Output/Directory", "blocker/out")], setup=make_blocker_file,
                 **R))
    add(Mutation("manu.out.proc", "Output/Directory in /proc (unwritable even for root)",
                 "manu", sets=[("Output/Directory", "/proc/contact-stefan-mutation")], **R))
    add(Mutation("manu.out.empty", "Output/Directory empty", "manu",
                 sets=[("Output/Directory", "")], **R))
    add(Mutation("manu.out.stats-empty", "Output/Statistics file empty", "manu",
                 sets=[("Output/Directory", "output"), ("Output/Statistics file", "")], **R))
    add(Mutation("manu.out.stats-dir", "the statistics file exists as a directory", "manu",
                 sets=[("Output/Directory", "output")],
                 setup=make_output_entry("statistics.txt", "dir"), **R))
    add(Mutation("manu.out.stats-subdir", "Statistics file = no/such/dir/stats.txt", "manu",
                 sets=[("Output/Directory", "output"),
                       ("Output/Statistics file", "no/such/dir/stats.txt")], **R))
    add(Mutation("manu.out.stats-full", "the statistics file is /dev/full (disk full)",
                 "manu", sets=[("Output/Directory", "output")],
                 setup=make_output_entry("statistics.txt", "full"), **R))
    add(Mutation("manu.out.vtu-full", "the first VTU file is /dev/full (disk full)",
                 "manu", sets=[("Output/Directory", "output"), ("Output/VTU interval", "1")],
                 setup=make_output_entry("solution_00000.0.vtu", "full"), **R))
    # (solution.pvd is written as solution.pvd.tmp and renamed: the disk is
    # full where the text goes)
    add(Mutation("manu.out.pvd-full", "the PVD file is /dev/full (disk full)",
                 "manu", sets=[("Output/Directory", "output"), ("Output/VTU interval", "1")],
                 setup=make_output_entry("solution.pvd.tmp", "full"), **R))
    add(Mutation("manu.out.vtu-dir", "the first VTU file exists as a directory",
                 "manu", sets=[("Output/Directory", "output"), ("Output/VTU interval", "1")],
                 setup=make_output_entry("solution_00000.0.vtu", "dir"), **R))

    # 7. Huge problems and time steps below the resolution of t. A run may go on
    # only if it ends in time (slow: probably not; scheduled first).
    add(Mutation("patch.huge.refine12", "Initial global refinements = 12", "patch",
                 sets=[("Mesh refinement/Initial global refinements", "12")], slow=True))
    add(Mutation("manu.huge.refine12", "Initial global refinements = 12 (thermal)", "manu",
                 sets=[("Mesh refinement/Initial global refinements", "12")], slow=True))
    add(Mutation("manu.huge.subdivisions", "Subdivisions = 100000, 100000", "manu",
                 sets=[("Geometry/Subdivisions", "100000, 100000")], slow=True))
    add(Mutation("hertz.huge.prerefine", "Pre-refinement steps = 40", "hertz",
                 sets=[("Mesh refinement/Pre-refinement steps", "40")], slow=True))
    add(Mutation("manu.time.resolution", "Start time = 1e20, End time = 1.0000000001e20, "
                 "Time step = 1000 (t + tau == t)", "manu",
                 sets=[("Time stepping/Start time", "1e20"),
                       ("Time stepping/End time", "1.0000000001e20"),
                       ("Time stepping/Time step", "1000")], slow=True, **R))
    add(Mutation("manu.time.end-1e308", "End time = 1e308", "manu",
                 sets=[("Time stepping/End time", "1e308")], slow=True))
    add(Mutation("manu.time.tau-1e-12", "Time step = 1e-12", "manu",
                 sets=[("Time stepping/Time step", "1e-12")], slow=True))
    add(Mutation("patch.time.tau-1e-12", "Time step = 1e-12 (contact)", "patch",
                 sets=[("Time stepping/Time step", "1e-12")], slow=True))
    add(Mutation("manu.time.tau-denorm-start", "Start time = 1e-300, End time = 2e-300, "
                 "Time step = 1e-320", "manu",
                 sets=[("Time stepping/Start time", "1e-300"),
                       ("Time stepping/End time", "2e-300"),
                       ("Time stepping/Time step", "1e-320")], slow=True))
    add(Mutation("neu.time.end-before-start", "End time = Start time = 0.1", "neu",
                 sets=[("Time stepping/End time", "0.1")], **R))
    add(Mutation("neu.solver.relaxation-endless",
                 "relaxation solver, parameter 1e-300, 2147483647 iterations", "neu",
                 sets=[("Solver/Enthalpy solver", "relaxation"),
                       ("Solver/Relaxation parameter", "1e-300"),
                       ("Solver/Relaxation max iterations", "2147483647")], slow=True))
    add(Mutation("neu.solver.cg-zero", "cg-amg with CG max iterations = 0", "neu",
                 sets=[("Solver/Linear solver", "cg-amg"), ("Solver/CG max iterations", "0")],
                 **R))
    add(Mutation("hertz.contact.max-iterations-1e9", "Contact Max iterations = 2000000000, "
                 "Tolerance = 0", "hertz",
                 sets=[("Contact/Max iterations", "2000000000"), ("Contact/Tolerance", "0")],
                 slow=True))

    ids = [m.id for m in muts]
    dup = sorted({i for i in ids if ids.count(i) > 1})
    if dup:
        raise SystemExit("duplicate mutation ids: %s" % ", ".join(dup))
    return muts


# --------------------------------------------------------------------------------
# Running one case.

NONFINITE = re.compile(r"(?<![A-Za-z_])[-+]?(nan|inf|infinity)(?![A-Za-z_])", re.I)
CRASH_TEXT = ("terminate called", "Stacktrace", "stacktrace", "Backtrace", "backtrace",
              "MPI_ABORT", "Segmentation fault")
CONTROL = re.compile(rb"[\x00-\x08\x0b-\x1f\x7f]")


def prepare(m, work, base_texts, meshes):
    os.makedirs(work)
    prm = os.path.join(work, m.prm_name)
    scene = None
    if m.prm_kind == "dir":
        os.mkdir(prm)
    elif m.prm_kind == "missing":
        pass
    elif m.prm_bytes is not None:
        with open(prm, "wb") as f:
            f.write(m.prm_bytes)
    else:
        scene = Scene(base_texts[m.base])
        if m.delete is not None:
            scene.delete(m.delete)
        for path, value in m.sets:
            scene.set(path, value)
        with open(prm, "w") as f:
            f.write(scene.text())
            f.write(m.append)
    if m.base in MESHES:
        name = MESHES[m.base][0]
        target = os.path.join(work, name)
        content = meshes[m.base].encode() if m.mesh is None else m.mesh(meshes[m.base])
        if content == "dir":
            os.mkdir(target)
        elif content != "missing":
            with open(target, "wb") as f:
                f.write(content)
    if m.setup:
        m.setup(work)
    return prm, scene


def check_vtk_file(path):
    """Problems of one .vtu/.pvtu/.pvd file: unclosed, or non-finite data."""
    with open(path, "rb") as f:
        data = f.read()
    if not data.rstrip().endswith(b"</VTKFile>"):
        return ["%s is truncated (no closing </VTKFile>, %d bytes)" % (path, len(data))]
    problems = []
    text = data.decode("latin-1")
    for m in re.finditer(r'<DataArray([^>]*)>(.*?)</DataArray>', text, re.S):
        attrs, body = m.group(1), m.group(2).strip()
        kind = re.search(r'type="(Float32|Float64)"', attrs)
        if not kind:
            continue
        name = re.search(r'Name="([^"]*)"', attrs)
        name = name.group(1) if name else "points"
        values = None
        if 'format="ascii"' in attrs:
            if NONFINITE.search(body):
                values = [float("nan")]
        else:
            values = decode_binary(body, "f" if kind.group(1) == "Float32" else "d",
                                   "compressor" in text[:2000])
        if values is not None and not all(math.isfinite(v) for v in values):
            bad = sum(1 for v in values if not math.isfinite(v))
            problems.append("%s: %d non-finite values in '%s'" %
                            (os.path.basename(path), bad, name))
    return problems


def decode_binary(body, code, compressed):
    try:
        body = "".join(body.split())
        if compressed:
            head = base64.b64decode(body[:8])
            nblocks = int.from_bytes(head[:4], "little")
            hbytes = (3 + nblocks) * 4
            hlen = 4 * ((hbytes + 2) // 3)
            header = base64.b64decode(body[:hlen])
            sizes = [int.from_bytes(header[4 * k:4 * k + 4], "little")
                     for k in range(3, 3 + nblocks)]
            raw = base64.b64decode(body[hlen:])
            out, pos = b"", 0
            for s in sizes:
                out += zlib.decompress(raw[pos:pos + s])
                pos += s
        else:
            raw = base64.b64decode(body)
            out = raw[4:]
        values = array.array(code)
        values.frombytes(out[: len(out) - len(out) % values.itemsize])
        return values
    except Exception:  # undecodable: not judged here
        return None


def check_statistics(path):
    problems = []
    with open(path, "rb") as f:
        data = f.read()
    text = data.decode("utf-8", "replace")
    if not text:
        return problems
    if not text.endswith("\n"):
        problems.append("%s: last line incomplete" % os.path.basename(path))
    lines = [line for line in text.splitlines() if not line.startswith("#")]
    if not lines:
        return problems
    ncol = len(lines[0].split())
    for k, line in enumerate(lines[1:], 2):
        fields = line.split()
        if len(fields) != ncol:
            problems.append("%s line %d: %d columns, header has %d" %
                            (os.path.basename(path), k, len(fields), ncol))
            break
    for k, line in enumerate(lines[1:], 2):
        for token in line.split():
            try:
                v = float(token)
            except ValueError:
                continue
            if not math.isfinite(v):
                problems.append("%s line %d: non-finite '%s'" %
                                (os.path.basename(path), k, token))
                return problems
    return problems


def check_outputs(work, scene):
    """Half-written or non-finite output files in the work directory."""
    stats_names = {"statistics.txt"}
    if scene is not None:
        name = scene.get("Output/Statistics file")
        if name:
            stats_names.add(os.path.basename(name))
    problems = []
    for root, dirs, files in os.walk(work):
        for name in files:
            path = os.path.join(root, name)
            if os.path.islink(path) or not os.path.isfile(path):
                continue
            rel = os.path.relpath(path, work)
            try:
                if name.endswith((".vtu", ".pvtu", ".pvd")):
                    problems += [p.replace(path, rel) for p in check_vtk_file(path)]
                elif name in stats_names:
                    problems += check_statistics(path)
            except OSError as e:
                problems.append("%s unreadable: %s" % (rel, e))
    return problems


def printable(text):
    """text with control characters and non-ASCII escaped (safe for any terminal)."""
    text = re.sub(r"[\x00-\x08\x0b-\x1f\x7f]", lambda m: "\\x%02x" % ord(m.group()), text)
    return text.encode("ascii", "backslashreplace").decode()


def first_lines(data, n=2, width=200):
    text = data.decode("utf-8", "backslashreplace")
    lines = [l for l in text.split("\n") if l.strip()][:n]
    out = " | ".join(l[:width] + ("..." if len(l) > width else "") for l in lines)
    return printable(out) or "(empty)"


def classify(rc, timed_out, out, err, output_problems, timeout, must_refuse):
    """('refused' | 'ran' | 'fail', reason)."""
    text_err = err.decode("utf-8", "replace")
    text_out = out.decode("utf-8", "replace")
    if timed_out:
        last = [l for l in text_out.splitlines() if l.strip()]
        return "fail", "timeout after %g s (hang); last stdout line: %s" % (
            timeout, printable(" ".join(last[-1].split())[:150]) if last else "(none)")
    if rc < 0:
        try:
            name = signal.Signals(-rc).name
        except ValueError:
            name = str(-rc)
        return "fail", "killed by signal %s; stderr: %s" % (name, first_lines(err))
    crash = [t for t in CRASH_TEXT if t in text_err or t in text_out]
    if crash:
        return "fail", "exit %d with crash text '%s'; stderr: %s" % (rc, crash[0],
                                                                     first_lines(err))
    if rc in (0, 3):
        # 0: a clean run (empty stderr, or warnings about the mesh). 3: finished with complete, finite
        # output, but one of the run's own checks failed (a strain above the
        # small-strain limit, enthalpies outside H(Theta)): one 'warning:'
        # line each on stderr, no error line.
        problems = []
        lines = [l for l in err.split(b"\n") if l]
        if rc == 3 and not lines:
            problems.append("no warning line")
        for line in lines:
            if not line.startswith(b"contact-stefan: warning: ") or CONTROL.search(line):
                problems.append("stderr line is not a warning: %s" % printable(
                    line.decode("utf-8", "replace")[:150]))
                break
        for line in text_out.splitlines():
            if NONFINITE.search(line):
                problems.append("non-finite number in stdout: '%s'" %
                                printable(line.strip()[:150]))
                break
        problems += output_problems
        if must_refuse:
            problems.insert(0, "the invalid input was accepted")
        if problems:
            return "fail", "exit %d but " % rc + "; ".join(problems[:3])
        return ("ran", "") if rc == 0 and not lines else ("warned", printable(text_err.strip()))
    if rc in (1, 2):
        problems = []
        lines = err.split(b"\n")
        if lines and lines[-1] == b"":
            lines.pop()
        if not lines:
            problems.append("stderr is empty")
        elif len(lines) != 1:
            problems.append("stderr has %d lines: %s" % (len(lines), first_lines(err, 3)))
        elif not lines[0].strip():
            problems.append("the stderr line is empty")
        else:
            line = lines[0]
            if CONTROL.search(line):
                problems.append("stderr has raw control bytes: %s" % first_lines(err))
            try:
                line.decode("utf-8")
            except UnicodeDecodeError:
                problems.append("stderr is not UTF-8: %s" % first_lines(err))
            message = re.sub(r"^contact-stefan: error(\s*\(rank \d+\))?:\s*", "",
                             line.decode("utf-8", "replace")).strip()
            if len(message) < 12 or re.fullmatch(r"[\w:]+", message):
                problems.append("stderr does not name the cause: '%s'" % message)
            elif message.endswith(("<", ":")):
                problems.append("the error line ends in '%s' (cut off, or no cause named): "
                                "'%s'" % (message[-1], message[-60:]))
        problems += output_problems
        if problems:
            return "fail", "exit %d but " % rc + "; ".join(problems[:3])
        return "refused", printable(text_err.strip())
    return "fail", "exit code %d; stderr: %s" % (rc, first_lines(err))


def read_bounded(path, limit=1 << 20):
    with open(path, "rb") as f:
        data = f.read(limit)
    return data


def make_writable(path):
    for root, dirs, _ in os.walk(path):
        for d in dirs:
            p = os.path.join(root, d)
            if not os.path.islink(p):
                try:
                    os.chmod(p, 0o755)
                except OSError:
                    pass


def remove_tree(path):
    make_writable(path)
    shutil.rmtree(path, ignore_errors=True)


def keep_case(case, dest, m, reason):
    """Copy the work directory (without Open MPI's session files) and the outputs."""
    remove_tree(dest)
    make_writable(case)
    try:
        shutil.copytree(os.path.join(case, "work"), os.path.join(dest, "work"),
                        symlinks=True, ignore_dangling_symlinks=True)
    except (shutil.Error, OSError) as e:
        os.makedirs(dest, exist_ok=True)
        with open(os.path.join(dest, "copy-errors.txt"), "w") as f:
            f.write("%s\n" % e)
    for name in ("stdout.txt", "stderr.txt"):
        try:
            shutil.copy(os.path.join(case, name), dest)
        except OSError:
            pass
    with open(os.path.join(dest, "verdict.txt"), "w") as f:
        f.write("%s\n%s\nFAIL: %s\n" % (m.id, m.desc, reason))


def run_case(m, args, root, base_texts, meshes):
    case = os.path.join(root, m.id)
    work = os.path.join(case, "work")
    tmp = os.path.join(case, "tmp")
    os.makedirs(tmp)
    prm, scene = prepare(m, work, base_texts, meshes)
    env = dict(os.environ)
    env["TMPDIR"] = tmp  # Open MPI's session directory: one per case
    # (The serial MPI start is the program's own, as a user gets it:
    # include/contact-stefan/app/mpi_start.h.)
    stdout_path, stderr_path = os.path.join(case, "stdout.txt"), os.path.join(case,
                                                                            "stderr.txt")
    start = time.monotonic()
    timed_out = False
    with open(stdout_path, "wb") as out, open(stderr_path, "wb") as err:
        proc = subprocess.Popen([args.binary, os.path.basename(prm)], cwd=work, stdout=out,
                                stderr=err, stdin=subprocess.DEVNULL, env=env,
                                start_new_session=True)
        try:
            rc = proc.wait(timeout=args.timeout)
        except subprocess.TimeoutExpired:
            timed_out = True
            try:
                os.killpg(proc.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
            rc = proc.wait()
    elapsed = time.monotonic() - start
    out, err = read_bounded(stdout_path, 64 << 20), read_bounded(stderr_path)
    problems = [] if timed_out else check_outputs(work, scene)
    verdict, reason = classify(rc, timed_out, out, err, problems, args.timeout, m.refuse)
    if verdict == "fail" and args.keep:
        keep_case(case, os.path.join(args.keep, m.id), m, reason)
    remove_tree(case)
    return m, verdict, reason, elapsed


# --------------------------------------------------------------------------------

def generate_meshes(args, directory):
    script = os.path.join(args.source_dir, "tests", "make_two_blocks_msh.cmake")
    meshes = {}
    for base, (name, kink) in MESHES.items():
        target = os.path.join(directory, name)
        if kink == "mortar":
            subprocess.run([sys.executable, os.path.join(args.source_dir, "tests",
                                                         "make_mortar_msh.py"),
                            target, "--lower", "2,2", "--upper", "7,3", "--perturb", "upper"],
                           check=True, stdout=subprocess.DEVNULL)
            with open(target) as f:
                meshes[base] = f.read()
            continue
        command = [args.cmake, "-DOUTPUT=" + target]
        if kink:
            command.append("-DKINK=ON")
        subprocess.run(command + ["-P", script], check=True, stdout=subprocess.DEVNULL)
        with open(target) as f:
            meshes[base] = f.read()
    return meshes


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--binary", help="the contact-stefan executable")
    parser.add_argument("--source-dir", default=os.path.join(os.path.dirname(
        os.path.abspath(__file__)), os.pardir), help="repository root (finds the scenes)")
    parser.add_argument("--jobs", type=int, default=2, help="cases run in parallel")
    parser.add_argument("--timeout", type=float, default=30, help="seconds per case")
    parser.add_argument("--list", action="store_true", help="print the mutations and exit")
    parser.add_argument("--keep", help="copy the work directories of failures here")
    parser.add_argument("--filter", help="run only mutations whose id matches this regex")
    parser.add_argument("--cmake", default=shutil.which("cmake") or "cmake",
                        help="cmake, to generate the Gmsh test meshes")
    parser.add_argument("--memory-limit", type=int, default=4096,
                        help="address-space limit per case in MiB (0: none)")
    parser.add_argument("--verbose", action="store_true", help="one line per case")
    parser.add_argument("--sample", type=int, default=1,
                        help="run every N-th mutation only (1: all)")
    parser.add_argument("--sample-offset", type=int,
                        help="which N-th (0..N-1); default: the UTC day number modulo N, "
                             "so that N consecutive days run every mutation")
    args = parser.parse_args()
    args.source_dir = os.path.abspath(args.source_dir)

    base_texts = {}
    for base, rel in BASES.items():
        with open(os.path.join(args.source_dir, rel)) as f:
            base_texts[base] = f.read()
    defaults = {}
    reference = os.path.join(args.source_dir, "doc", "parameters.prm")
    if os.path.exists(reference):
        with open(reference) as f:
            defaults = {p: v for p, _, v in Scene(f.read()).entries()}
    mutations = build_mutations(base_texts, defaults)
    if args.filter:
        mutations = [m for m in mutations if re.search(args.filter, m.id)]
    # A sample for the regression suite: each case starts the solver, whose
    # dynamic loading alone is about 0.5 s of CPU (benchmarks/startup.py), so the
    # 641 cases are most of 4 minutes on 2 cores. The sample rotates with the
    # day: a case left out today runs tomorrow, and the offset printed here
    # repeats today's choice.
    sample_note = ""
    if args.sample < 1:
        parser.error("--sample must be at least 1")
    if args.sample_offset is not None and args.sample == 1:
        parser.error("--sample-offset needs --sample N with N > 1")
    if args.sample > 1:
        offset = args.sample_offset
        if offset is None:
            offset = int(time.time() // 86400) % args.sample
        if not 0 <= offset < args.sample:
            parser.error("--sample-offset must lie in 0..%d" % (args.sample - 1))
        total = len(mutations)
        mutations = [m for k, m in enumerate(mutations) if k % args.sample == offset]
        sample_note = ("sample: %d of %d mutations (--sample %d --sample-offset %d; "
                       "--sample 1 runs all)" % (len(mutations), total, args.sample, offset))
    # A selection that runs nothing would pass without having checked anything.
    if not mutations:
        parser.error("no mutation selected (--filter %r%s)" % (
            args.filter, ", " + sample_note if sample_note else ""))

    if sample_note:
        print(sample_note, flush=True)
    if args.list:
        for m in mutations:
            print("%-48s %s %s%s" % (m.id, "refuse" if m.refuse else "either",
                                     ("[%s] " % BASES[m.base]) if m.base else "", m.desc))
        print("%d mutations" % len(mutations))
        return 0
    if not args.binary:
        parser.error("--binary is required")
    args.binary = os.path.abspath(args.binary)
    if not os.access(args.binary, os.X_OK):
        parser.error("cannot execute %s" % args.binary)
    if args.keep:
        args.keep = os.path.abspath(args.keep)
        os.makedirs(args.keep, exist_ok=True)

    # Limits inherited by every case: no core files, bounded memory and file size,
    # so that a huge mutation fails alone instead of taking the machine with it.
    resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    if args.memory_limit > 0:
        limit = args.memory_limit << 20
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
    resource.setrlimit(resource.RLIMIT_FSIZE, (1 << 30, 1 << 30))

    start = time.monotonic()
    root = tempfile.mkdtemp(prefix="contact-stefan-mutation-")
    try:
        meshes = generate_meshes(args, root)
        order = sorted(range(len(mutations)), key=lambda k: not mutations[k].slow)
        results = {}
        with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
            futures = {pool.submit(run_case, mutations[k], args, root, base_texts, meshes): k
                       for k in order}
            for future in concurrent.futures.as_completed(futures):
                m, verdict, reason, elapsed = future.result()
                results[futures[future]] = (verdict, reason, elapsed)
                if args.verbose:
                    print("%-7s %5.1fs  %s  %s" % (verdict, elapsed, m.id, reason[:160]),
                          flush=True)
    finally:
        remove_tree(root)

    counts = {"refused": 0, "ran": 0, "warned": 0, "fail": 0}
    for k, m in enumerate(mutations):
        verdict, reason, _ = results[k]
        counts[verdict] += 1
        if verdict == "fail":
            print("FAIL %s: %s: %s" % (m.id, m.desc, reason))
    # Counts by class: the kind of mutation, the second part of its id
    # ("neu.fn.heat-source.nan": fn), or its first for the whole-file cases
    # ("prm.crlf": prm).
    by_class = {}
    for k, m in enumerate(mutations):
        parts = m.id.split(".")
        cls = parts[0] if parts[0] == "prm" or len(parts) < 2 else parts[1]
        row = by_class.setdefault(cls, {"refused": 0, "ran": 0, "fail": 0})
        verdict = results[k][0]
        row["ran" if verdict == "warned" else verdict] += 1
    print("%-10s %8s %5s %7s" % ("class", "refused", "ran", "failed"))
    for cls in sorted(by_class):
        row = by_class[cls]
        print("%-10s %8d %5d %7d" % (cls, row["refused"], row["ran"], row["fail"]))
    clean = counts["refused"] + counts["ran"] + counts["warned"]
    print("mutations: %d  refused: %d  ran: %d  ran with warnings (exit 0 or 3): %d  clean: %d  "
          "failed: %d" % (len(mutations), counts["refused"], counts["ran"], counts["warned"],
                          clean, counts["fail"]))
    print("wall time: %.0f s with %d job(s)" % (time.monotonic() - start, args.jobs))
    print("%d passed, %d failed" % (clean, counts["fail"]))
    return 1 if counts["fail"] else 0


if __name__ == "__main__":
    sys.exit(main())
