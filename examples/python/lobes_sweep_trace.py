#!/usr/bin/env python3
"""Lobes, a speed sweep and two simulated traces of one milling case, with cutdyn from Python.

    python3 lobes_sweep_trace.py [OUT_DIR] [--case NAME_OR_TOML] [--rpm RPM --depth-mm MM]
                                 [--points N]

Writes three figures into OUT_DIR (default: the current directory) and prints the key numbers:

  lobes.png   critical depth against spindle speed, the lowest critical depth marked, the
              operating point checked with `cutdyn.check` (its verdict in the legend);
  sweep.png   the simulated vibration at the operating depth over the lobes' speed range
              (`cutdyn.sweep` of simulate.rpm), chattering cuts marked, the speed ranges the
              lobes call stable at that depth shaded;
  trace.png   displacement and force against time (`cutdyn.simulate`) at the operating point
              and at 1.25 times its critical depth.

The case is a built-in example (default milling-insperger, see `cutdyn example --list`) or a
milling case file; the operating point is its [simulate] table (rpm, depth_mm) unless --rpm and
--depth-mm give it. Needs numpy and matplotlib, and the cutdyn package on PYTHONPATH
(build/python after a build).
"""

import argparse
import os
import sys

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.ticker  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import cutdyn  # noqa: E402

# Numbers are printed to 6 significant digits.
FMT = "{:.6g}"
CHATTER_FACTOR = 1.25  # the second trace: this many times the critical depth at the checked speed


def load_case(spec):
    """A built-in example by name, or a case file (TOML)."""
    if spec.endswith(".toml") or os.path.sep in spec:
        return cutdyn.Case.from_toml(spec)
    return cutdyn.example(spec)


def plot_lobes(lobes, checked, path):
    rpm, depth = lobes.spindle_rpm, lobes.critical_depth_mm
    lowest = lobes.lowest
    fig, ax = plt.subplots(figsize=(8, 5))
    ax.plot(rpm, depth, color="C0", lw=1.5, label=f"critical depth ({lobes.method})")
    ax.fill_between(rpm, depth, depth.max() * 1.05, color="C3", alpha=0.08, lw=0,
                    label="chatter (above the lobes)")
    ax.plot(lowest["spindle_rpm"], lowest["critical_depth_mm"], "v", color="k", ms=9,
            clip_on=False, zorder=5, label=f"lowest: {lowest['critical_depth_mm']:.4f} mm at "
                  f"{lowest['spindle_rpm']:.0f} rpm")
    verdict = "stable" if checked.stable else "chatter"
    ax.plot(checked.spindle_rpm, checked.depth_mm, "o", ms=9, zorder=5,
            color="C2" if checked.stable else "C3",
            label=f"check {checked.spindle_rpm:.0f} rpm, {checked.depth_mm:g} mm: {verdict} "
                  f"(margin {checked.margin:+.0%})")
    ax.set_xlabel("spindle speed (rpm)")
    ax.set_ylabel("axial depth of cut (mm)")
    ax.set_title(f"Stability lobes: {lobes.report['source']}")
    ax.set_xlim(rpm.min(), rpm.max())
    ax.set_ylim(0, min(depth.max() * 1.05, 8 * lowest["critical_depth_mm"]))
    ax.grid(alpha=0.3)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.14), ncol=2, fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_sweep(sweep, metric, depth_mm, stable_ranges, path):
    rpm = sweep.values
    chatter = sweep.chatter.astype(bool)
    values = sweep.columns[metric]
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for i, r in enumerate(stable_ranges):
        ax.axvspan(r["rpm_from"], r["rpm_to"], color="C2", alpha=0.12, lw=0,
                   label="stable by the lobes" if i == 0 else None)
    ax.plot(rpm, values, color="0.5", lw=1)
    ax.plot(rpm[~chatter], values[~chatter], "o", color="C2", ms=5, label="simulated: stable")
    ax.plot(rpm[chatter], values[chatter], "x", color="C3", ms=7, mew=2,
            label="simulated: chatter")
    ax.set_yscale("log")
    ax.yaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    ax.yaxis.set_minor_formatter(matplotlib.ticker.FuncFormatter(
        lambda v, _: f"{v:g}" if str(f"{v:g}")[0] in "25" else ""))
    ax.set_xlabel("spindle speed (rpm)")
    ax.set_ylabel("vibration peak-to-peak in x (µm)")
    ax.set_title(f"Speed sweep at {depth_mm:g} mm depth: {sweep.report['source']}")
    ax.grid(alpha=0.3, which="both")
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_traces(runs, rpm, path):
    """runs: [(label, Simulation)]; displacement over the whole run, force over its last
    revolutions."""
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(8, 6.5))
    revolution_s = 60.0 / rpm
    # The larger (chattering) trace first, so that the stable one stays visible on top of it.
    for (label, sim), color, z in zip(runs, ["C2", "C3"], [3, 2]):
        top.plot(sim.time_s, sim.x_um, color=color, lw=0.8, label=label, zorder=z)
        last = sim.time_s >= sim.time_s[-1] - 3 * revolution_s
        bottom.plot(sim.time_s[last] * 1e3, sim.force_n[last], color=color, lw=1, label=label,
                    zorder=z)
    top.set_xlabel("time (s)")
    top.set_ylabel("tool displacement x (µm)")
    top.set_title(f"Simulated cut at {rpm:.0f} rpm: displacement over the whole run")
    bottom.set_xlabel("time (ms)")
    bottom.set_ylabel("resultant cutting force (N)")
    bottom.set_title("Force over the last 3 revolutions")
    for ax in (top, bottom):
        ax.grid(alpha=0.3)
        ax.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out_dir", nargs="?", default=".", help="where the PNGs go (default .)")
    parser.add_argument("--case", default="milling-insperger",
                        help="a built-in milling example or a milling case file")
    parser.add_argument("--rpm", type=float, help="operating speed (default: [simulate] rpm)")
    parser.add_argument("--depth-mm", type=float,
                        help="operating depth of cut (default: [simulate] depth_mm)")
    parser.add_argument("--points", type=int, default=41,
                        help="speeds in the sweep, over the lobes' speed range (default 41)")
    args = parser.parse_args(argv)
    if args.points < 2:
        parser.error("--points: at least 2")
    os.makedirs(args.out_dir, exist_ok=True)

    case = load_case(args.case)
    settings = case.to_dict()
    if settings["process"] != "milling":
        parser.error(f"{args.case}: the sweep and the traces need a milling case")
    point = settings.get("simulate", {})
    rpm = args.rpm if args.rpm is not None else point.get("rpm")
    depth_mm = args.depth_mm if args.depth_mm is not None else point.get("depth_mm")
    if rpm is None or depth_mm is None:
        parser.error(f"{args.case} has no [simulate] rpm and depth_mm: give --rpm and --depth-mm")
    print(f"case: {case.source}")

    # 1. Lobes, with the speed ranges stable at the operating depth, and one check.
    lobes = cutdyn.lobes(case, target_depth_mm=depth_mm)
    lowest = lobes.lowest
    print(f"lobes: {lobes.method}, {len(lobes.spindle_rpm)} speeds "
          f"{FMT.format(lobes.spindle_rpm.min())} to {FMT.format(lobes.spindle_rpm.max())} rpm")
    print(f"lowest critical depth: {FMT.format(lowest['critical_depth_mm'])} mm at "
          f"{FMT.format(lowest['spindle_rpm'])} rpm")
    if "recommended_rpm" in lobes.report:
        print(f"recommended speed at {FMT.format(depth_mm)} mm: "
              f"{FMT.format(lobes.report['recommended_rpm'])} rpm")
    checked = cutdyn.check(case, rpm=rpm, depth_mm=depth_mm)
    print(f"check at {FMT.format(rpm)} rpm, {FMT.format(depth_mm)} mm: "
          f"{'stable' if checked.stable else 'chatter'} (critical depth "
          f"{FMT.format(checked.critical_depth_mm)} mm, margin {FMT.format(checked.margin)})")
    plot_lobes(lobes, checked, os.path.join(args.out_dir, "lobes.png"))

    # 2. A sweep of the spindle speed at the operating depth: one simulation per speed.
    metric = "vibration_pp_x_um"
    speeds = np.linspace(lobes.spindle_rpm.min(), lobes.spindle_rpm.max(), args.points)
    sweep = cutdyn.sweep(case, "simulate.rpm", speeds, metric=metric, depth_mm=depth_mm)
    values = sweep.columns[metric]
    worst = int(np.nanargmax(values))
    print(f"sweep of simulate.rpm at {FMT.format(depth_mm)} mm: {len(speeds)} speeds "
          f"{FMT.format(speeds[0])}:{FMT.format(speeds[1] - speeds[0])}:{FMT.format(speeds[-1])}"
          f" rpm, {int(sweep.chatter.sum())} chatter, largest {metric} "
          f"{FMT.format(values[worst])} at {FMT.format(sweep.values[worst])} rpm")
    plot_sweep(sweep, metric, depth_mm, lobes.report.get("stable_ranges", []),
               os.path.join(args.out_dir, "sweep.png"))

    # 3. Traces at the operating point and above the critical depth at the same speed.
    deep_mm = CHATTER_FACTOR * checked.critical_depth_mm
    runs = []
    for label, depth in [("operating point", depth_mm), ("above the lobes", deep_mm)]:
        sim = cutdyn.simulate(case, rpm=rpm, depth_mm=depth)
        s = sim.summary
        print(f"simulate at {FMT.format(rpm)} rpm, {FMT.format(depth)} mm: {s['verdict']}, "
              f"vibration_pp_x_um {FMT.format(s['vibration_pp_x_um'])}, "
              f"peak_force_n {FMT.format(s['peak_force_n'])}")
        runs.append((f"{depth:.4g} mm ({label}): {s['verdict']}", sim))
    plot_traces(runs, rpm, os.path.join(args.out_dir, "trace.png"))

    print(f"wrote lobes.png, sweep.png, trace.png in {args.out_dir}")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except cutdyn.CaseError as e:  # bad case or request: the command line's message, exit 2
        print(f"{os.path.basename(sys.argv[0])}: {e}", file=sys.stderr)
        sys.exit(2)
