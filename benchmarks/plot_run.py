#!/usr/bin/python3
"""Turn any run's output directory into pictures: fields and time series.

    /usr/bin/python3 benchmarks/plot_run.py OUTPUT_DIR [--output DIR] [--frames 3]

Reads what every run writes into its `Output/Directory` (doc/output.md):
`solution.pvd` with its VTU pieces (one per MPI rank), the statistics table and
`provenance.json`, and writes two pictures (by default into OUTPUT_DIR/pictures/):

  fields.png   at the first, middle and last written time (--frames): the
               temperature with the isotherms of the transition temperatures
               (read from the parameters in provenance.json), the liquid
               fraction, and the von Mises stress on the deformed shape (the
               recovered point field `von_mises`, magnified so that the largest
               displacement is 3 % of the section) -- each where the run has it
  series.png   every statistics column against time, one panel each, titled
               with the unit the table's header gives; columns that do not
               change (to 1e-9, relative) are listed in the caption instead

The time axis is in s, min, h, d, yr, kyr or Myr, whichever makes the end time
a number between 1 and 1000 (`--time-unit none` keeps the scene's own unit, for
dimensionless scenes); lengths in m, or km or mm where that reads better.
doc/make_pictures.py uses the same readers and field picture for the
application scenes. Needs Debian's python3-matplotlib and python3-meshio
(`./setup.sh pictures` installs them); run with /usr/bin/python3.
"""
import argparse
import json
import math
import os
import re
import sys
import xml.etree.ElementTree as ET

try:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.tri as mtri
    import meshio
    import numpy as np
except ImportError as e:
    sys.exit("plot_run.py: %s (install python3-matplotlib python3-meshio, "
             "e.g. ./setup.sh pictures, and run with /usr/bin/python3)" % e)

YEAR = 3.15576e7
TIME_UNITS = [("s", 1.0), ("min", 60.0), ("h", 3600.0), ("d", 86400.0), ("yr", YEAR),
              ("kyr", 1e3 * YEAR), ("Myr", 1e6 * YEAR)]


# --- readers ----------------------------------------------------------------------

def read_pvd(path):
    """The (time, file) records of a PVD index."""
    return [(float(ds.get("timestep")), ds.get("file"))
            for ds in ET.parse(path).getroot().iter("DataSet")]


def read_pieces(directory, pvtu):
    """Points, quadrilaterals and point data of one output step, its pieces (one
    per MPI rank) stacked."""
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


def read_statistics(path):
    """The statistics table: column names, {name: (unit, meaning)} from the
    header's comment lines, and the rows as floats."""
    units, names, rows = {}, None, []
    for line in open(path):
        if line.startswith("#"):
            m = re.match(r"#\s+(\S+)\s+\[([^\]]*)\]\s*(.*)", line)
            if m:
                units[m.group(1)] = (m.group(2), m.group(3).strip())
            continue
        words = line.split()
        if not words:
            continue
        if names is None:
            names = words
        else:
            rows.append([float(w) for w in words])
    if names is None:
        sys.exit("plot_run.py: %s has no line of column names" % path)
    return names, units, np.array(rows).reshape(-1, len(names))


def read_provenance(directory):
    path = os.path.join(directory, "provenance.json")
    try:
        return json.load(open(path))
    except (OSError, ValueError):
        return {}


def transition_temperatures(parameters):
    """Every 'Transition temperatures' entry of the parameter text (all bodies)."""
    levels = set()
    for m in re.finditer(r"^\s*set\s+Transition temperatures\s*=\s*([^#\n]*)", parameters or "",
                         re.M):
        for word in m.group(1).split(","):
            try:
                levels.add(float(word))
            except ValueError:
                pass
    return sorted(levels)


def parameter(parameters, name):
    m = re.search(r"^\s*set\s+%s\s*=\s*([^#\n]*)" % re.escape(name), parameters or "", re.M)
    return m.group(1).strip() if m else None


# --- scales -------------------------------------------------------------------------

def time_unit(t_end, choice="auto"):
    if choice == "none":
        return "", 1.0
    if choice != "auto":
        return choice, dict(TIME_UNITS)[choice]
    best = TIME_UNITS[0]
    for name, scale in TIME_UNITS:
        if t_end / scale >= 1.0:
            best = (name, scale)
    return best


def length_unit(size):
    if size >= 5e3:
        return "km", 1e3
    if size <= 5e-2:
        return "mm", 1e-3
    return "m", 1.0


def triangulation(points, quads, shift=None):
    xy = points if shift is None else points + shift
    # VTK quads run counter-clockwise (0, 1, 2, 3).
    triangles = np.vstack([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    return mtri.Triangulation(xy[:, 0], xy[:, 1], triangles)


# --- pictures -----------------------------------------------------------------------

def fields_figure(title, frames, path, temperature_levels=(), time_scale=(None, 1.0),
                  length=None, figsize=None, temperature_unit="degC", stress_units=True):
    """Rows: the frames (time, points, quads, point data); columns: temperature
    with the transition isotherms, liquid fraction, von Mises stress on the
    deformed shape -- each where the frames have it."""
    data = frames[0][3]
    columns = [c for c in ("temperature", "liquid_fraction", "von_mises") if c in data]
    if not columns:
        sys.exit("plot_run.py: the output has none of temperature, liquid_fraction, von_mises")
    points0 = frames[0][1]
    size = max(np.ptp(points0[:, 0]), np.ptp(points0[:, 1]))
    unit_name, L = length if length else length_unit(size)
    t_name, t_scale = time_scale
    if figsize is None:
        aspect = np.ptp(points0[:, 1]) / max(np.ptp(points0[:, 0]), 1e-300)
        figsize = (5.2 * len(columns), min(3.0 + 3.2 * aspect, 5.5) * len(frames))
    fig, axes = plt.subplots(len(frames), len(columns), figsize=figsize, squeeze=False)
    magnify = 1.0
    if "von_mises" in columns and "displacement" in data:
        # One magnification for all times: the largest displacement becomes 3 %
        # of the section's size.
        umax = max(np.abs(f[3]["displacement"][:, :2]).max() for f in frames) or 1.0
        magnify = 0.03 * size / umax
    if "temperature" in columns:
        t_lo = min(f[3]["temperature"].min() for f in frames)
        t_hi = max(f[3]["temperature"].max() for f in frames)
        pad = 1e-6 * (t_hi - t_lo) + 1e-9 * (abs(t_hi) + 1)
    if "von_mises" in columns:
        # The colour scale of the stress ends at its 99th percentile: an elastic
        # corner concentrates stress in a few cells and would flatten the rest.
        vm_hi = max(np.percentile(f[3]["von_mises"], 99) for f in frames)
        vm_scale, vm_unit = ((1e6, "MPa") if vm_hi > 1e5 else (1.0, "Pa")) if stress_units \
            else (1.0, "")
        vm_hi = vm_hi / vm_scale or 1.0
    for row, (t, points, quads, d) in enumerate(frames):
        tri = triangulation(points / L, quads)
        when = "t = %.3g %s" % (t / t_scale, t_name)
        for col, field in enumerate(columns):
            ax = axes[row][col]
            if field == "temperature":
                c = ax.tricontourf(tri, d["temperature"],
                                   levels=np.linspace(t_lo - pad, t_hi + pad, 21), cmap="inferno")
                inside = [v for v in temperature_levels
                          if d["temperature"].min() < v < d["temperature"].max()]
                if inside:
                    ax.tricontour(tri, d["temperature"], levels=inside, colors="cyan",
                                  linewidths=1.0)
                fig.colorbar(c, ax=ax, shrink=0.85, label=temperature_unit)
                ax.set_title(when + ": temperature" +
                             (", transition isotherms (cyan)" if temperature_levels else ""),
                             fontsize=9)
            elif field == "liquid_fraction":
                c = ax.tricontourf(tri, np.clip(d["liquid_fraction"], 0, 1),
                                   levels=np.linspace(-1e-9, 1 + 1e-9, 11), cmap="Blues")
                fig.colorbar(c, ax=ax, shrink=0.85, label="-")
                ax.set_title(when + ": liquid fraction", fontsize=9)
            else:
                shift = d["displacement"][:, :2] * magnify / L if "displacement" in d else None
                tri_d = triangulation(points / L, quads, shift)
                c = ax.tricontourf(tri_d, np.minimum(d["von_mises"] / vm_scale, vm_hi),
                                   levels=np.linspace(0, vm_hi * (1 + 1e-9), 21), cmap="viridis")
                fig.colorbar(c, ax=ax, shrink=0.85, label=vm_unit)
                ax.set_title(when + ": von Mises stress, shape deformed x %.3g" % magnify,
                             fontsize=9)
            ax.set_aspect("equal")
            ax.set_xlabel("x (%s)" % unit_name if unit_name else "x", fontsize=8)
            ax.tick_params(labelsize=7)
    fig.suptitle(title, fontsize=12)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def series_figure(title, statistics, path, time_scale):
    names, units, rows = statistics
    t_name, t_scale = time_scale
    t = rows[:, names.index("time")] / t_scale
    shown, constant = [], []
    for k, name in enumerate(names):
        if name in ("step", "time"):
            continue
        # Constant to round-off (a contact force that equilibrium fixes) is
        # constant: its panel would plot the last digits.
        y = rows[:, k]
        (shown if np.ptp(y) > 1e-9 * np.abs(y).max() else constant).append(k)
    n = max(len(shown), 1)
    ncols = min(4, n)
    nrows = (n + ncols - 1) // ncols
    fig, axes = plt.subplots(nrows, ncols, figsize=(3.9 * ncols, 2.9 * nrows + 0.6),
                             squeeze=False)
    for panel, k in enumerate(shown):
        ax = axes[panel // ncols][panel % ncols]
        name = names[k]
        unit, meaning = units.get(name, ("", ""))
        y = rows[:, k]
        if name == "energy_residual" and (y[1:] > 0).any():
            ax.semilogy(t[1:], np.maximum(y[1:], 1e-18), "o-", ms=2.5)
        else:
            ax.plot(t, y, "o-", ms=2.5)
        ax.set_title("%s [%s]" % (name, unit) if unit else name, fontsize=9)
        ax.set_xlabel("time" + (" (%s)" % t_name if t_name else ""), fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(alpha=0.3)
    for panel in range(len(shown), nrows * ncols):
        axes[panel // ncols][panel % ncols].axis("off")
    caption = ", ".join("%s = %.7g" % (names[k], rows[-1, k]) for k in constant)
    fig.suptitle(title + ": statistics" + ("\nconstant: " + caption if caption else ""),
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("directory", help="a run's Output/Directory")
    parser.add_argument("--output", help="where to write the pictures (OUTPUT_DIR/pictures)")
    parser.add_argument("--frames", type=int, default=3,
                        help="output times in fields.png, first to last (3)")
    parser.add_argument("--time-unit", default="auto",
                        choices=["auto", "none"] + [u for u, _ in TIME_UNITS])
    parser.add_argument("--title", help="picture titles (the scene file's name)")
    args = parser.parse_args()
    directory = args.directory
    provenance = read_provenance(directory)
    parameters = provenance.get("parameters", "")
    title = args.title or os.path.basename(
        (provenance.get("parameter_files") or [directory.rstrip("/")])[0])
    output = args.output or os.path.join(directory, "pictures")
    os.makedirs(output, exist_ok=True)

    statistics_name = parameter(parameters, "Statistics file") or "statistics.txt"
    statistics_path = os.path.join(directory, statistics_name)
    statistics = read_statistics(statistics_path) if os.path.exists(statistics_path) else None
    pvd = os.path.join(directory, "solution.pvd")
    records = read_pvd(pvd) if os.path.exists(pvd) else []
    if not records and statistics is None:
        sys.exit("plot_run.py: %s holds neither solution.pvd nor a statistics table" % directory)
    t_end = records[-1][0] if records else statistics[2][-1, statistics[0].index("time")]
    # A dimensionless scene (Coupling/Temperature scale = dimensionless) gets no
    # units: no s/h/yr on the time axis, no m, no Pa.
    dimensionless = (parameter(parameters, "Temperature scale") or "").lower() == "dimensionless"
    scale = time_unit(t_end, "none" if dimensionless and args.time_unit == "auto" else
                      args.time_unit)
    written = []
    if records:
        k = max(1, min(args.frames, len(records)))
        chosen = [records[round(i * (len(records) - 1) / max(k - 1, 1))] for i in range(k)]
        frames = [(t,) + read_pieces(directory, f) for t, f in chosen]
        # The unit the scene says its temperatures are in (Coupling/Temperature
        # scale); none for 'dimensionless' or 'unspecified'.
        scale_name = (parameter(parameters, "Temperature scale") or "").lower()
        fields_figure(title, frames, os.path.join(output, "fields.png"),
                      transition_temperatures(parameters), scale,
                      length=("", 1.0) if dimensionless else None,
                      temperature_unit={"kelvin": "K", "celsius": "degC"}.get(scale_name, ""),
                      stress_units=not dimensionless)
        written.append("fields.png")
    if statistics is not None:
        series_figure(title, statistics, os.path.join(output, "series.png"), scale)
        written.append("series.png")
    print("wrote %s" % ", ".join(os.path.join(output, w) for w in written))


if __name__ == "__main__":
    main()
