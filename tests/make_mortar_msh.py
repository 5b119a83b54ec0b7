#!/usr/bin/python3
"""Writes a Gmsh 2.2 mesh of two blocks meshed independently (for the mortar
tests, doc/contact.md): a lower block [0, W] x [0, H] (physical surface 1) and
an upper block [0, W] x [H, 2H] (physical surface 2), each a structured grid of
its own, so that their nodes along y = H do not match. Physical lines: 10 the
left sides (x = 0), 11 the right sides (x = W), 12 the bottom, 13 the top, 14
the lower block's side of the interface, 15 the upper block's.

  make_mortar_msh.py OUTPUT --lower NX,NY --upper NX,NY [--width W] [--height H]
                     [--perturb lower|upper] [--bump A] [--shift S] [--merge]
                     [--split-lower X] [--lift L] [--rotate DEG] [--centre]
                     [--upper-width WU]

--perturb moves the interior interface nodes of one block along x by up to 0.3
of its cell width (x_i += 0.3 h sin(7 i)), with the column of nodes above or
below them, so that no two interface nodes line up. --bump A makes the
interface the curve y = H + A sin(pi x / W) (both blocks' nodes on it: the two
polylines differ by O(h^2)). --shift S moves the upper block right by S (it
then overhangs the lower one). --merge (equal NX, no perturbation or shift)
writes the same mesh with the interface nodes shared, for the node-to-node
interface to compare with (no lines 14 and 15). --split-lower X makes the lower
block's cells right of x = X body 3 (sharing the nodes on x = X with body 1),
their top faces line 16 and the upper block's bottom faces right of X line 17:
two interfaces, 1-2 and 2-3, whose sides meet at x = X. --lift L moves the
upper block up by L (a gap). --rotate DEG turns the whole mesh by DEG degrees
about the middle of the interface (W/2, H). --centre moves the mesh left by W/2,
so that the middle of the interface is at x = 0 (lines 10 and 11 at x = -W/2 and
W/2). --upper-width WU makes the upper block [S, S + WU] wide (a block on a
longer base, for the sliding tests). The test meshes are generated, never
committed."""
import argparse
import math


def block(nx, ny, width, x0, y_bottom, y_top, perturb):
    """Nodes (x, y) of a structured grid between the curves y_bottom(x) and
    y_top(x), row by row from the bottom; with perturb the interior columns
    move along x."""
    nodes = []
    h = width / nx
    for j in range(ny + 1):
        for i in range(nx + 1):
            x = x0 + i * h
            if perturb and 0 < i < nx:
                x += 0.3 * h * math.sin(7.0 * i)
            yb, yt = y_bottom(x - x0), y_top(x - x0)
            nodes.append((x, yb + (yt - yb) * j / ny))
    return nodes


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("output")
    parser.add_argument("--lower", default="4,2")
    parser.add_argument("--upper", default="8,4")
    parser.add_argument("--width", type=float, default=1.0)
    parser.add_argument("--height", type=float, default=0.5)
    parser.add_argument("--perturb", choices=["lower", "upper", "none"], default="none")
    parser.add_argument("--bump", type=float, default=0.0)
    parser.add_argument("--shift", type=float, default=0.0)
    parser.add_argument("--merge", action="store_true")
    parser.add_argument("--split-lower", type=float, default=None)
    parser.add_argument("--lift", type=float, default=0.0)
    parser.add_argument("--rotate", type=float, default=0.0)
    parser.add_argument("--centre", action="store_true")
    parser.add_argument("--upper-width", type=float, default=None)
    args = parser.parse_args()
    W, H = args.width, args.height
    interface = lambda x: H + args.bump * math.sin(math.pi * x / W)
    lx, ly = (int(v) for v in args.lower.split(","))
    ux, uy = (int(v) for v in args.upper.split(","))
    lower = block(lx, ly, W, 0.0, lambda x: 0.0, interface, args.perturb == "lower")
    WU = W if args.upper_width is None else args.upper_width
    upper = block(ux, uy, WU, args.shift, lambda x: interface(x) + args.lift,
                  lambda x: 2 * H + args.lift, args.perturb == "upper")

    elements = []  # (type, physical, nodes) with 1-based node numbers

    if args.merge and (lx != ux or args.perturb != "none" or args.shift != 0 or WU != W):
        parser.error("--merge needs equal NX, no --perturb, --shift or --upper-width")

    def add_block(nodes, nx, ny, offset, body, bottom_id, top_id):
        def index(i, j):
            # Merged: the upper block's bottom row is the lower block's top row.
            if args.merge and offset > 0 and j == 0:
                return ly * (lx + 1) + i + 1
            return offset + j * (nx + 1) + i + 1
        for j in range(ny):
            for i in range(nx):
                elements.append((3, body, [index(i, j), index(i + 1, j), index(i + 1, j + 1),
                                           index(i, j + 1)]))
        for i in range(nx):
            if not (args.merge and bottom_id == 15):
                elements.append((1, bottom_id, [index(i, 0), index(i + 1, 0)]))
            if not (args.merge and top_id == 14):
                elements.append((1, top_id, [index(i, ny), index(i + 1, ny)]))
        for j in range(ny):
            elements.append((1, 10, [index(0, j), index(0, j + 1)]))
            elements.append((1, 11, [index(nx, j), index(nx, j + 1)]))

    add_block(lower, lx, ly, 0, 1, 12, 14)
    add_block(upper, ux, uy, len(lower), 2, 15, 13)
    if args.split_lower is not None:
        all_nodes = lower + upper
        right = lambda ids: sum(all_nodes[i - 1][0] for i in ids) / len(ids) > args.split_lower
        for n, (kind, physical, ids) in enumerate(elements):
            if kind == 3 and physical == 1 and right(ids):
                elements[n] = (kind, 3, ids)
            elif kind == 1 and physical == 14 and right(ids):
                elements[n] = (kind, 16, ids)
            elif kind == 1 and physical == 15 and right(ids):
                elements[n] = (kind, 17, ids)
    nodes = lower + upper
    if args.merge:
        # Drop the upper block's bottom row and renumber the rest.
        nodes = lower + upper[ux + 1:]
        shift = ux + 1
        elements[:] = [(kind, physical, [i - shift if i > len(lower) + shift else i
                                         for i in ids]) for kind, physical, ids in elements]
    if args.rotate:
        c, s = math.cos(math.radians(args.rotate)), math.sin(math.radians(args.rotate))
        nodes = [(W / 2 + c * (x - W / 2) - s * (y - H), H + s * (x - W / 2) + c * (y - H))
                 for x, y in nodes]
    if args.centre:
        nodes = [(x - W / 2, y) for x, y in nodes]
    with open(args.output, "w") as f:
        f.write("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n%d\n" % len(nodes))
        for n, (x, y) in enumerate(nodes):
            f.write("%d %.17g %.17g 0\n" % (n + 1, x, y))
        f.write("$EndNodes\n$Elements\n%d\n" % len(elements))
        for n, (kind, physical, ids) in enumerate(elements):
            f.write("%d %d 2 %d %d %s\n" % (n + 1, kind, physical, physical,
                                           " ".join(str(i) for i in ids)))
        f.write("$EndElements\n")


if __name__ == "__main__":
    main()
