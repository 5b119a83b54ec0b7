#!/usr/bin/python3
"""Render the application scenes to the pictures of doc/scenes.md.

Runs each scene (prm/subduction.prm, prm/casting.prm) with the given binary in a
temporary directory, reads its VTU output (meshio) and statistics table, and
writes to doc/figures/scenes/:

  <scene>_fields.png     temperature with the phase fronts, liquid fraction and
                         von Mises stress (the recovered point field
                         'von_mises', doc/output.md) on the deformed shape
                         (magnified) at three times
  <scene>_interface.png  contact pressure along the contact interface at those times
  <scene>_series.png     active contact nodes, melt area, largest contact pressure
                         and energy residual against time

    /usr/bin/python3 doc/make_pictures.py [--binary build/contact-stefan]
    cmake --build build --target pictures       (the same)

Needs Debian's python3-matplotlib and python3-meshio (`./setup.sh pictures`
installs them); run with /usr/bin/python3, which sees Debian's packages.
"""
import argparse
import math
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.tri as mtri
    import meshio
    import numpy as np
except ImportError as e:
    sys.exit("make_pictures.py: %s (install python3-matplotlib python3-meshio, "
             "e.g. ./setup.sh pictures, and run with /usr/bin/python3)" % e)

YEAR = 3.15576e7


def subduction_interface(points):
    # Distance to the plane interface from (100 km, 0) dipping 30 degrees; the
    # coordinate along it is the depth in km.
    x, y = points[:, 0], points[:, 1]
    fault_x = 100e3 + (-y) / math.tan(math.radians(30))
    on = np.abs(x - fault_x) < 1.0
    return on, -y / 1e3, "depth along the interface (km)"


def casting_interface(points):
    r = np.hypot(points[:, 0], points[:, 1])
    on = np.abs(r - 0.05) < 1e-9
    return on, np.degrees(np.arctan2(points[:, 1], points[:, 0])), \
        "position on the casting surface (degrees from y = 0)"


SCENES = {
    "subduction": dict(prm="prm/subduction.prm", out="output-subduction",
                       time_scale=1e6 * YEAR, time_unit="Myr", length=1e3, length_unit="km",
                       interface=subduction_interface, temperature_levels=[1150, 1300],
                       figsize=(18, 7)),
    "casting": dict(prm="prm/casting.prm", out="output-casting",
                    time_scale=1.0, time_unit="s", length=1e-3, length_unit="mm",
                    interface=casting_interface, temperature_levels=[660],
                    figsize=(13, 11)),
}


def read_pvd(path):
    import xml.etree.ElementTree as ET
    records = []
    for ds in ET.parse(path).getroot().iter("DataSet"):
        records.append((float(ds.get("timestep")), ds.get("file")))
    return records


def read_pieces(directory, pvtu):
    # The .pvtu names its pieces; read and stack them (one per MPI rank).
    import xml.etree.ElementTree as ET
    pieces = [p.get("Source") for p in ET.parse(os.path.join(directory, pvtu)).getroot()
              .iter("Piece")]
    points, data, quads, offset = [], {}, [], 0
    for piece in pieces:
        m = meshio.read(os.path.join(directory, piece))
        points.append(m.points[:, :2])
        quads.append(m.cells_dict["quad"] + offset)
        offset += len(m.points)
        for k, v in m.point_data.items():
            data.setdefault(k, []).append(v)
    return np.vstack(points), np.vstack(quads), {k: np.concatenate(v) for k, v in data.items()}


def triangulation(points, quads, shift=None):
    xy = points if shift is None else points + shift
    # VTK quads run counter-clockwise (0, 1, 2, 3).
    triangles = np.vstack([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    return mtri.Triangulation(xy[:, 0], xy[:, 1], triangles)


def fields_figure(name, scene, frames, path):
    # Rows: the three times; columns: temperature with the transition isotherms,
    # liquid fraction, von Mises stress on the deformed shape.
    L = scene["length"]
    fig, axes = plt.subplots(len(frames), 3, figsize=scene["figsize"], squeeze=False)
    # One magnification for all times: the largest displacement becomes 3 % of
    # the section's size.
    size = max(np.ptp(frames[0][1][:, 0]), np.ptp(frames[0][1][:, 1]))
    umax = max(np.abs(f[3]["displacement"][:, :2]).max() for f in frames) or 1.0
    magnify = 0.03 * size / umax
    t_lo = min(f[3]["temperature"].min() for f in frames)
    t_hi = max(f[3]["temperature"].max() for f in frames)
    pad = 1e-6 * (t_hi - t_lo + 1)
    # The colour scale of the stress ends at its 99th percentile: an elastic
    # corner (the interface's end, a roller corner) concentrates stress in a
    # few cells and would flatten the rest.
    vm_hi = max(np.percentile(f[3]["von_mises"], 99) for f in frames) / 1e6 or 1.0
    for row, (t, points, quads, d) in enumerate(frames):
        tri = triangulation(points / L, quads)
        when = "t = %.3g %s" % (t / scene["time_scale"], scene["time_unit"])
        ax = axes[row][0]
        c = ax.tricontourf(tri, d["temperature"], levels=np.linspace(t_lo - pad, t_hi + pad, 21),
                           cmap="inferno")
        ax.tricontour(tri, d["temperature"], levels=scene["temperature_levels"],
                      colors="cyan", linewidths=1.0)
        fig.colorbar(c, ax=ax, shrink=0.85, label="degC")
        ax.set_title(when + ": temperature, transition isotherms (cyan)", fontsize=9)
        ax = axes[row][1]
        c = ax.tricontourf(tri, np.clip(d["liquid_fraction"], 0, 1),
                           levels=np.linspace(-1e-9, 1 + 1e-9, 11), cmap="Blues")
        fig.colorbar(c, ax=ax, shrink=0.85, label="-")
        ax.set_title(when + ": liquid fraction", fontsize=9)
        ax = axes[row][2]
        tri_d = triangulation(points / L, quads, d["displacement"][:, :2] * magnify / L)
        c = ax.tricontourf(tri_d, np.minimum(d["von_mises"] / 1e6, vm_hi),
                           levels=np.linspace(0, vm_hi * (1 + 1e-9), 21), cmap="viridis")
        fig.colorbar(c, ax=ax, shrink=0.85, label="MPa")
        ax.set_title(when + ": von Mises stress, shape deformed x %.3g" % magnify, fontsize=9)
        for col in range(3):
            axes[row][col].set_aspect("equal")
            axes[row][col].set_xlabel("x (%s)" % scene["length_unit"], fontsize=8)
            axes[row][col].tick_params(labelsize=7)
    fig.suptitle(name, fontsize=12)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def interface_figure(name, scene, frames, path):
    fig, ax = plt.subplots(figsize=(7, 4))
    for t, points, quads, d in frames:
        on, s, label = scene["interface"](points)
        # Interface vertices appear once per adjacent cell; the pressure sits on
        # the cells of the lower body id: take the largest value per position.
        keys = np.round(s[on], 6)
        pressure = {}
        for k, p in zip(keys, d["contact_pressure"][on]):
            pressure[k] = max(pressure.get(k, 0.0), p)
        ks = sorted(pressure)
        ax.plot(ks, [pressure[k] / 1e6 for k in ks], "o-", ms=3,
                label="t = %.3g %s" % (t / scene["time_scale"], scene["time_unit"]))
    ax.set_xlabel(label)
    ax.set_ylabel("contact pressure (MPa)")
    ax.set_title("%s: contact pressure along the interface" % name)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def series_figure(name, scene, statistics, path):
    rows = [line.split() for line in open(statistics)]
    header, rows = rows[0], [r for r in rows[1:] if r]
    col = {h: i for i, h in enumerate(header)}
    t = np.array([float(r[col["time"]]) for r in rows]) / scene["time_scale"]
    series = [("active_nodes", "active contact nodes", 1.0),
              ("liquid_area", "melt area (m^2 per m)", 1.0),
              ("max_pressure", "largest contact pressure (MPa)", 1e-6),
              ("energy_residual", "energy residual (relative)", 1.0)]
    fig, axes = plt.subplots(1, 4, figsize=(15, 3.4))
    for ax, (key, label, factor) in zip(axes, series):
        y = np.array([float(r[col[key]]) for r in rows]) * factor
        if key == "energy_residual":
            ax.semilogy(t[1:], np.maximum(y[1:], 1e-18), "o-", ms=3)
        else:
            ax.plot(t, y, "o-", ms=3)
        ax.set_xlabel("time (%s)" % scene["time_unit"])
        ax.set_title(label, fontsize=9)
        ax.grid(alpha=0.3)
    fig.suptitle(name + ": statistics", fontsize=11)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--binary", default=os.path.join(ROOT, "build", "contact-stefan"))
    parser.add_argument("--np", type=int, default=1)
    parser.add_argument("--scenes", nargs="*", default=list(SCENES))
    parser.add_argument("--output", default=os.path.join(HERE, "figures", "scenes"))
    args = parser.parse_args()
    os.makedirs(args.output, exist_ok=True)
    work = tempfile.mkdtemp(prefix="scene-pictures-")
    for name in args.scenes:
        scene = SCENES[name]
        command = [os.path.abspath(args.binary), os.path.join(ROOT, scene["prm"])]
        if args.np > 1:
            command = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np",
                       str(args.np)] + command
        run = subprocess.run(command, cwd=work, capture_output=True, text=True)
        if run.returncode != 0:
            sys.exit("%s failed: %s" % (name, (run.stderr or run.stdout).strip()[-300:]))
        directory = os.path.join(work, scene["out"])
        records = read_pvd(os.path.join(directory, "solution.pvd"))
        chosen = [records[0], records[len(records) // 2], records[-1]]
        frames = [(t,) + read_pieces(directory, f) for t, f in chosen]
        fields_figure(name, scene, frames, os.path.join(args.output, name + "_fields.png"))
        interface_figure(name, scene, frames, os.path.join(args.output, name + "_interface.png"))
        series_figure(name, scene, os.path.join(directory, "statistics.txt"),
                      os.path.join(args.output, name + "_series.png"))
        print("wrote %s/%s_{fields,interface,series}.png" % (args.output, name))


if __name__ == "__main__":
    main()
