#!/usr/bin/python3
"""Render the application scenes to the pictures of doc/scenes.md.

Runs each scene (prm/subduction.prm, prm/casting.prm, prm/casting_mortar.prm)
with the given binary in a temporary directory, reads its VTU output (meshio)
and statistics table, and writes to doc/figures/scenes/:

  <scene>_fields.png     temperature with the phase fronts, liquid fraction and
                         von Mises stress (the recovered point field
                         'von_mises', doc/output.md) on the deformed shape
                         (magnified) at three times
  <scene>_interface.png  contact pressure along the contact interface at those times
  <scene>_series.png     active contact nodes, melt area, largest contact pressure
                         and energy residual against time
  casting_birth.png, crustal_intrusion_stress_birth.png
                         the residual stress of the frozen casting (t = 200 s)
                         and of the refrozen crust (prm/crustal_intrusion_stress.prm,
                         400 kyr) with and without 'Stress free at solidification'
                         (doc/solidification.md): sigma_zz and von Mises

    /usr/bin/python3 doc/make_pictures.py [--binary build/contact-stefan]
    cmake --build build --target pictures       (the same)

Needs Debian's python3-matplotlib and python3-meshio (`./setup.sh pictures`
installs them); run with /usr/bin/python3, which sees Debian's packages.
"""
import argparse
import os
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

# The readers and the field picture are those of the generic plotting script
# (benchmarks/plot_run.py, which turns any run into pictures); this script adds
# the scenes' interface profiles and their chosen statistics.
sys.path.insert(0, os.path.join(ROOT, "benchmarks"))
from plot_run import fields_figure, np, plt, read_pieces, read_pvd, triangulation  # noqa: E402
from ladder import set_path  # noqa: E402

YEAR = 3.15576e7


def subduction_interface(points, data):
    # The interface bends (Geometry/Interface dip at base): its vertices are
    # those that cells of both bodies share (every cell writes its own copies
    # of its vertices). The coordinate along it is the depth in km.
    keys = [tuple(k) for k in np.round(points, 3)]
    bodies = {}
    for k, b in zip(keys, data["body_id"]):
        bodies.setdefault(k, set()).add(int(round(b)))
    on = np.array([len(bodies[k]) > 1 for k in keys])
    return on, -points[:, 1] / 1e3, "depth along the interface (km)"


def casting_interface(points, data):
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
    # The die meshed on its own, a mortar wall: the pressure sits on the
    # slave side, the die's (body 1).
    "casting_mortar": dict(prm="prm/casting_mortar.prm", out="output-casting-mortar",
                           time_scale=1.0, time_unit="s", length=1e-3, length_unit="mm",
                           interface=casting_interface, temperature_levels=[660],
                           figsize=(13, 11), pressure_body=1),
}


def interface_figure(name, scene, frames, path):
    fig, ax = plt.subplots(figsize=(7, 4))
    for t, points, quads, d in frames:
        on, s, label = scene["interface"](points, d)
        if "pressure_body" in scene:
            # (A mortar interface: the other side's vertices carry no pressure.)
            of_body = np.zeros(len(points), dtype=bool)
            of_body[quads[d["body_id"][quads[:, 0]] == scene["pressure_body"]].ravel()] = True
            on = on & of_body
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
    rows = [line.split() for line in open(statistics) if not line.startswith("#")]
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


# The two comparisons of doc/scenes.md: each scene run twice, with the seed's one
# reference and with every point born stress-free at solidification
# (doc/solidification.md), and its cell-centre stresses compared at the end.
BIRTH_COMPARISONS = {
    "casting": dict(
        prm="prm/casting.prm", bodies=[0], end=200.0, body_only=0, length=(1e3, "mm"),
        # The scene as doc/scenes.md's table measured it (before 2026-12-07):
        # the 8 x 8 mesh and the linear interference (the test scenes/casting-birth).
        settings={"Mesh refinement/Adaptive refinement interval": "0",
                  "Mesh refinement/Initial adaptive refinements": "0",
                  "Contact/Interface gap": "-3e-4 * (1 - y / 0.05)"},
        limits=((0, 52), (0, 52)), figsize=(9.5, 8.4), time="t = 200 s",
        off="one reference (pouring, 700 degC)", on="born stress-free at 660 degC",
        title="Casting: residual stress of the frozen casting (cell centres)"),
    "crustal_intrusion_stress": dict(
        prm="prm/crustal_intrusion_stress.prm", bodies=[0, 1], end=None, body_only=None,
        length=(1e-3, "km"), limits=None, figsize=(11, 6.4), time="t = 400 kyr",
        off="one reference (the initial geotherm)", on="born stress-free at solidification",
        title="Crust after the intrusion: residual stress of the refrozen crust (cell centres)"),
}


def birth_figure(binary, work, name, path):
    """Runs the comparison `name` of BIRTH_COMPARISONS; sigma_zz and von Mises
    of the cell centres at the end, one row per model."""
    c = BIRTH_COMPARISONS[name]
    text = open(os.path.join(ROOT, c["prm"])).read()
    # (Included files are named relative to the scene's directory.)
    text = text.replace("include include/", "include %s/prm/include/" % ROOT)
    if c["end"] is not None:
        text = set_path(text, "Time stepping/End time", repr(c["end"]))
    for entry, value in c.get("settings", {}).items():
        text = set_path(text, entry, value)
    text = set_path(text, "Output/VTU interval", "100000")
    text = set_path(text, "Output/Directory", "output")
    rows, summary = [], []
    for switch in ("false", "true"):
        directory = os.path.join(work, "%s-birth-%s" % (name, switch))
        os.makedirs(directory, exist_ok=True)
        scene = text
        for body in c["bodies"]:
            scene = set_path(scene, "Materials/Body %d/Phase change/Stress free at "
                             "solidification" % body, switch)
        with open(os.path.join(directory, "scene.prm"), "w") as f:
            f.write(scene)
        run = subprocess.run([binary, "scene.prm"], cwd=directory, capture_output=True, text=True)
        if run.returncode != 0:
            sys.exit("%s (birth %s) failed: %s" % (name, switch, run.stderr.strip()[-300:]))
        out = os.path.join(directory, "output")
        t, last = read_pvd(os.path.join(out, "solution.pvd"))[-1]
        points, quads, data = read_pieces(out, last)
        if c["body_only"] is not None:
            quads = quads[data["body_id"][quads[:, 0]] == c["body_only"]]
        rows.append((switch, points, quads, data))
        vm = data["cell_von_mises"][quads[:, 0]] / 1e6
        szz = data["cell_stress_zz"][quads[:, 0]] / 1e6
        summary.append((switch, vm.max(), vm.mean(), szz.min(), szz.max()))
    zz_lo = min(r[3]["cell_stress_zz"][r[2][:, 0]].min() for r in rows) / 1e6
    zz_hi = max(r[3]["cell_stress_zz"][r[2][:, 0]].max() for r in rows) / 1e6
    zz_abs = max(abs(zz_lo), abs(zz_hi))
    vm_hi = max(r[3]["cell_von_mises"][r[2][:, 0]].max() for r in rows) / 1e6
    fig, axes = plt.subplots(2, 2, figsize=c["figsize"])
    scale, unit = c["length"]
    for row, (switch, points, quads, data) in enumerate(rows):
        tri = triangulation(points * scale, quads)
        for col, (field, lo, hi, cmap) in enumerate(
                (("cell_stress_zz", -zz_abs, zz_abs, "coolwarm"),
                 ("cell_von_mises", 0, vm_hi, "viridis"))):
            ax = axes[row][col]
            # Cell data: constant on each cell's own copies of its vertices;
            # the triangulation holds each cell's first triangles, then its second.
            values = data[field][quads[:, 0]] / 1e6
            cells = ax.tripcolor(tri, facecolors=np.concatenate([values, values]),
                                 vmin=lo, vmax=hi, cmap=cmap)
            fig.colorbar(cells, ax=ax, shrink=0.85, label="MPa")
            ax.set_title("%s, %s: %s" % (c["on" if switch == "true" else "off"], c["time"],
                                         "sigma_zz" if col == 0 else "von Mises"), fontsize=9)
            ax.set_aspect("equal")
            if c["limits"]:
                ax.set_xlim(*c["limits"][0])
                ax.set_ylim(*c["limits"][1])
            ax.set_xlabel("x (%s)" % unit, fontsize=8)
            ax.tick_params(labelsize=7)
    fig.suptitle(c["title"], fontsize=12)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    for switch, vm_max, vm_mean, zz_min, zz_max in summary:
        print("%s, stress free at solidification = %s: von Mises max %.1f MPa, mean "
              "%.1f MPa; sigma_zz %.1f .. %.1f MPa" % (name, switch, vm_max, vm_mean, zz_min,
                                                       zz_max))


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
        fields_figure(name, frames, os.path.join(args.output, name + "_fields.png"),
                      scene["temperature_levels"], (scene["time_unit"], scene["time_scale"]),
                      length=(scene["length_unit"], scene["length"]), figsize=scene["figsize"])
        interface_figure(name, scene, frames, os.path.join(args.output, name + "_interface.png"))
        series_figure(name, scene, os.path.join(directory, "statistics.txt"),
                      os.path.join(args.output, name + "_series.png"))
        print("wrote %s/%s_{fields,interface,series}.png" % (args.output, name))
        if name == "casting":
            for comparison in BIRTH_COMPARISONS:
                birth_figure(os.path.abspath(args.binary), work, comparison,
                             os.path.join(args.output, comparison + "_birth.png"))
                print("wrote %s/%s_birth.png" % (args.output, comparison))


if __name__ == "__main__":
    main()
