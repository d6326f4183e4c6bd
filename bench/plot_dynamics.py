#!/usr/bin/python3
"""Analysis of bench/dynamics.sh's results: the comparison with Bullet, the cost exponent,
the plots and a printed summary.

    plot_dynamics.py RESULTS_DIR [MACHINE CPU]

Reads RESULTS_DIR/dynamics.csv, dynamics_payuse.csv (optional) and bullet_hang.csv; writes
RESULTS_DIR/dynamics_vs_bullet.csv, dynamics_fit.csv and dynamics.png. MACHINE and CPU name
the machine in the written rows (default: those of dynamics.csv's first row).
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

TARGET_RATIO = 0.25   # cloth.h ms/frame at most a quarter of Bullet's ...
TARGET_STRAIN = 0.05  # ... with max edge strain under 5 %
TARGET_N = 64

SHORT = {
    "symplectic_euler": "symplectic Euler",
    "backward_euler_linearized": "linearized BE",
    "backward_euler_newton": "Newton BE",
    "bdf2": "BDF2",
}
COLOURS = {
    "symplectic_euler": "tab:orange",
    "backward_euler_linearized": "tab:blue",
    "backward_euler_newton": "tab:green",
    "bdf2": "tab:red",
}


def read_csv(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def num(row, key):
    v = row.get(key, "")
    try:
        return float(v)
    except (TypeError, ValueError):
        return float("nan")


def ok(row):
    return row.get("status") == "ok"


def fmt(x, digits=3):
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "-"
    return f"{x:.{digits}g}" if abs(x) < 10 ** digits else f"{x:.0f}"


def pct(x):
    return "-" if math.isnan(x) else f"{100 * x:.1f}%"


def fit_exponent(rows, key):
    """Least-squares slope of log(key) against log(vertices) over the rows."""
    pts = [(num(r, "vertices"), num(r, key)) for r in rows]
    pts = [(v, y) for v, y in pts if v > 0 and y > 0]
    if len(pts) < 2:
        return float("nan"), len(pts)
    x = np.log([p[0] for p in pts])
    y = np.log([p[1] for p in pts])
    slope = np.polyfit(x, y, 1)[0]
    return float(slope), len(pts)


def table(title, header, rows):
    print(f"\n{title}")
    widths = [max(len(str(h)), *(len(str(r[i])) for r in rows)) if rows else len(str(h)) for i, h in enumerate(header)]
    print("  " + "  ".join(str(h).rjust(w) for h, w in zip(header, widths)))
    for r in rows:
        print("  " + "  ".join(str(c).rjust(w) for c, w in zip(r, widths)))


def main():
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    results = sys.argv[1]
    rows = read_csv(os.path.join(results, "dynamics.csv"))
    payuse = read_csv(os.path.join(results, "dynamics_payuse.csv"))
    bullet = read_csv(os.path.join(results, "bullet_hang.csv"))
    if not rows:
        sys.exit(f"plot_dynamics: no rows in {results}/dynamics.csv")
    machine = sys.argv[2] if len(sys.argv) > 2 else rows[0]["machine"]
    cpu = sys.argv[3] if len(sys.argv) > 3 else rows[0]["cpu"]

    def select(set_=None, integrator=None, material=None, tol=None, precond=None, status_ok=False):
        out = []
        for r in rows:
            if set_ and r["set"] != set_:
                continue
            if integrator and r["integrator"] != integrator:
                continue
            if material and r["material"] != material:
                continue
            if tol is not None and not math.isclose(num(r, "cg_tolerance"), tol, rel_tol=1e-6):
                continue
            if precond and r["preconditioner"] != precond:
                continue
            if status_ok and not ok(r):
                continue
            out.append(r)
        return sorted(out, key=lambda r: num(r, "n"))

    # Bullet: the docs/scenes.md set-up (bending links, distance 2)
    bullet2 = {int(num(b, "n")): b for b in bullet if b.get("scene") == "hang" and b.get("bending_distance") == "2"}
    bullet0 = {int(num(b, "n")): b for b in bullet if b.get("scene") == "hang" and b.get("bending_distance") == "0"}

    # ---- comparison with Bullet --------------------------------------------------------
    lbe = "backward_euler_linearized"
    configs = []  # (label, rows)
    main_tol = None
    for r in rows:
        if r["set"] == "main" and r["integrator"] == lbe:
            main_tol = num(r, "cg_tolerance")
            break
    seen = set()
    for r in rows:
        if r["integrator"] != lbe or r["preconditioner"] != "block_jacobi" or r["set"] not in ("main", "tolerance", "stiff"):
            continue
        key = (r["set"], r["material"], r["cg_tolerance"])
        if key in seen:
            continue
        seen.add(key)
        configs.append(key)
    vs_rows = []
    for set_, material, tol in configs:
        for r in select(set_=set_, integrator=lbe, material=material, tol=float(tol)):
            n = int(num(r, "n"))
            b = bullet2.get(n)
            cms, cwall = num(r, "ms_per_frame_cpu"), num(r, "ms_per_frame_wall")
            bcpu = num(b, "cpu_ms_per_frame_median") if b else float("nan")
            bwall = num(b, "ms_per_frame_median") if b else float("nan")
            worst = num(r, "strain_worst")
            ratio_cpu = cms / bcpu if ok(r) and bcpu > 0 else float("nan")
            ratio_wall = cwall / bwall if ok(r) and bwall > 0 else float("nan")
            meets_time = ok(r) and ratio_cpu <= TARGET_RATIO
            meets_strain = ok(r) and worst < TARGET_STRAIN
            vs_rows.append({
                "machine": machine, "cpu": cpu, "n": n, "vertices": n * n,
                "clothh_integrator": lbe, "clothh_material": material, "clothh_c11_n_per_m": r["c11_n_per_m"],
                "clothh_cg_tolerance": tol, "clothh_preconditioner": r["preconditioner"], "clothh_set": set_,
                "clothh_status": r["status"], "clothh_runs": r["runs"],
                "clothh_ms_per_frame_cpu": r["ms_per_frame_cpu"] if ok(r) else "",
                "clothh_ms_per_frame_wall": r["ms_per_frame_wall"] if ok(r) else "",
                "clothh_cg_per_frame": r["cg_per_frame"] if ok(r) else "",
                "clothh_max_strain_end": r["strain_end"] if ok(r) else "",
                "clothh_max_strain_run": r["strain_worst"] if ok(r) else "",
                "clothh_lowest_y": r["lowest_y"] if ok(r) else "",
                "bullet_bending_distance": b["bending_distance"] if b else "",
                "bullet_substeps_per_frame": b["substeps_per_frame"] if b else "",
                "bullet_piterations": b["piterations"] if b else "",
                "bullet_ms_per_frame_cpu": b["cpu_ms_per_frame_median"] if b else "",
                "bullet_ms_per_frame_wall": b["ms_per_frame_median"] if b else "",
                "bullet_max_strain_end": b["max_strain_end"] if b else "",
                "bullet_max_strain_run": b["max_strain_run"] if b else "",
                "ratio_cpu": f"{ratio_cpu:.3f}" if not math.isnan(ratio_cpu) else "",
                "ratio_wall": f"{ratio_wall:.3f}" if not math.isnan(ratio_wall) else "",
                "target_ratio": TARGET_RATIO, "target_strain": TARGET_STRAIN,
                "meets_time": int(meets_time), "meets_strain": int(meets_strain),
                "meets_target": int(meets_time and meets_strain),
            })
    with open(os.path.join(results, "dynamics_vs_bullet.csv"), "w", newline="") as f:
        if vs_rows:
            w = csv.DictWriter(f, fieldnames=list(vs_rows[0].keys()))
            w.writeheader()
            w.writerows(vs_rows)

    # ---- cost exponent -------------------------------------------------------------------
    fits = []
    groups = {}
    for r in rows:
        if not ok(r) or r["set"] == "preconditioner":
            continue
        key = (r["set"], r["integrator"], r["material"], r["cg_tolerance"], r["preconditioner"])
        groups.setdefault(key, []).append(r)
    for key, g in groups.items():
        g = sorted(g, key=lambda r: num(r, "n"))
        e_cpu, k = fit_exponent(g, "ms_per_frame_cpu")
        e_wall, _ = fit_exponent(g, "ms_per_frame_wall")
        e_cg, _ = fit_exponent(g, "cg_per_frame")
        if k < 2:
            continue
        fits.append({
            "machine": machine, "cpu": cpu, "simulator": "cloth.h", "set": key[0], "integrator": key[1], "material": key[2],
            "cg_tolerance": key[3], "preconditioner": key[4], "sizes": " ".join(r["n"] for r in g),
            "exponent_cpu": f"{e_cpu:.3f}", "exponent_wall": f"{e_wall:.3f}",
            "exponent_cg_iterations": f"{e_cg:.3f}" if not math.isnan(e_cg) else "",
        })
    for label, bl in (("bullet, bending links 2", bullet2), ("bullet, no bending links", bullet0)):
        g = [{"vertices": bl[n]["vertices"], "ms_per_frame_cpu": bl[n]["cpu_ms_per_frame_median"],
              "ms_per_frame_wall": bl[n]["ms_per_frame_median"]} for n in sorted(bl)]
        e_cpu, k = fit_exponent(g, "ms_per_frame_cpu")
        e_wall, _ = fit_exponent(g, "ms_per_frame_wall")
        if k >= 2:
            fits.append({"machine": bullet[0]["machine"], "cpu": bullet[0]["cpu"], "simulator": label, "set": "", "integrator": "",
                         "material": "", "cg_tolerance": "", "preconditioner": "", "sizes": " ".join(str(n) for n in sorted(bl)),
                         "exponent_cpu": f"{e_cpu:.3f}", "exponent_wall": f"{e_wall:.3f}", "exponent_cg_iterations": ""})
    with open(os.path.join(results, "dynamics_fit.csv"), "w", newline="") as f:
        if fits:
            w = csv.DictWriter(f, fieldnames=list(fits[0].keys()))
            w.writeheader()
            w.writerows(fits)

    # ---- plots ---------------------------------------------------------------------------------
    fig, axes = plt.subplots(2, 2, figsize=(13, 10))
    ax = axes[0][0]
    for integ in SHORT:
        g = select(set_="main", integrator=integ, status_ok=True)
        if g:
            ax.loglog([num(r, "vertices") for r in g], [num(r, "ms_per_frame_cpu") for r in g], "o-", color=COLOURS[integ],
                      label=f"{SHORT[integ]} (CG {fmt(num(g[0], 'cg_tolerance'))})" if integ != "symplectic_euler" else SHORT[integ])
        p = [r for r in select(set_="main", integrator=integ) if r["status"].startswith("skipped: ") and "pilot" in r["status"]]
        if p:
            ax.loglog([num(r, "vertices") for r in p], [num(r, "ms_per_frame_cpu") for r in p], "x", color=COLOURS[integ], ms=9)
    for tol, style in ((1e-3, "s--"), (1e-2, "^:")):
        g = select(set_="tolerance", integrator=lbe, tol=tol, status_ok=True)
        if g:
            ax.loglog([num(r, "vertices") for r in g], [num(r, "ms_per_frame_cpu") for r in g], style, color=COLOURS[lbe],
                      label=f"linearized BE, CG {tol:g}", alpha=0.8)
    g = select(set_="stiff", integrator=lbe, status_ok=True)
    if g:
        ax.loglog([num(r, "vertices") for r in g], [num(r, "ms_per_frame_cpu") for r in g], "d-.", color="tab:purple",
                  label=f"linearized BE, {g[0]['material']}, CG {fmt(num(g[0], 'cg_tolerance'))}")
    if bullet2:
        ns = sorted(bullet2)
        ax.loglog([num(bullet2[n], "vertices") for n in ns], [num(bullet2[n], "cpu_ms_per_frame_median") for n in ns], "k*-", ms=10,
                  label="Bullet 3.24 (bending links, 4 substeps, 10 it.) CPU")
        ax.loglog([num(bullet2[n], "vertices") for n in ns], [num(bullet2[n], "ms_per_frame_median") for n in ns], "k*:", ms=7,
                  alpha=0.5, label="Bullet wall")
        ax.loglog([num(bullet2[n], "vertices") for n in ns], [TARGET_RATIO * num(bullet2[n], "cpu_ms_per_frame_median") for n in ns],
                  color="grey", ls="--", lw=1, label="target: 1/4 of Bullet's CPU ms/frame")
    ax.set_xlabel("vertices")
    ax.set_ylabel("ms per frame (process CPU time, median)")
    ax.set_title("hang: cost per 1/60 s frame (x: pilot estimate, run skipped)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)

    ax = axes[0][1]
    for integ in SHORT:
        if integ == "symplectic_euler":
            continue
        g = select(set_="main", integrator=integ, status_ok=True)
        if g:
            ax.semilogy([num(r, "n") for r in g], [num(r, "cg_per_frame") for r in g], "o-", color=COLOURS[integ],
                        label=f"{SHORT[integ]}, CG {fmt(num(g[0], 'cg_tolerance'))}")
        g = select(set_="tolerance", integrator=integ, tol=1e-3, status_ok=True)
        if g:
            ax.semilogy([num(r, "n") for r in g], [num(r, "cg_per_frame") for r in g], "s--", color=COLOURS[integ],
                        label=f"{SHORT[integ]}, CG 1e-3", alpha=0.8)
    g = select(set_="tolerance", integrator=lbe, tol=1e-2, status_ok=True)
    if g:
        ax.semilogy([num(r, "n") for r in g], [num(r, "cg_per_frame") for r in g], "^:", color=COLOURS[lbe], label="linearized BE, CG 1e-2")
    pre = {}
    for r in rows:
        if r["integrator"] == lbe and ok(r) and math.isclose(num(r, "cg_tolerance"), 1e-3) and r["material"] == "cotton" \
                and r["set"] in ("preconditioner", "tolerance") and r["n"] in ("32", "64"):
            pre.setdefault(r["preconditioner"], []).append(r)
    for p, g in sorted(pre.items()):
        if p == "block_jacobi":
            continue
        g = sorted(g, key=lambda r: num(r, "n"))
        ax.semilogy([num(r, "n") for r in g], [num(r, "cg_per_frame") for r in g], "v-", lw=1, label=f"linearized BE, CG 1e-3, {p}")
    ax.set_xscale("log", base=2)
    ax.set_xlabel("n (vertices per side)")
    ax.set_ylabel("CG iterations per frame (all Newton iterations)")
    ax.set_title("CG iterations (block Jacobi unless named; cap 1000/solve)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)

    ax = axes[1][0]
    labels, assembly, solve, other = [], [], [], []
    for integ in SHORT:
        for r in select(set_="main", integrator=integ, status_ok=True):
            labels.append(f"{SHORT[integ]}\nn={r['n']}")
            assembly.append(num(r, "assembly_ms_per_frame"))
            solve.append(num(r, "solve_ms_per_frame"))
            other.append(max(0.0, num(r, "other_ms_per_frame")))
    if labels:
        tot = [a + s + o for a, s, o in zip(assembly, solve, other)]
        a_sh = [a / t if t > 0 else 0 for a, t in zip(assembly, tot)]
        s_sh = [s / t if t > 0 else 0 for s, t in zip(solve, tot)]
        o_sh = [o / t if t > 0 else 0 for o, t in zip(other, tot)]
        x = np.arange(len(labels))
        ax.bar(x, a_sh, label="assembly (forces, Hessians; line search)", color="tab:cyan")
        ax.bar(x, s_sh, bottom=a_sh, label="solve (CG)", color="tab:olive")
        ax.bar(x, o_sh, bottom=[a + s for a, s in zip(a_sh, s_sh)], label="other (backup, checks)", color="tab:gray")
        for xi, t in zip(x, tot):
            ax.text(xi, 1.01, f"{t:.3g}", ha="center", va="bottom", fontsize=6, rotation=90)
        ax.set_xticks(x)
        ax.set_xticklabels(labels, fontsize=6, rotation=90)
        ax.set_ylim(0, 1.32)
    ax.set_ylabel("share of cloth_step_stats.time_total")
    ax.set_title("where a frame goes (main set; ms/frame CPU above the bars)")
    ax.legend(fontsize=7, loc="upper center", ncol=3)

    ax = axes[1][1]
    for integ in SHORT:
        g = select(set_="main", integrator=integ, status_ok=True)
        if g:
            ax.semilogy([num(r, "n") for r in g], [100 * num(r, "strain_worst") for r in g], "o-", color=COLOURS[integ],
                        label=f"{SHORT[integ]} worst frame")
            ax.semilogy([num(r, "n") for r in g], [100 * num(r, "strain_end") for r in g], "o:", color=COLOURS[integ], alpha=0.6)
    g = select(set_="stiff", integrator=lbe, status_ok=True)
    if g:
        ax.semilogy([num(r, "n") for r in g], [100 * num(r, "strain_worst") for r in g], "d-.", color="tab:purple",
                    label=f"linearized BE, {g[0]['material']} worst")
    g = select(set_="tolerance", integrator=lbe, tol=1e-2, status_ok=True)
    if g:
        ax.semilogy([num(r, "n") for r in g], [100 * num(r, "strain_worst") for r in g], "^:", color=COLOURS[lbe],
                    label="linearized BE, CG 1e-2 worst")
    if bullet2:
        ns = sorted(bullet2)
        ax.semilogy(ns, [100 * num(bullet2[n], "max_strain_run") for n in ns], "k*-", label="Bullet worst (bending links)")
        ax.semilogy(ns, [100 * num(bullet2[n], "max_strain_end") for n in ns], "k*:", alpha=0.6, label="Bullet end")
    ax.axhline(100 * TARGET_STRAIN, color="grey", ls="--", lw=1, label="5 % target")
    ax.set_xscale("log", base=2)
    ax.set_xlabel("n (vertices per side)")
    ax.set_ylabel("max edge strain, % (solid: worst frame, dotted: end)")
    ax.set_title("stretch accuracy")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    fig.suptitle(f"cloth.h hang scene (docs/scenes.md), {machine}, {cpu}; single thread", fontsize=10)
    fig.tight_layout()
    fig.savefig(os.path.join(results, "dynamics.png"), dpi=110)

    # ---- summary -------------------------------------------------------------------------------
    print(f"\ncloth.h dynamics: hang scene, {machine}, {cpu}")
    loads = [num(r, "loadavg") for r in rows if not math.isnan(num(r, "loadavg"))]
    if loads:
        print(f"load average during the runs: {min(loads):.2f} .. {max(loads):.2f} (on {os.cpu_count()} cores)")

    def noise(r):
        m = num(r, "ms_per_frame_cpu")
        lo, hi = num(r, "ms_per_frame_cpu_min"), num(r, "ms_per_frame_cpu_max")
        if not ok(r) or num(r, "runs") < 2 or not m > 0:
            return "-"
        return f"{100 * (hi - lo) / m:.0f}%"

    def scene_rows(sel):
        out = []
        for r in sel:
            if r["status"].startswith("skipped: the smaller") or (r["status"].startswith("skipped") and "pilot" not in r["status"]):
                out.append([SHORT.get(r["integrator"], r["integrator"]), r["n"], r["material"], fmt(num(r, "cg_tolerance")),
                            r["preconditioner"], "skipped"] + ["-"] * 12)
                continue
            tag = "" if ok(r) else " (pilot)" if "pilot" in r["status"] else " (" + r["status"] + ")"
            out.append([
                SHORT.get(r["integrator"], r["integrator"]), r["n"], r["material"], fmt(num(r, "cg_tolerance")), r["preconditioner"],
                r["runs"] + tag,
                fmt(num(r, "ms_per_frame_cpu")), noise(r), fmt(num(r, "ms_per_frame_wall")),
                fmt(num(r, "substeps_per_frame")), fmt(num(r, "cg_per_frame")), r["cg_capped_solves"],
                fmt(num(r, "newton_per_frame")),
                f"{fmt(num(r, 'assembly_ms_per_frame'))}/{fmt(num(r, 'solve_ms_per_frame'))}/{fmt(num(r, 'other_ms_per_frame'), 2)}",
                pct(num(r, "strain_end")), pct(num(r, "strain_worst")), fmt(num(r, "lowest_y")), fmt(num(r, "bytes_per_vertex"), 4),
            ])
        return out

    header = ["integrator", "n", "material", "CG tol", "precond", "runs", "ms/frame CPU", "spread", "ms/frame wall", "substeps",
              "CG/frame", "CG capped", "Newton/frame", "assembly/solve/other ms", "strain end", "strain worst", "lowest y", "B/vertex"]
    table("main set (library defaults; spread = (max - min) / median of the runs' CPU ms/frame):", header,
          scene_rows([r for integ in SHORT for r in select(set_="main", integrator=integ)]))
    table("tolerance set (CG tolerance as the speed-accuracy knob):", header,
          scene_rows([r for integ in SHORT for r in select(set_="tolerance", integrator=integ)]))
    table("stiff set:", header, scene_rows(select(set_="stiff")))
    table("preconditioner set (block Jacobi: the tolerance set's 1e-3 rows):", header,
          scene_rows(select(set_="preconditioner") + [r for r in select(set_="tolerance", integrator=lbe, tol=1e-3) if r["n"] in ("32", "64")]))
    for r in rows:
        if not ok(r) and not r["status"].startswith("skipped: the smaller"):
            print(f"  note: {SHORT.get(r['integrator'], r['integrator'])} n={r['n']} {r['set']} CG {r['cg_tolerance']}: {r['status']}")

    table("cost exponent: ms per frame ~ vertices^k (least squares on log-log, sizes that ran in full):",
          ["simulator", "set", "integrator", "material", "CG tol", "sizes", "k (CPU)", "k (wall)", "k (CG iterations)"],
          [[f["simulator"], f["set"], SHORT.get(f["integrator"], f["integrator"]), f["material"], f["cg_tolerance"], f["sizes"],
            f["exponent_cpu"], f["exponent_wall"], f["exponent_cg_iterations"]] for f in fits])

    if payuse:
        table("pay for what you use (n = 64, linearized BE, one step from the t = 1 s state, median of the repetitions):",
              ["variant", "step ms CPU", "assembly ms (min..max)", "solve ms", "other ms (min..max)", "CG", "B/vertex",
               "matrix B/vertex"],
              [[p["variant"], fmt(num(p, "step_ms_cpu")),
                f"{fmt(num(p, 'assembly_ms'))} ({fmt(num(p, 'assembly_ms_min'))}..{fmt(num(p, 'assembly_ms_max'))})",
                fmt(num(p, "solve_ms")), f"{fmt(num(p, 'other_ms'), 2)} ({fmt(num(p, 'other_ms_min'), 2)}..{fmt(num(p, 'other_ms_max'), 2)})",
                p["cg_iterations"], fmt(num(p, "bytes_per_vertex"), 4), fmt(num(p, "matrix_bytes_per_vertex"), 4)] for p in payuse])
        by = {p["variant"]: p for p in payuse}
        on = next((p for p in payuse if p["bending"] == "1" and num(p, "wind_m_per_s") == 0), None)
        off = next((p for p in payuse if p["bending"] == "0" and num(p, "wind_m_per_s") == 0), None)
        wind = next((p for p in payuse if p["bending"] == "1" and num(p, "wind_m_per_s") > 0), None)
        if on and off:
            a_on, a_off = num(on, "assembly_ms"), num(off, "assembly_ms")
            print(f"  bending: assembly {fmt(a_on)} ms with it, {fmt(a_off)} ms without: bending's share of assembly "
                  f"{100 * (a_on - a_off) / a_on:.0f}%; memory {fmt(num(on, 'bytes_per_vertex'), 4)} -> "
                  f"{fmt(num(off, 'bytes_per_vertex'), 4)} bytes/vertex")
        if on and wind:
            print(f"  wind: 'other' time {fmt(num(on, 'other_ms'), 2)} ms without wind, {fmt(num(wind, 'other_ms'), 2)} ms with "
                  f"5 m/s (the aerodynamic forces are computed there); assembly {fmt(num(on, 'assembly_ms'))} vs "
                  f"{fmt(num(wind, 'assembly_ms'))} ms")
        del by

    if vs_rows:
        table("against Bullet 3.24 btSoftBody (bending links, 4 substeps, 10 iterations; bench/results/bullet_hang.csv):",
              ["n", "cloth.h config", "status", "cloth.h CPU", "wall", "strain worst (end)", "Bullet CPU", "wall",
               "Bullet strain worst (end)", "ratio CPU", "ratio wall", "meets target"],
              [[v["n"], f"{v['clothh_material']} CG {v['clothh_cg_tolerance']}", "ok" if v["clothh_status"] == "ok" else "skipped",
                fmt(num(v, "clothh_ms_per_frame_cpu")), fmt(num(v, "clothh_ms_per_frame_wall")),
                f"{pct(num(v, 'clothh_max_strain_run'))} ({pct(num(v, 'clothh_max_strain_end'))})",
                fmt(num(v, "bullet_ms_per_frame_cpu")), fmt(num(v, "bullet_ms_per_frame_wall")),
                f"{pct(num(v, 'bullet_max_strain_run'))} ({pct(num(v, 'bullet_max_strain_end'))})",
                v["ratio_cpu"] or "-", v["ratio_wall"] or "-", "yes" if v["meets_target"] else "no"] for v in vs_rows])
        at = [v for v in vs_rows if v["n"] == TARGET_N and v["clothh_status"] == "ok"]
        met = [v for v in at if v["meets_target"]]
        print(f"\ntarget (hang {TARGET_N}, one implicit step per frame, <= {TARGET_RATIO:g} x Bullet's ms/frame, max edge strain "
              f"< {100 * TARGET_STRAIN:g}%): {'MET by ' + ', '.join(v['clothh_material'] + ' CG ' + v['clothh_cg_tolerance'] for v in met) if met else 'NOT MET'}")
        for v in at:
            need = num(v, "ratio_cpu") / TARGET_RATIO
            print(f"  {v['clothh_material']}, CG {v['clothh_cg_tolerance']}: {fmt(num(v, 'clothh_ms_per_frame_cpu'))} ms/frame CPU = "
                  f"{v['ratio_cpu']} x Bullet's {fmt(num(v, 'bullet_ms_per_frame_cpu'))} (needs {need:.1f}x faster), worst strain "
                  f"{pct(num(v, 'clothh_max_strain_run'))}")
    print(f"\nwrote {results}/dynamics_vs_bullet.csv, {results}/dynamics_fit.csv, {results}/dynamics.png")


if __name__ == "__main__":
    main()
