"""Plot bench/results/stress.csv (bench/stress.sh): ms per frame per scene and n, the time
split of the largest n each scene completed, edge strain, and the contact checks as text.
Usage: plot_stress.py stress.csv stress.png"""
import csv
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt


def num(row, key):
    try:
        return float(row[key])
    except (KeyError, ValueError):
        return float("nan")


def short_status(r):
    """complete, timeout, killed, or "killed@F" for bench/stress.sh's "killed in frame F"."""
    st = r["status"]
    if st.startswith("killed in frame "):
        return "killed@" + st[len("killed in frame "):]
    return st


def main():
    rows = list(csv.DictReader(open(sys.argv[1])))
    scenes = list(dict.fromkeys(r["scene"] for r in rows))
    ns = sorted({int(r["n"]) for r in rows})
    fig, ax = plt.subplots(2, 2, figsize=(13, 9))
    width = 0.8 / max(len(ns), 1)
    for k, n in enumerate(ns):
        xs, ys, labels = [], [], []
        for i, s in enumerate(scenes):
            for r in rows:
                if r["scene"] == s and int(r["n"]) == n and r["status"] != "killed":
                    xs.append(i + k * width)
                    ys.append(num(r, "ms_frame_median"))
                    labels.append("" if r["status"] == "complete" else short_status(r) + " @" + r["frames"])
        bars = ax[0][0].bar(xs, ys, width, label="n = %d (median; dot: mean)" % n)
        means = [num(r, "ms_frame_mean") for i, s in enumerate(scenes) for r in rows
                 if r["scene"] == s and int(r["n"]) == n and r["status"] != "killed"]
        ax[0][0].plot(xs, means, "k.", markersize=6)
        for b, t in zip(bars, labels):
            if t:
                ax[0][0].text(b.get_x(), b.get_height(), t, fontsize=7, rotation=90, va="bottom")
    ax[0][0].set_xticks([i + 0.4 - width / 2 for i in range(len(scenes))])
    ax[0][0].set_xticklabels(scenes, rotation=20)
    ax[0][0].set_yscale("log")
    ax[0][0].set_ylabel("ms per frame (median CPU, stepping only)")
    ax[0][0].legend()
    ax[0][0].set_title("cost")
    # time split at the largest completed n of each scene
    parts = [("assembly_ms", "assembly"), ("solve_ms", "solve"), ("collide_ms", "collide"), ("other_ms", "other")]
    bottom = [0.0] * len(scenes)
    chosen = []
    for s in scenes:
        done = [r for r in rows if r["scene"] == s and r["status"] != "killed"]
        chosen.append(max(done, key=lambda r: int(r["n"])) if done else None)
    for key, label in parts:
        vals = [num(r, key) if r else 0.0 for r in chosen]
        ax[0][1].bar(range(len(scenes)), vals, 0.6, bottom=bottom, label=label)
        bottom = [b + v for b, v in zip(bottom, vals)]
    ax[0][1].set_xticks(range(len(scenes)))
    ax[0][1].set_xticklabels(["%s\nn=%s" % (s, r["n"] if r else "-") for s, r in zip(scenes, chosen)])
    ax[0][1].set_ylabel("ms per frame (mean over successful steps)")
    ax[0][1].legend()
    ax[0][1].set_title("time split (cloth_step_stats)")
    for k, n in enumerate(ns):
        xs, end, worst = [], [], []
        for i, s in enumerate(scenes):
            for r in rows:
                if r["scene"] == s and int(r["n"]) == n and r["status"] != "killed":
                    xs.append(i + k * width)
                    end.append(100 * num(r, "strain_end"))
                    worst.append(100 * num(r, "strain_worst"))
        ax[1][0].bar(xs, worst, width, alpha=0.35, color="C%d" % k)
        ax[1][0].bar(xs, end, width, label="n = %d (pale: worst over the run)" % n, color="C%d" % k)
    ax[1][0].set_xticks([i + 0.4 - width / 2 for i in range(len(scenes))])
    ax[1][0].set_xticklabels(scenes, rotation=20)
    ax[1][0].set_ylabel("max edge strain at the end (%, log)")
    ax[1][0].set_yscale("log")
    ax[1][0].legend()
    ax[1][0].set_title("stretch")
    ax[1][1].axis("off")
    lines = ["scene            n  status     frames pairs(max) obst.pairs penetr.(m) unresolved through"]
    for r in rows:
        lines.append("%-15s %3s %-10s %6s %10s %10s %10s %10s %7s" % (
            r["scene"], r["n"], short_status(r), r["frames"], r["pairs_max"], r["obstacle_pairs_max"], r["penetration_m"],
            r["unresolved_steps"], r["projectile_through"]))
    ax[1][1].text(0, 1, "\n".join(lines), family="monospace", fontsize=7.5, va="top")
    ax[1][1].set_title("exact checks after every step")
    machine = rows[0]["machine"] + ", " + rows[0]["cpu"] if rows else ""
    fig.suptitle("cloth.h contact stress scenes (docs/scenes.md), 1 step per frame at 60 fps; " + machine, fontsize=10)
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=100)


if __name__ == "__main__":
    main()
