"""Plot bench/results/target.csv (bench/target.sh): per scene, cloth.h's ms per frame on 1 and
2 threads as a ratio to Bullet's of the same round (bars: the median over the rounds; dots: each
round) against the target ratio (dashed), and the ms per frame themselves.
Usage: plot_target.py target.csv target.png"""
import csv
import statistics
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt


def main():
    rows = list(csv.DictReader(open(sys.argv[1])))
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    fig, ax = plt.subplots(1, 2, figsize=(12, 5))
    # (engine, threads, settings prefix or "" for the first settings of the kind, label)
    kinds = [("bullet", "1", "", "Bullet 3.24 (1 thread)"), ("cloth.h", "1", "CG 1e-2", "cloth.h, 1 thread"),
             ("cloth.h", "2", "", "cloth.h, 2 threads"), ("cloth.h", "1", "CG 3e-2", "cloth.h, 1 thread, CG 3e-2")]
    kinds = [k for k in kinds if not k[2] or any(r["settings"].startswith(k[2]) for r in rows)]
    width = 0.8 / len(kinds)
    for k, (engine, threads, prefix, label) in enumerate(kinds):
        for panel, key in enumerate(("ratio", "ms_per_frame")):
            xs, meds = [], []
            for i, s in enumerate(scenes):
                vals = [float(r[key]) for r in rows
                        if r["scene"] == s and r["engine"] == engine and r["threads"] == threads and
                        r["settings"].startswith(prefix)]
                if not vals:
                    continue
                x = i + k * width
                xs.append(x)
                meds.append(statistics.median(vals))
                ax[panel].plot([x] * len(vals), vals, "k.", markersize=5)
            ax[panel].bar(xs, meds, width, label=label if panel == 0 else None)
    for i, s in enumerate(scenes):
        target = [float(r["target"]) for r in rows if r["scene"] == s][0]
        ax[0].plot([i - width / 2, i + 0.8 - width / 2], [target, target], "r--")
        ax[0].text(i + 0.8 - width / 2, target, " target %.2fx" % target, color="r", fontsize=8, va="center")
    for panel, ylabel in enumerate(("ms per frame / Bullet's (same round)", "ms per frame (median of the round's runs)")):
        ax[panel].set_xticks([i + 0.4 - width / 2 for i in range(len(scenes))])
        ax[panel].set_xticklabels(["%s 64" % s for s in scenes])
        ax[panel].set_ylabel(ylabel)
    ax[0].legend(fontsize=8)
    first = rows[0]
    fig.suptitle("speed targets, %d rounds, %s (%s)" % (len({r["round"] for r in rows}), first["machine"], first["cpu"]),
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=100)


if __name__ == "__main__":
    main()
