#!/usr/bin/python3
"""Plots of gpsemu's noise models, real receivers against the calibrated models, and the figures
of the cgrw report ("Using random walks to simulate GPS sensing", SBEL TR-2022-02) reproduced.

  tools/plot_noise.py [--gpsemu BIN] [--out DIR] [LOG ...]

  tools/plot_noise.py judge DIR [--out DIR2]   (the figures of `gpsemu judge LOG --plots DIR` alone)

For each LOG (a stationary receiver's NMEA log) it runs `gpsemu compare LOG --csv` and draws the
real series against every calibrated model's first run per axis (LOG_series.png) and the
histograms of their first differences (LOG_d1_hist.png); then `gpsemu judge LOG --plots` and draws
the Kalman filter's NIS histograms, real against each model (LOG_judge_nis.png), and its four
scores side by side (LOG_judge_scores.png). Without logs or with them, it draws:
  stationary_trace.png   a stationary receiver with the default cgrw noise (report Fig. 1/5)
  widths.png             cgrw one knob at 0.1, 1 and 10 m (report Fig. 10)
  line_drive.png         the straight-line drive, cgrw vs gaussian sigma 1 m (report Fig. 8/9)
  composite.png          the composite model against its smooth part alone (same seed): the
                         difference is its white jitter and its jumps
Data comes from the emulator itself (`gpsemu --fast --output stdout`), parsed from its GGA
sentences. Needs numpy and matplotlib (Debian: python3-numpy python3-matplotlib).
"""
import argparse
import csv
import math
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ORIGIN = (43.0725, -89.4125, 260.0)  # the emulator's default origin
START = "2024-05-01T12:00:00Z"
COLOURS = {"real": "black", "cgrw": "tab:blue", "chrono": "tab:orange", "gaussian": "tab:gray",
           "gauss-markov": "tab:green", "gauss-markov-2": "tab:red", "composite": "tab:purple"}


def find_gpsemu(given):
    candidates = [given] if given else [os.environ.get("GPSEMU", ""),
                                        os.path.join(ROOT, "build", "emulator", "gpsemu")]
    for c in candidates:
        if c and os.access(c, os.X_OK):
            return c
    sys.exit("gpsemu binary not found: build it (tools/run or cmake) or pass --gpsemu PATH")


def nmea_degrees(value, hemisphere):
    dot = value.index(".")
    deg = float(value[: dot - 2]) + float(value[dot - 2:]) / 60.0
    return -deg if hemisphere in "SW" else deg


def enu(lat, lon, alt, origin=ORIGIN):
    """Local east/north/up metres about origin (small offsets: WGS84 radii of curvature)."""
    a, f = 6378137.0, 1 / 298.257223563
    e2 = f * (2 - f)
    phi = math.radians(origin[0])
    w = math.sqrt(1 - e2 * math.sin(phi) ** 2)
    m_per_deg_lat = math.radians(a * (1 - e2) / w ** 3)
    m_per_deg_lon = math.radians(a / w * math.cos(phi))
    return ((np.asarray(lon) - origin[1]) * m_per_deg_lon, (np.asarray(lat) - origin[0]) * m_per_deg_lat,
            np.asarray(alt) - origin[2])


def emulate(gpsemu, args):
    """Runs the emulator; returns (t_s, east_m, north_m, up_m) of its GGA fixes."""
    cmd = [gpsemu, "--fast", "--output", "stdout", "--log-level", "warn", "--start-time", START] + args
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    t, lat, lon, alt = [], [], [], []
    for line in out.splitlines():
        f = line.split(",")
        if len(f) > 9 and f[0].endswith("GGA") and f[2] and f[6] != "0":
            hh, mm, ss = int(f[1][:2]), int(f[1][2:4]), float(f[1][4:])
            t.append(hh * 3600 + mm * 60 + ss)
            lat.append(nmea_degrees(f[2], f[3]))
            lon.append(nmea_degrees(f[4], f[5]))
            alt.append(float(f[9]))
    t = np.asarray(t) - t[0]
    e, n, u = enu(lat, lon, alt)
    return t, e, n, u


def save(fig, path):
    fig.savefig(path, dpi=110)
    plt.close(fig)
    print(path)


def plot_log(gpsemu, log, out_dir):
    name = os.path.splitext(os.path.basename(log))[0]
    csv_path = os.path.join(out_dir, name + "_compare.csv")
    report = subprocess.run([gpsemu, "compare", log, "--csv", csv_path, "--log-level", "warn"], check=True,
                            capture_output=True, text=True).stdout
    with open(os.path.join(out_dir, name + "_compare.txt"), "w") as f:
        f.write(report)
    scores = {}
    for line in report.splitlines():
        if line.startswith("score"):
            parts = line.split(":", 1)[1].split()
            for model, value in zip(parts[0::2], parts[1::2]):
                scores[model.lstrip("*")] = float(value)
    with open(csv_path) as f:
        rows = list(csv.reader(f))
    header, data = rows[0], rows[1:]
    col = {h: i for i, h in enumerate(header)}

    def series(label, axis):
        """One column, about its own mean (the real log is about its mean position; a simulated
        run is about the true position, and a slow process can sit metres away from it)."""
        i = col[f"{label}_{axis}_m"]
        x = np.array([float(r[i]) if r[i] else np.nan for r in data])
        return x - np.nanmean(x)

    t = np.array([float(r[0]) for r in data])
    models = [h[: -len("_east_m")] for h in header if h.endswith("_east_m") and not h.startswith("real")]
    best = min(models, key=lambda m: scores.get(m, 1e9))
    fig, axes = plt.subplots(3, 1, figsize=(11, 9), sharex=True)
    for ax, axis in zip(axes, ("east", "north", "up")):
        for m in models:
            if m == "gaussian":
                continue  # white noise hides everything else; its d1 histogram shows it
            ax.plot(t, series(m, axis), lw=1.0 if m == best else 0.7, alpha=1.0 if m == best else 0.6,
                    color=COLOURS.get(m), label=f"{m} (score {scores.get(m, float('nan')):.2f})")
        ax.plot(t, series("real", axis), color="black", lw=1.4, label="real receiver")
        ax.set_ylabel(f"{axis} (m)")
        ax.grid(alpha=0.3)
    axes[0].legend(loc="upper right", fontsize=8, ncol=3)
    axes[-1].set_xlabel("time since first fix (s)")
    fig.suptitle(f"{name}: real receiver vs calibrated models (best: {best})\n"
                 "each about its own mean; first simulated run of each; gaussian (white) left out")
    fig.tight_layout()
    save(fig, os.path.join(out_dir, name + "_series.png"))

    fig, axes = plt.subplots(1, 3, figsize=(13, 4))
    for ax, axis in zip(axes, ("east", "north", "up")):
        real_d1 = np.diff(series("real", axis))
        real_d1 = real_d1[~np.isnan(real_d1)]
        lim = 1.25 * np.max(np.abs(real_d1))
        # Quantised logs (output resolution): one bin per quantum, centred on it.
        steps = np.unique(np.round(np.abs(real_d1), 6))
        quantum = steps[steps > 0].min() if np.any(steps > 0) else lim / 20
        if lim / quantum <= 30:
            steps_out = math.ceil(lim / quantum)
            bins = (np.arange(-steps_out, steps_out + 2) - 0.5) * quantum
        else:
            bins = np.linspace(-lim, lim, 41)
        for m in ["real"] + models:
            d1 = np.diff(series(m, axis))
            d1 = d1[~np.isnan(d1)]
            outside = np.mean(np.abs(d1) > lim)
            label = m + (f" ({100 * outside:.0f}% outside)" if outside > 0.005 else "")
            ax.hist(d1[np.abs(d1) <= lim], bins=bins, histtype="step", lw=1.8 if m in ("real", best) else 0.9,
                    color=COLOURS.get(m), label=label, weights=np.full(np.sum(np.abs(d1) <= lim), 1.0 / len(d1)))
        ax.set_xlabel(f"{axis} first difference (m per sample)")
        ax.set_yscale("log")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    axes[0].set_ylabel("fraction of differences (log scale)")
    fig.suptitle(f"{name}: first-difference histograms, real vs models (x range: 1.25 x the real extremes)")
    fig.tight_layout()
    save(fig, os.path.join(out_dir, name + "_d1_hist.png"))


def plot_judge(judge_dir, name, out_dir):
    """The figures of `gpsemu judge --plots judge_dir`: NIS histograms and the four scores."""
    nis = {}
    with open(os.path.join(judge_dir, "judge_nis.csv")) as f:
        for row in csv.DictReader(f):
            nis.setdefault(row["source"], []).append(float(row["nis"]))
    with open(os.path.join(judge_dir, "judge_summary.csv")) as f:
        summary = {row["source"]: row for row in csv.DictReader(f)}
    models = [m for m in summary if m != "real"]
    best = min(models, key=lambda m: float(summary[m]["distance"]))
    real = np.asarray(nis["real"])
    top = max(3 * np.percentile(real, 95), 12.0)
    bins = np.linspace(0, top, 50)
    fig, axes = plt.subplots(2, (len(models) + 1) // 2, figsize=(14, 7), sharex=True, sharey=True)
    for ax, m in zip(axes.flat, models):
        ax.hist(np.clip(real, 0, top), bins=bins, density=True, histtype="stepfilled", alpha=0.35, color="black",
                label="real")
        ax.hist(np.clip(np.asarray(nis.get(m, [0.0])), 0, top), bins=bins, density=True, histtype="step", lw=1.6,
                color=COLOURS.get(m), label=m)
        x = np.linspace(0.01, top, 200)
        ax.plot(x, 0.5 * np.exp(-x / 2), "k:", lw=0.8, label="chi-square, 2 dof")
        s_ = summary[m]
        ax.set_title(f"{'* ' if m == best else ''}{m}: NIS mean {float(s_['nis_mean']):.2f} "
                     f"(real {float(summary['real']['nis_mean']):.2f})", fontsize=9)
        ax.set_yscale("log")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    for ax in axes.flat[len(models):]:
        ax.axis("off")
    fig.suptitle(f"{name}: NIS of the judge's constant-velocity Kalman filter, real vs each calibrated model "
                 f"(all runs; last bin holds everything beyond)")
    fig.tight_layout()
    save(fig, os.path.join(out_dir, name + "_judge_nis.png"))

    keys = [("nis_mean", "NIS mean"), ("nis_p95", "NIS 95th percentile"), ("innov_rho1", "innovation lag-1 acf"),
            ("pos_err_m", "position error (m)")]
    fig, axes = plt.subplots(1, 4, figsize=(15, 4))
    for ax, (key, title) in zip(axes, keys):
        names = ["real"] + models
        values = [float(summary[n][key]) for n in names]
        ax.bar(range(len(names)), values, color=[COLOURS.get(n, "tab:gray") for n in names])
        ax.axhline(float(summary["real"][key]), color="black", lw=0.8, ls="--")
        ax.set_xticks(range(len(names)))
        ax.set_xticklabels(names, rotation=45, ha="right", fontsize=8)
        ax.set_title(title, fontsize=10)
        ax.grid(alpha=0.3, axis="y")
    fig.suptitle(f"{name}: the judge's filter on the real log (dashed) and on each model (best: {best})")
    fig.tight_layout()
    save(fig, os.path.join(out_dir, name + "_judge_scores.png"))


def judge_log(gpsemu, log, out_dir):
    name = os.path.splitext(os.path.basename(log))[0]
    judge_dir = os.path.join(out_dir, name + "_judge")
    report = subprocess.run([gpsemu, "judge", log, "--plots", judge_dir, "--log-level", "warn"], check=True,
                            capture_output=True, text=True).stdout
    with open(os.path.join(out_dir, name + "_judge.txt"), "w") as f:
        f.write(report)
    plot_judge(judge_dir, name, out_dir)


def plot_composite(gpsemu, out_dir):
    smooth = ["--duration", "600", "--seed", "4", "--resolution", "7"]
    _, e0, n0, _ = emulate(gpsemu, smooth + ["--noise", "gauss-markov", "--gm-order", "2", "--gm-sigma", "0.5",
                                             "--gm-tau", "20"])
    t, e1, n1, _ = emulate(gpsemu, smooth + ["--noise", "composite", "--composite-sigma", "0.5", "--composite-tau",
                                             "20", "--composite-jitter", "0.03", "--composite-jump-rate", "0.01",
                                             "--composite-jump-size", "0.4", "--composite-jump-decay", "30"])
    fig, axes = plt.subplots(2, 1, figsize=(12, 7), sharex=True)
    axes[0].plot(t, e0, color="tab:red", lw=1.0, label="smooth part alone (gauss-markov-2, sigma 0.5 m, tau 20 s)")
    axes[0].plot(t, e1, color="tab:purple", lw=0.8, label="composite: + jitter 0.03 m + jumps 0.01/s of 0.4 m, "
                 "decay 30 s")
    axes[0].set_ylabel("east (m)")
    axes[0].legend(fontsize=8)
    axes[0].grid(alpha=0.3)
    axes[1].plot(t, e1 - e0, color="tab:purple", lw=0.8)
    axes[1].set_ylabel("composite - smooth (m)")
    axes[1].set_xlabel("time (s)")
    axes[1].grid(alpha=0.3)
    axes[1].set_title("the difference: white jitter and decaying jumps", fontsize=9)
    fig.suptitle("The composite model (same seed: the smooth part is the same process)")
    fig.tight_layout()
    save(fig, os.path.join(out_dir, "composite.png"))


def plot_stationary(gpsemu, out_dir):
    t, e, n, _ = emulate(gpsemu, ["--duration", "600", "--seed", "3"])
    fig, (a, b) = plt.subplots(1, 2, figsize=(12, 5.2), gridspec_kw={"width_ratios": [1, 1.4]})
    a.plot(e, n, lw=0.8)
    a.plot(e[0], n[0], "go", label="start")
    a.plot(0, 0, "k+", ms=12, label="true position")
    a.set_aspect("equal", adjustable="datalim")
    a.set_xlabel("east (m)")
    a.set_ylabel("north (m)")
    a.legend(fontsize=8)
    a.grid(alpha=0.3)
    a.set_title("trace, 600 s at 1 Hz")
    b.plot(t, e, label="east")
    b.plot(t, n, label="north")
    b.set_xlabel("time (s)")
    b.set_ylabel("error (m)")
    b.legend(fontsize=8)
    b.grid(alpha=0.3)
    b.set_title("error against time")
    fig.suptitle("Stationary receiver, default cgrw noise (width 1 m): report Fig. 1/5")
    fig.tight_layout()
    save(fig, os.path.join(out_dir, "stationary_trace.png"))


def plot_widths(gpsemu, out_dir):
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.8))
    for ax, width, seed in zip(axes, (0.1, 1.0, 10.0), (5, 6, 7)):
        _, e, n, _ = emulate(gpsemu, ["--duration", "300", "--width", str(width), "--seed", str(seed),
                                      "--resolution", "7"])
        ax.plot(e, n, lw=0.8)
        ax.plot(0, 0, "k+", ms=12)
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("east (m)")
        ax.set_ylabel("north (m)")
        ax.grid(alpha=0.3)
        ax.set_title(f"--width {width:g} m: east max-min {np.ptp(e):.3g} m, north {np.ptp(n):.3g} m",
                     fontsize=9)
    fig.suptitle("cgrw one knob, 300 s at 1 Hz: 0.1 m high accuracy, 1 m preset, 10 m low accuracy "
                 "(report Fig. 10)")
    fig.tight_layout()
    save(fig, os.path.join(out_dir, "widths.png"))


def plot_line(gpsemu, out_dir):
    common = ["--source", "sim:line", "--duration", "20", "--rate", "10", "--sim-speed", "2",
              "--sim-drive-time", "20", "--seed", "2"]
    t0, e0, n0, _ = emulate(gpsemu, common + ["--noise", "none"])
    tc, ec, nc, _ = emulate(gpsemu, common + ["--noise", "cgrw", "--width", "1"])
    tg, eg, ng, _ = emulate(gpsemu, common + ["--noise", "gaussian", "--gaussian-sigma", "1"])
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(13, 7.5), gridspec_kw={"height_ratios": [1.1, 1]})
    top.plot(eg, ng, ".", ms=3, color="tab:gray", label="gaussian, sigma 1 m (report Fig. 9)")
    top.plot(ec, nc, "-", lw=1.4, color="tab:blue", label="cgrw, width 1 m (report Fig. 8)")
    top.plot(e0, n0, "k--", lw=1.0, label="truth: 2 m/s east for 20 s")
    top.set_aspect("equal", adjustable="box")
    top.set_xlim(-2, 42)
    top.set_ylim(-3.5, 3.5)
    top.set_xlabel("east (m)")
    top.set_ylabel("north (m)")
    top.grid(alpha=0.3)
    top.legend(fontsize=8, loc="upper left", ncol=3)
    top.set_title("trace (equal scales)")
    bottom.plot(tg, ng - n0, ".", ms=3, color="tab:gray", label="gaussian")
    bottom.plot(tc, nc - n0, "-", lw=1.4, color="tab:blue", label="cgrw")
    bottom.plot(tc, ec - e0, "-", lw=1.0, color="tab:cyan", label="cgrw, along-track (east) error")
    bottom.set_xlabel("time (s)")
    bottom.set_ylabel("error (m)")
    bottom.grid(alpha=0.3)
    bottom.legend(fontsize=8, loc="upper left", ncol=3)
    bottom.set_title("cross-track (north) error against time: a smooth wander vs white noise")
    fig.suptitle("Straight-line drive (--source sim:line) at 10 Hz, cgrw vs gaussian")
    fig.tight_layout()
    save(fig, os.path.join(out_dir, "line_drive.png"))


def main():
    if len(sys.argv) >= 3 and sys.argv[1] == "judge":
        out = sys.argv[sys.argv.index("--out") + 1] if "--out" in sys.argv else "plots"
        os.makedirs(out, exist_ok=True)
        plot_judge(sys.argv[2], os.path.basename(os.path.normpath(sys.argv[2])), out)
        return
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("logs", nargs="*", help="stationary receivers' NMEA logs to compare")
    p.add_argument("--gpsemu", help="the gpsemu binary (default: $GPSEMU, then build/emulator/gpsemu)")
    p.add_argument("--out", default="plots", help="output folder (default ./plots)")
    a = p.parse_args()
    gpsemu = find_gpsemu(a.gpsemu)
    os.makedirs(a.out, exist_ok=True)
    for log in a.logs:
        plot_log(gpsemu, log, a.out)
        judge_log(gpsemu, log, a.out)
    plot_composite(gpsemu, a.out)
    plot_stationary(gpsemu, a.out)
    plot_widths(gpsemu, a.out)
    plot_line(gpsemu, a.out)


if __name__ == "__main__":
    main()
