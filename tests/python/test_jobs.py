"""cutdyn.drive, drive_sweep, plan, force, fit and identify against the command line: on every
example, a job the command line runs gives its --json report and its text, arrays its --out
columns to the last digit; a job it refuses raises CaseError with its message."""

import os

import numpy as np
import pytest

import cutdyn
from conftest import assert_columns_equal, cli_csv, cli_json, printed, run_cli, same_as_cli, toml_of

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLES = os.path.join(HERE, "..", "..", "examples")


@pytest.mark.parametrize("name", cutdyn.examples())
def test_plan_and_force_on_every_example(name, tmp):
    same_as_cli("plan", name, cutdyn.plan, tmp)
    same_as_cli("force", name, cutdyn.force, tmp)


def test_plan_with_a_fixed_feed(tmp):
    result = same_as_cli("plan", "bore-plan", lambda c: cutdyn.plan(c, axial_feed_mm=2.5), tmp,
                         "--axial-feed-mm", "2.5")
    assert result.axial_feed_mm == pytest.approx(2.5, rel=1e-12)
    with pytest.raises(cutdyn.CaseError, match="axial_feed_mm"):
        cutdyn.plan(cutdyn.example("bore-plan"), axial_feed_mm=-1)


@pytest.mark.parametrize("name", cutdyn.examples())
def test_drive_on_every_example(name, tmp):
    code, out, err = run_cli("drive", name, "--json", str(tmp / "r.json"), "--out",
                             str(tmp / "t.csv"))
    result = same_as_cli("drive", name, cutdyn.drive, tmp, "--out", str(tmp / "t.csv"))
    if result is not None:
        assert_columns_equal(result.columns, cli_csv(tmp / "t.csv"))
        assert [a["axis"] for a in result.axes] == sorted(set(result.axis), key=result.axis.index)


def test_drive_overrides_and_currents(tmp):
    # The example with current noise on its motors, so that the seed matters.
    data = cutdyn.example("ermolaev2020").to_dict()
    for d in data["drives"]:
        d["current_noise_a"] = 0.01
    case = cutdyn.Case(data)
    (tmp / "noisy.toml").write_text(toml_of(data))
    flags = ["--rpm", "3000", "--depth-mm", "1.5", "--seed", "7"]
    code, out, err = run_cli("drive", str(tmp / "noisy.toml"), *flags, "--json",
                             str(tmp / "r.json"), "--currents", str(tmp / "i.csv"))
    assert code == 0, err
    result = cutdyn.drive(case, rpm=3000, depth_mm=1.5, seed=7, currents=True)
    cli = cli_json(tmp / "r.json")
    assert result.report["axes"] == cli["axes"]
    with open(tmp / "i.csv") as f:
        assert result.current_log == f.read()
    other_seed = cutdyn.drive(case, rpm=3000, depth_mm=1.5, seed=8, currents=True)
    assert other_seed.current_log != result.current_log  # the seed reaches the current noise
    assert other_seed.report == result.report  # and nothing else


def test_drive_sweep_is_the_command_lines(tmp):
    spec = "simulate.rpm=1000:1000:3000"
    code, out, err = run_cli("drive", "ermolaev2020", "--sweep", spec, "--metric", "k_delta",
                             "--out", str(tmp / "w.csv"), "--json", str(tmp / "w.json"))
    assert code == 0, err
    result = cutdyn.drive_sweep(cutdyn.example("ermolaev2020"), "simulate.rpm",
                                np.array([1000.0, 2000.0, 3000.0]), metric="k_delta")
    assert_columns_equal(result.columns, cli_csv(tmp / "w.csv"))
    assert result.report == cli_json(tmp / "w.json")
    assert str(result) == printed(out)


def test_bad_drive_requests_raise():
    case = cutdyn.example("ermolaev2020")
    with pytest.raises(cutdyn.CaseError, match="metric"):
        cutdyn.drive_sweep(case, "simulate.rpm", [1000], metric="colour")
    with pytest.raises(cutdyn.CaseError, match="nope"):
        cutdyn.drive_sweep(case, "drives[0].nope", [1])
    with pytest.raises(cutdyn.CaseError, match="rpm"):
        cutdyn.drive(case, rpm=-1)


FRF_FILES = ["tool_x.frf", "tool_x.csv", "tool_x.uff", "tool_y.frf", "tool_y.uff"]


@pytest.mark.parametrize("file", FRF_FILES)
@pytest.mark.parametrize("options,flags", [({}, []),
                                           ({"modes": 1, "band": (200.0, 1500.0)},
                                            ["--modes", "1", "--band", "200:1500"]),
                                           ({"direction": "y"}, ["--direction", "y"])])
def test_fit_is_the_command_lines(file, options, flags, tmp):
    path = os.path.join(EXAMPLES, "frf", file)
    code, out, err = run_cli("fit", path, *flags, "--json", str(tmp / "f.json"), "--out",
                             str(tmp / "m.toml"))
    assert code == 0, err
    result = cutdyn.fit(path, **options)
    assert result.report == cli_json(tmp / "f.json")
    assert str(result) == printed(out)
    with open(tmp / "m.toml") as f:
        assert result.modes_toml == f.read()
    assert result.receptance_m_per_n.dtype == np.complex128
    assert result.frequency_hz.dtype == np.float64
    assert len(result.fitted_frequency_hz) == len(result.fitted_receptance_m_per_n) > 0
    # The fitted modes rebuild the fitted FRF: the sum of k·ωn²/(ωn² − ω² + 2iζωnω) over them.
    w = 2 * np.pi * result.fitted_frequency_hz
    model = sum(1 / m["stiffness_n_per_m"] * (2 * np.pi * m["natural_hz"]) ** 2 /
                ((2 * np.pi * m["natural_hz"]) ** 2 - w ** 2 +
                 2j * m["damping_ratio"] * 2 * np.pi * m["natural_hz"] * w)
                for m in result.modes)
    peak = np.max(np.abs(result.fitted_receptance_m_per_n))
    assert np.max(np.abs(model - result.fitted_receptance_m_per_n)) < 0.25 * peak


def test_bad_fits_raise_naming_what():
    path = os.path.join(EXAMPLES, "frf", "tool_x.frf")
    for modes in (0, -1, "three", 2.5):
        with pytest.raises(cutdyn.CaseError, match="modes"):
            cutdyn.fit(path, modes=modes)
    with pytest.raises(cutdyn.CaseError, match="direction"):
        cutdyn.fit(path, direction="z")
    with pytest.raises(cutdyn.CaseError, match="format"):
        cutdyn.fit(path, format="xls")
    with pytest.raises(cutdyn.CaseError, match="band"):
        cutdyn.fit(path, band=(900.0, 100.0))
    with pytest.raises(cutdyn.CaseError, match="missing.frf"):
        cutdyn.fit(os.path.join(EXAMPLES, "frf", "missing.frf"))


def test_identify_is_the_command_lines(tmp):
    forces = os.path.join(EXAMPLES, "forces", "milling-insperger-mean-forces.csv")
    code, out, err = run_cli("identify", "milling-insperger", forces, "--json",
                             str(tmp / "i.json"), "--out", str(tmp / "c.toml"))
    assert code == 0, err
    result = cutdyn.identify(cutdyn.example("milling-insperger"), forces)
    assert result.report == cli_json(tmp / "i.json")
    assert str(result) == printed(out)
    with open(tmp / "c.toml") as f:
        assert result.cutting_toml == f.read()
    # The [cutting] table it writes is a case file's: the case with it loads.
    with pytest.raises(cutdyn.CaseError, match="force"):
        cutdyn.identify(cutdyn.example("milling-insperger"), [])
    with pytest.raises(cutdyn.CaseError, match="nowhere.csv"):
        cutdyn.identify(cutdyn.example("milling-insperger"), ["nowhere.csv"])
