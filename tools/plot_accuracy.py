#!/usr/bin/python3
"""Log-log plot of error against run time from `drape accuracy` output.

usage: plot_accuracy.py accuracy.csv reference.csv out.png [--title TEXT]

One panel per sample time. Each line is one solver at one stretch-pass count, its points the
substep counts (labelled); the dashed lines are how far the reference is from its own check
(16x vs 32x substeps), the floor below which an error cannot be resolved. Unstable and skipped
configurations have no error and are listed under the panels instead.
Runs under /usr/bin/python3 (Debian's python3-matplotlib).
"""
import argparse
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLOURS = {"cpu-xprev": "tab:red", "cpu": "tab:blue", "cpu64": "tab:green", "gpu": "tab:purple",
           "cpu+xpbd": "tab:cyan", "cpu64+xpbd": "tab:olive", "gpu+xpbd": "tab:pink",
           "cpu+vbd": "tab:orange", "cpu64+vbd": "tab:brown", "gpu+vbd": "tab:gray"}
LINESTYLES = {"xpbd": "--", "vbd": ":"}
MARKERS = {0: "x", 1: "o", 2: "s", 4: "^"}


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("accuracy_csv")
    parser.add_argument("reference_csv")
    parser.add_argument("out_png")
    parser.add_argument("--title", default="")
    args = parser.parse_args()

    rows = read_rows(args.accuracy_csv)
    refs = read_rows(args.reference_csv)
    times = sorted({float(r["t"]) for r in rows if r["status"] == "ok"})
    if not times:
        # Still a figure, so that a run where everything blew up says so where the plot is expected.
        print("plot_accuracy.py: %s has no stable configuration; the figure says so" % args.accuracy_csv,
              file=sys.stderr)
        times = sorted({float(r["t"]) for r in refs if r["status"] == "ok"}) or [0.0]

    fig, axes = plt.subplots(1, len(times), figsize=(5.2 * len(times) + 1.8, 4.8), squeeze=False)
    for ax, t in zip(axes[0], times):
        lines = defaultdict(list)
        for r in rows:
            if r["status"] == "ok" and float(r["t"]) == t:
                key = (r["solver"], int(r["stretch_passes"]))
                lines[key].append((float(r["ms_per_sim_s"]), float(r["rms_error_over_size"]), int(r["steps_per_frame"])))
        for (solver, passes), points in sorted(lines.items()):
            points.sort(key=lambda p: p[2])
            xs = [p[0] for p in points]
            # An exact match (error 0) cannot sit on a log axis; draw it at the axis floor instead.
            ys = [max(p[1], 1e-12) for p in points]
            # XPBD runs ("<solver>+xpbd") dashed and VBD's dotted beside Verlet's solid lines.
            integrator = solver.rpartition("+")[2] if "+" in solver else "verlet"
            ax.plot(xs, ys, color=COLOURS.get(solver, "black"), marker=MARKERS.get(passes, "d"), linewidth=1,
                    linestyle=LINESTYLES.get(integrator, "-"), markersize=4, label="%s, %d pass%s" % (solver, passes, "" if passes == 1 else "es"))
            for x, y, p in zip(xs, ys, points):
                ax.annotate(str(p[2]), (x, y), textcoords="offset points", xytext=(3, 3), fontsize=6,
                            color=COLOURS.get(solver, "black"))
        for r in refs:
            if r["status"] == "ok" and float(r["t"]) == t:
                ax.axhline(max(float(r["rms_difference_over_size"]), 1e-12), linestyle="--", linewidth=0.8,
                           color="grey")
                ax.annotate("reference vs check, %s pass%s" % (r["stretch_passes"],
                                                               "" if r["stretch_passes"] == "1" else "es"),
                            (0.01, max(float(r["rms_difference_over_size"]), 1e-12)), xycoords=("axes fraction", "data"),
                            fontsize=6, color="grey", va="bottom")
        if not lines:
            ax.text(0.5, 0.5, "no stable configuration", transform=ax.transAxes, ha="center")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("wall ms per simulated second")
        ax.set_ylabel("RMS position error / cloth size")
        ax.set_title("t = %g s" % t)
        ax.grid(True, which="both", linewidth=0.3)
    if any(ax.get_legend_handles_labels()[0] for ax in axes[0]):
        axes[0][-1].legend(fontsize=6, loc="upper left", bbox_to_anchor=(1.02, 1.0))

    missing = sorted({"%s %s substeps %s passes: %s" % (r["solver"], r["steps_per_frame"], r["stretch_passes"],
                                                         r["status"] + (" at frame " + r["unstable_frame"]
                                                                        if r["unstable_frame"] else ""))
                      for r in rows if r["status"] != "ok"})
    title = args.title + (" — " if args.title else "") + "error against run time"
    if missing:
        shown = missing[:12] + (["... and %d more" % (len(missing) - 12)] if len(missing) > 12 else [])
        fig.text(0.01, 0.01, "not plotted: " + "; ".join(shown), fontsize=6, wrap=True)
    fig.suptitle(title)
    fig.tight_layout(rect=(0, 0.06 if missing else 0, 1, 0.95))
    fig.savefig(args.out_png, dpi=130)


if __name__ == "__main__":
    main()
