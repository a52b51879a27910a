"""cutdyn.monitor against `cutdyn monitor`: calibrate, teach and estimate on the same logs give
the command line's files, reports and text; a log given as arrays gives exactly what the same
log as a file gives; bad arrays raise CaseError naming the column and row."""

import os

import numpy as np
import pytest

import cutdyn
from conftest import cli_csv, cli_json, printed, run_cli

KT = 0.16  # N·m/A
INERTIA = 1.5e-3  # kg·m²


def servo_log(segments, seed, dt=1e-3, axes=("x", "y")):
    """A log of constant-speed holds, the columns of a current log: per axis and hold
    (speed rad/s, force N, seconds) phase currents of the torque 0.3·sign ω + 0.002·ω +
    0.0005·F N·m (space-vector measure), with noise on the currents and the speed."""
    rng = np.random.default_rng(seed)
    columns = {k: [] for k in ("time_s", "axis", "iu_a", "iv_a", "iw_a", "speed_rad_s",
                               "force_n")}
    for a, axis in enumerate(axes):
        t, angle = 0.0, 0.0
        for speed, force, hold in segments:
            n = int(round(hold / dt))
            w = np.full(n, float(speed))
            current = (0.3 * np.sign(w) + 0.002 * w + 0.0005 * force) / KT * (1 + 0.1 * a)
            theta = angle + 4 * np.cumsum(w) * dt
            angle = theta[-1]
            columns["time_s"] += list(t + dt * np.arange(n))
            t += n * dt
            columns["axis"] += [axis] * n
            for name, shift in (("iu_a", 0.0), ("iv_a", -2 * np.pi / 3), ("iw_a", 2 * np.pi / 3)):
                columns[name] += list(current * np.cos(theta + shift) + 0.005 * rng.normal(size=n))
            columns["speed_rad_s"] += list(w + 0.02 * rng.normal(size=n))
            columns["force_n"] += [float(force)] * n
    return {k: (v if k == "axis" else np.asarray(v)) for k, v in columns.items()}


IDLE = [(20, 0, 0.4), (60, 0, 0.4), (120, 0, 0.4), (-40, 0, 0.4), (-150, 0, 0.4)]
LOADED = [(50, 0, 0.3), (50, 1500, 0.3), (50, 4000, 0.3), (80, 2500, 0.3), (-60, -3000, 0.3)]


def write_log(columns, path):
    """The columns as a log file, numbers in shortest round-trip form (repr)."""
    names = list(columns)
    with open(path, "w") as f:
        f.write(",".join(names) + "\n")
        for i in range(len(columns["time_s"])):
            f.write(",".join(columns[n][i] if n == "axis" else repr(float(columns[n][i]))
                             for n in names) + "\n")
    return str(path)


@pytest.fixture
def logs(tmp):
    idle = servo_log(IDLE, seed=1)
    loaded = servo_log(LOADED, seed=2)
    cut = servo_log(LOADED[1:3] + LOADED[1:3], seed=3)
    return {"idle": idle, "loaded": loaded, "cut": cut,
            "idle_file": write_log(idle, tmp / "idle.csv"),
            "loaded_file": write_log(loaded, tmp / "loaded.csv"),
            "cut_file": write_log(cut, tmp / "cut.csv")}


def calibrate_cli(logs, tmp):
    code, out, err = run_cli("monitor", "calibrate", "--idle", logs["idle_file"], "--loaded",
                             logs["loaded_file"], "--kt", str(KT), "--inertia", str(INERTIA),
                             "--out", str(tmp / "calib.json"))
    assert code == 0, err
    return out


def test_calibrate_is_the_command_lines_on_files_and_arrays(logs, tmp):
    out = calibrate_cli(logs, tmp)
    from_files = cutdyn.monitor.calibrate(idle=logs["idle_file"], loaded=[logs["loaded_file"]],
                                          kt=KT, inertia=INERTIA)
    assert from_files.calibration == cli_json(tmp / "calib.json")
    from_files.save(tmp / "py.json")
    assert (tmp / "py.json").read_text() == (tmp / "calib.json").read_text()
    assert str(from_files) == printed(out)
    # The same logs as arrays: the same calibration, to the last digit.
    from_arrays = cutdyn.monitor.calibrate(idle=[logs["idle"]], loaded=logs["loaded"],
                                           kt={"x": KT, "y": KT}, inertia=INERTIA)
    assert from_arrays.calibration == from_files.calibration
    # It found the torque of the logs: Tnzm 0.3 N·m and X 0.002 N·m·s/rad on x.
    x = from_files.calibration["axes"]["x"]
    assert x["friction_nm"] == pytest.approx(0.3, rel=0.02)
    assert x["viscous_nm_s_per_rad"] == pytest.approx(0.002, rel=0.05)


def test_estimate_and_teach_are_the_command_lines(logs, tmp):
    calibrate_cli(logs, tmp)
    calib = str(tmp / "calib.json")
    code, out, err = run_cli("monitor", "teach", "--calib", calib, logs["loaded_file"],
                             logs["cut_file"], "--out", str(tmp / "band.json"), "--bin-s", "0.02")
    assert code == 0, err
    band = cutdyn.monitor.teach([logs["loaded_file"], logs["cut_file"]], calib, bin_s=0.02)
    assert band.band == cli_json(tmp / "band.json")
    assert str(band) == printed(out)
    assert band.warnings == [line[len("cutdyn: warning: "):] for line in err.splitlines()]
    # Taught from arrays and a calibration in memory: the same band but for the names.
    in_memory = cutdyn.monitor.teach([logs["loaded"], logs["cut"]],
                                     cutdyn.monitor.calibrate(idle=logs["idle_file"],
                                                              loaded=logs["loaded_file"], kt=KT,
                                                              inertia=INERTIA),
                                     bin_s=0.02)
    assert {**in_memory.band, "calibration": calib} == band.band

    flags = ["--band", str(tmp / "band.json"), "--persist-s", "0.004", "--tooth-frequency-hz",
             "40"]
    code, out, err = run_cli("monitor", "estimate", "--calib", calib, logs["idle_file"], *flags,
                             "--out", str(tmp / "e.csv"), "--json", str(tmp / "e.json"),
                             "--alarms", str(tmp / "a.csv"))
    assert code == 0, err
    est = cutdyn.monitor.estimate(logs["idle_file"], calib, band=str(tmp / "band.json"),
                                  persist_s=0.004, tooth_frequency_hz=40)
    assert est.report == cli_json(tmp / "e.json")
    assert str(est) == printed(out)
    cli = cli_csv(tmp / "e.csv")
    assert list(est.columns) == list(cli)
    assert [float(v) for v in cli["time_s"]] == list(est.time_s)
    assert est.axis == cli["axis"]
    assert est.alarm == cli["alarm"]
    for name in ("force_n", "force_sigma_n", "speed_rad_s", "accel_rad_s2", "level_n", "upper_n",
                 "lower_n"):
        assert est.columns[name].dtype == np.float64
        # The CSV holds 7 significant digits; the arrays full precision.
        np.testing.assert_allclose(est.columns[name], [float(v) for v in cli[name]],
                                   rtol=6e-7, atol=1e-300, err_msg=name)
    alarms = cli_csv(tmp / "a.csv") if os.path.getsize(tmp / "a.csv") > 40 else {}
    assert [a["alarm"] for a in est.alarms] == alarms.get("alarm", [])
    assert len(est.alarms) > 0  # an idle log against the band of a cut: the force is too low
    # The same log as arrays gives the same numbers exactly.
    from_arrays = cutdyn.monitor.estimate(logs["idle"], calib, band=band, persist_s=0.004,
                                          tooth_frequency_hz=40)
    for name, values in est.columns.items():
        if isinstance(values, np.ndarray):
            assert np.array_equal(values, from_arrays.columns[name], equal_nan=True), name
        else:
            assert values == from_arrays.columns[name], name
    assert from_arrays.alarms == est.alarms


def test_estimate_of_drive_currents_on_the_preset():
    # `cutdyn drive`'s motor currents (space-vector, with the rotor angle) through the preset's
    # constants in that measure, as a log in memory.
    currents = cutdyn.drive(cutdyn.example("ermolaev2020"), currents=True).current_log
    lines = [line for line in currents.splitlines() if not line.startswith("#")]
    header = lines[0].split(",")
    rows = [line.split(",") for line in lines[1:]]
    log = {name: ([r[k] for r in rows] if name == "axis" else np.array([float(r[k]) for r in rows]))
           for k, name in enumerate(header)}
    calib = cutdyn.monitor.calibrate(base="zheng2012", measure="space-vector")
    est = cutdyn.monitor.estimate(log, calib)
    assert all(a["torque_current"].startswith("signed") for a in est.report["axes"].values())
    assert len(est.force_n) == len(rows)
    assert np.all(np.isfinite(est.force_n))


def test_bad_logs_and_options_raise_naming_what(logs, tmp):
    calib = "zheng2012"
    bad = dict(logs["cut"])
    bad["iu_a"] = bad["iu_a"].copy()
    bad["iu_a"][3] = np.nan
    with pytest.raises(cutdyn.CaseError, match=r"log: line 5: iu_a = \"?nan"):
        cutdyn.monitor.estimate(bad, calib)
    short = dict(logs["cut"], speed_rad_s=logs["cut"]["speed_rad_s"][:-1])
    with pytest.raises(cutdyn.CaseError, match="speed_rad_s"):
        cutdyn.monitor.estimate(short, calib)
    backwards = dict(logs["cut"], time_s=logs["cut"]["time_s"][::-1].copy())
    with pytest.raises(cutdyn.CaseError, match="line 3"):
        cutdyn.monitor.estimate(backwards, calib)
    skipped = cutdyn.monitor.estimate(bad, calib, on_bad_line="skip")
    assert len(skipped.time_s) == len(logs["cut"]["time_s"]) - 1
    missing = {k: v for k, v in logs["cut"].items() if k != "iw_a"}
    with pytest.raises(cutdyn.CaseError, match="iw_a"):
        cutdyn.monitor.estimate(missing, calib)
    with pytest.raises(cutdyn.CaseError, match="on_bad_line"):
        cutdyn.monitor.estimate(logs["cut"], calib, on_bad_line="ignore")
    with pytest.raises(cutdyn.CaseError, match="bandwidth"):
        cutdyn.monitor.estimate(logs["cut"], calib, bandwidth_hz=-1)
    with pytest.raises(cutdyn.CaseError, match="calib"):
        cutdyn.monitor.estimate(logs["cut"], {"format": "something else"})
    with pytest.raises(cutdyn.CaseError, match="measure"):
        cutdyn.monitor.calibrate(idle=logs["idle"], kt=KT, inertia=INERTIA, measure="dc")
    with pytest.raises(cutdyn.CaseError, match="kt"):
        cutdyn.monitor.calibrate(idle=logs["idle"], kt="abc", inertia=INERTIA)
    with pytest.raises(cutdyn.CaseError, match=r"idle\[0\]"):
        cutdyn.monitor.calibrate(idle=[42], kt=KT, inertia=INERTIA)
    with pytest.raises(cutdyn.CaseError, match="rpm and teeth"):
        cutdyn.monitor.teach([logs["cut"]], calib, rpm=3000)
    with pytest.raises(cutdyn.CaseError, match="nowhere.csv"):
        cutdyn.monitor.estimate(str(tmp / "nowhere.csv"), calib)
