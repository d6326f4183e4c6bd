#!/usr/bin/python3
"""Plot bench/results/io_load.csv (written by bench/run.sh) as a bar chart.

    /usr/bin/python3 bench/plot_io.py [bench/results/io_load.csv] [bench/results/io_load.png]

One group of bars per file format, one bar per reader, median wall-clock load time on a log
scale; each bar other than cloth.h's is annotated with its time over cloth.h's, in wall clock
and in process CPU time.
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

FORMAT_LABELS = {"obj": "OBJ (text)", "ply_binary_le": "PLY binary little endian"}


def main(argv):
    src = argv[1] if len(argv) > 1 else "bench/results/io_load.csv"
    dst = argv[2] if len(argv) > 2 else "bench/results/io_load.png"
    with open(src, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        raise SystemExit("plot_io: %s has no rows" % src)
    formats = list(dict.fromkeys(r["format"] for r in rows))
    readers = list(dict.fromkeys(r["reader"] for r in rows))
    colors = ["#2a6f97", "#e07a5f", "#81b29a", "#f2cc8f"]
    width = 0.8 / len(readers)
    fig, ax = plt.subplots(figsize=(7.5, 4.8), dpi=120)
    for k, reader in enumerate(readers):
        for i, fmt in enumerate(formats):
            match = [r for r in rows if r["format"] == fmt and r["reader"] == reader]
            if not match:
                continue
            r = match[0]
            t = float(r["median_s"])
            x = i + (k - (len(readers) - 1) / 2) * width
            ax.bar(x, t, width * 0.92, color=colors[k % len(colors)], label=reader if i == 0 else None)
            label = "%.3g s" % t
            if not reader.startswith("cloth.h"):
                label += "\n%.2f x cloth.h's time" % float(r["ratio_to_cloth_h"])
                if r.get("cpu_ratio_to_cloth_h"):
                    label += "\n(CPU time: %.2f x)" % float(r["cpu_ratio_to_cloth_h"])
            ax.annotate(label, (x, t), textcoords="offset points", xytext=(0, 3), ha="center", va="bottom", fontsize=8)
    ax.set_yscale("log")
    lo = min(float(r["median_s"]) for r in rows)
    hi = max(float(r["median_s"]) for r in rows)
    ax.set_ylim(lo / 3, hi * 10)
    ax.set_xticks(range(len(formats)))
    ax.set_xticklabels([FORMAT_LABELS.get(f, f) for f in formats])
    ax.set_ylabel("median load time, s (log scale)")
    runs = ", ".join("%s: %s runs" % (r, next(x["runs"] for x in rows if x["reader"] == r)) for r in readers)
    load = "; load average %s" % rows[0]["loadavg"] if rows[0].get("loadavg") else ""
    ax.set_title("Loading a %s-triangle mesh with uv (file read included)\n%s, %s; %s%s"
                 % ("{:,}".format(int(rows[0]["triangles"])), rows[0]["machine"], rows[0]["cpu"], runs, load), fontsize=9)
    ax.legend(loc="upper left", fontsize=8)
    ax.grid(axis="y", which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(dst)
    print("plot_io: wrote %s" % dst)


if __name__ == "__main__":
    main(sys.argv)
