"""Plot and print the speed-accuracy knobs of bench/knobs.sh.

    /usr/bin/python3 bench/plot_knobs.py dynamics_knobs.csv thickness.csv knobs.png

Left: the hang scene, ms per frame against the largest distance of any vertex from the
reference motion over the run, one point per knob setting. Right: the collision thickness
against ms per frame and the worst frame's edge strain, one line per stress scene. Also prints
both tables as bench/results/knobs.md shows them."""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def main():
    knobs, thick, png = sys.argv[1], sys.argv[2], sys.argv[3]
    k = rows(knobs)
    t = rows(thick)
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 4.8))

    marks = {"integrator": "o", "substeps": "s", "newton": "^"}
    print("| knob | setting | ms per frame | CG iterations per frame | solves per frame | strain end / worst | free corners' height error at the end | distance from the reference, max over frames / at the end | energy lost |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in k:
        ms = float(r["ms_per_frame_cpu"])
        dev = float(r["deviation_max_m"])
        print("| %s | %s | %s | %.1f | %.2f | %.1f%% / %.1f%% | %.1f mm | %.1f / %.1f cm | %.1f mJ |" % (
            r["knob"], r["value"], "%.2f" % ms if r["knob"] != "reference" else "(untimed)",
            float(r["cg_per_frame"]), float(r["newton_per_frame"]), 100 * float(r["strain_end"]),
            100 * float(r["strain_worst"]), 1e3 * float(r["corner_y_error_end"]), 100 * dev,
            100 * float(r["deviation_end_m"]), 1e3 * float(r["energy_lost_j"])))
        if r["knob"] == "reference":
            continue
        a.loglog(ms, dev, marks.get(r["knob"], "x"), color="C%d" % list(marks).index(r["knob"]))
        if r["knob"] == "newton" and r["value"] == "1":
            continue  # the same figures as the linearized step here (its line search took full steps): labelled with it
        label = "%s %s" % (r["knob"], r["value"]) + (" (= newton 1)" if r["value"] == "lbe" else "")
        a.annotate(label, (ms, dev), fontsize=7, xytext=(3, 3), textcoords="offset points")
    for i, name in enumerate(marks):
        a.plot([], [], marks[name], color="C%d" % i, label=name)
    a.legend(fontsize=8)
    a.set_xlabel("ms per frame (CPU)")
    a.set_ylabel("largest distance from the reference (m)")
    n = k[0]["n"] if k else "?"
    a.set_title("hang %s, 0.5 s: integrator, substeps, Newton cap" % n)
    a.grid(True, which="both", alpha=0.3)

    print()
    print("| thickness | scene | n | ms per frame | impacts per frame | obstacle contacts per frame | intersecting pairs | penetration | min distance to an obstacle | strain end / worst | failed steps | status |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    scenes = []
    for r in t:
        key = (r["scene"], r["n"])
        if key not in scenes:
            scenes.append(key)
        print("| %.2f mm | %s | %s | %.1f | %.1f | %.1f | %s | %s | %.2f mm | %.1f%% / %.1f%% | %d | %s |" % (
            1e3 * float(r["thickness_m"]), r["scene"], r["n"], float(r["ms_frame_median"]), float(r["impacts_per_frame"]),
            float(r["obstacle_contacts_per_frame"]), r["pairs_max"], r["penetration_m"],
            1e3 * float(r["min_obstacle_distance_m"]) if r["min_obstacle_distance_m"] not in ("inf", "") else float("inf"),
            100 * float(r["strain_end"]), 100 * float(r["strain_worst"]),
            int(r["unresolved_steps"]) + int(r["other_failed_steps"]), r["status"]))
    b2 = b.twinx()
    for i, (scene, n) in enumerate(scenes):
        sel = [r for r in t if (r["scene"], r["n"]) == (scene, n)]
        th = [1e3 * float(r["thickness_m"]) for r in sel]
        b.semilogx(th, [float(r["ms_frame_median"]) for r in sel], "o-", color="C%d" % i, label="%s %s: ms per frame" % (scene, n))
        b2.semilogx(th, [100 * float(r["strain_worst"]) for r in sel], "s--", color="C%d" % i, label="%s %s: worst strain" % (scene, n))
    b.set_xlabel("collision thickness (mm)")
    b.set_ylabel("ms per frame (CPU), solid")
    b2.set_ylabel("max edge strain in the worst frame (%), dashed")
    b.set_title("collision thickness (0 intersecting pairs and 0 penetration required)")
    lines = b.get_legend_handles_labels()[0] + b2.get_legend_handles_labels()[0]
    labels = b.get_legend_handles_labels()[1] + b2.get_legend_handles_labels()[1]
    b.legend(lines, labels, fontsize=7, loc="upper left")
    b.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(png, dpi=110)


if __name__ == "__main__":
    main()
