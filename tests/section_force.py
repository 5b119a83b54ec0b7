#!/usr/bin/python3
"""Section-force check of the written stress fields (doc/output.md).

    section_force.py OUTPUT_DIR --resultant F [--cell-tolerance 1e-10]
                     [--nodal-tolerance T] [--min-lines N]

Reads every step of OUTPUT_DIR/solution.pvd (all pieces of every .pvtu) and,
in each body (cell data 'body_id'), finds every horizontal mesh line: a height
y at which the faces of the body's cells cover the body's whole width from
above, or from below. Across each such line it integrates sigma_yy

  * of the cell data 'cell_stress_yy' (the value at the centre of each cell
    whose bottom, or top, face lies on the line, times the cell's width), and
  * of the point data 'stress_yy' (the recovered nodal field, by the
    trapezoidal rule along the same faces),

and compares each integral with F, the resultant that equilibrium fixes (N/m:
the applied traction times the width). On a side whose cells all have the same
height (a row of equal cells) the cell-centre integral is the exact section
force of the discrete equilibrium, and so is the recovered one on a uniform
mesh; where hanging nodes border the row neither is, and those sides are
reported, not checked (doc/output.md). It exits non-zero if a checked
deviation exceeds its tolerance, or if fewer than N sides on rows of equal
cells were checked in some step (so that a run that writes nothing cannot
pass). The closing line is 'N passed, M failed' over the steps. VTU files
hold single-precision values: a tolerance below about 1e-6 cannot be met.
"""
import argparse
import array
import base64
import os
import re
import sys
import zlib


def decode(attrs, body, compressed):
    code = {"Float32": "f", "Float64": "d", "Int32": "i", "UInt32": "I", "Int64": "q",
            "UInt64": "Q", "UInt8": "B"}[re.search(r'type="(\w+)"', attrs).group(1)]
    if 'format="ascii"' in attrs:
        return [float(v) for v in body.split()]
    body = "".join(body.split())
    if compressed:
        head = base64.b64decode(body[:8])
        nblocks = int.from_bytes(head[:4], "little")
        hlen = 4 * (((3 + nblocks) * 4 + 2) // 3)
        header = base64.b64decode(body[:hlen])
        sizes = [int.from_bytes(header[4 * k:4 * k + 4], "little")
                 for k in range(3, 3 + nblocks)]
        raw, out, pos = base64.b64decode(body[hlen:]), b"", 0
        for s in sizes:
            out += zlib.decompress(raw[pos:pos + s])
            pos += s
    else:
        out = base64.b64decode(body)[4:]
    values = array.array(code)
    values.frombytes(out[: len(out) - len(out) % values.itemsize])
    return list(values)


def read_piece(path):
    """Cells of one .vtu piece: (points, cell data, point data per cell)."""
    text = open(path, encoding="latin-1").read()
    compressed = "compressor" in text[:2000]
    arrays = {}
    for section in ("Points", "Cells", "PointData", "CellData"):
        m = re.search(r"<%s[^>]*>(.*?)</%s>" % (section, section), text, re.S)
        if not m:
            continue
        for d in re.finditer(r"<DataArray([^>]*)>(.*?)</DataArray>", m.group(1), re.S):
            name = re.search(r'Name="([^"]*)"', d.group(1))
            key = (section, name.group(1) if name else "")
            arrays[key] = (decode(d.group(1), d.group(2), compressed), d.group(1))
    points = arrays[("Points", "")][0]
    connectivity = arrays[("Cells", "connectivity")][0]
    offsets = arrays[("Cells", "offsets")][0]
    cells, start = [], 0
    for end in offsets:
        vertices = [int(v) for v in connectivity[int(start):int(end)]]
        cells.append(vertices)
        start = end
    cell_data = {k[1]: v[0] for k, v in arrays.items() if k[0] == "CellData"}
    point_data = {k[1]: v[0] for k, v in arrays.items() if k[0] == "PointData"}
    result = []
    for c, vertices in enumerate(cells):
        xy = [(points[3 * v], points[3 * v + 1]) for v in vertices]
        point = {k: [v[p] for p in vertices] for k, v in point_data.items()}
        # deal.II 9.4 writes cell data as point data, constant on each cell's
        # own copies of its vertices.
        cell = {k: v[0] for k, v in point.items() if k.startswith("cell_") or k == "body_id"}
        cell.update({k: v[c] for k, v in cell_data.items()})
        result.append({"xy": xy, "cell": cell, "point": point})
    return result


def read_step(pvtu):
    directory = os.path.dirname(pvtu)
    text = open(pvtu, encoding="latin-1").read()
    cells = []
    for piece in re.findall(r'<Piece Source="([^"]*)"', text):
        cells += read_piece(os.path.join(directory, piece))
    return cells


def edge_integral(cell, name, y):
    """Integral of the point data 'name' along the cell's face at height y."""
    pts = [(x, v) for (x, yy), v in zip(cell["xy"], cell["point"][name]) if yy == y]
    assert len(pts) == 2, "face of %d points" % len(pts)
    (x0, v0), (x1, v1) = pts
    return 0.5 * (v0 + v1) * abs(x1 - x0)


def check_step(cells):
    """[(body, y, side, cell integral, nodal integral)] for every full line."""
    lines = []
    for body in sorted({int(c["cell"]["body_id"]) for c in cells}):
        mine = [c for c in cells if int(c["cell"]["body_id"]) == body]
        for c in mine:
            xs = [p[0] for p in c["xy"]]
            ys = [p[1] for p in c["xy"]]
            c["box"] = (min(xs), max(xs), min(ys), max(ys))
        xmin = min(c["box"][0] for c in mine)
        xmax = max(c["box"][1] for c in mine)
        width = xmax - xmin
        heights = sorted({c["box"][2] for c in mine} | {c["box"][3] for c in mine})
        for y in heights:
            for side, index in (("above", 2), ("below", 3)):
                row = [c for c in mine if c["box"][index] == y]
                covered = sum(c["box"][1] - c["box"][0] for c in row)
                if not row or abs(covered - width) > 1e-12 * width:
                    continue  # the line cuts through cells of this side
                cell_force = sum(c["cell"]["cell_stress_yy"] * (c["box"][1] - c["box"][0])
                                 for c in row)
                nodal_force = sum(edge_integral(c, "stress_yy", y) for c in row)
                row_heights = [c["box"][3] - c["box"][2] for c in row]
                uniform = max(row_heights) - min(row_heights) <= 1e-6 * max(row_heights)
                lines.append((body, y, side, cell_force, nodal_force, uniform))
    return lines


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("directory")
    parser.add_argument("--resultant", type=float, required=True)
    parser.add_argument("--cell-tolerance", type=float, default=1e-10)
    parser.add_argument("--nodal-tolerance", type=float, required=True)
    parser.add_argument("--min-lines", type=int, default=4)
    args = parser.parse_args()

    pvd = open(os.path.join(args.directory, "solution.pvd")).read()
    steps = re.findall(r'timestep="([^"]*)"[^>]*file="([^"]*)"', pvd)
    if not steps:
        print("no steps in %s/solution.pvd" % args.directory)
        return 1
    passed = failed = 0
    worst = {"cell": 0.0, "nodal": 0.0, "cell, other rows": 0.0, "nodal, other rows": 0.0}
    scale = abs(args.resultant)
    for time, name in steps:
        lines = check_step(read_step(os.path.join(args.directory, name)))
        error = {}
        for key, index, uniform in (("cell", 3, True), ("nodal", 4, True),
                                    ("cell, other rows", 3, False),
                                    ("nodal, other rows", 4, False)):
            error[key] = max((abs(l[index] - args.resultant) / scale for l in lines
                              if l[5] == uniform), default=0)
            worst[key] = max(worst[key], error[key])
        n_uniform = sum(1 for l in lines if l[5])
        ok = (n_uniform >= args.min_lines and error["cell"] <= args.cell_tolerance and
              error["nodal"] <= args.nodal_tolerance)
        print("t = %-12s sides %3d (%3d on rows of equal cells: cell-centre %.3e, recovered "
              "%.3e; other rows %.3e, %.3e)  %s" %
              (time, len(lines), n_uniform, error["cell"], error["nodal"],
               error["cell, other rows"], error["nodal, other rows"], "ok" if ok else "FAIL"))
        if not ok:
            for body, y, side, cf, nf, uniform in lines:
                print("  body %d y = %g %s%s: cell %.10e nodal %.10e" %
                      (body, y, side, "" if uniform else " (unequal cells)", cf, nf))
        passed += ok
        failed += not ok
    print("largest relative deviation on rows of equal cells: cell-centre %.3e (tolerance "
          "%.1e), recovered %.3e (tolerance %.1e); on other rows (not checked): %.3e, %.3e" %
          (worst["cell"], args.cell_tolerance, worst["nodal"], args.nodal_tolerance,
           worst["cell, other rows"], worst["nodal, other rows"]))
    print("%d passed, %d failed" % (passed, failed))
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
