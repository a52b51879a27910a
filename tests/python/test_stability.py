"""cutdyn.lobes and cutdyn.check against the command line on every stability example: the
same numbers (the lobes to the last digit the CSV prints), float64 arrays, and the same
reports."""

import os
import re

import numpy as np
import pytest

import cutdyn
from conftest import assert_columns_equal, cli_csv, cli_json, printed, run_cli, same_as_cli

# Every built-in case the lobes command runs on (the plan case has no lobes; the FRF case
# reads files relative to the examples folder).
STABILITY_EXAMPLES = [
    "milling-insperger",
    "milling-variable-pitch",
    "turning-conventional",
    "turning-ultrasonic",
    "turning-ultrasonic-speed",
]


def shortest(x):
    """A number as the CSV prints it: the shortest text that reads back to it."""
    return repr(float(x))


@pytest.mark.parametrize("name", STABILITY_EXAMPLES)
def test_lobes_are_the_command_lines_to_the_last_digit(name, tmp):
    code, _, err = run_cli("lobes", name, "--out", str(tmp / "l.csv"), "--json",
                           str(tmp / "l.json"))
    assert code == 0, err
    cli = cli_csv(tmp / "l.csv")
    lobes = cutdyn.lobes(cutdyn.example(name))
    assert list(lobes.columns) == list(cli)
    for column, values in lobes.columns.items():
        if isinstance(values, np.ndarray):
            assert values.dtype in (np.float64, np.int64), column
            assert values.shape == (len(cli[column]),)
            assert [float(v) for v in cli[column]] == [float(v) for v in values], column
        else:
            assert list(values) == cli[column], column
    report = cli_json(tmp / "l.json")
    for key in ("method", "lowest", "command", "schema_version"):
        assert lobes.report[key] == report[key], key
    assert lobes.method == report["method"]


def without_timing(text):
    """The report's text without the seconds the run took (", 0.16 s")."""
    return re.sub(r", [0-9.]+ s\b", ", … s", text)


def test_lobes_text_and_pandas():
    lobes = cutdyn.lobes(cutdyn.example("milling-insperger"), target_depth_mm=0.5)
    code, out, _ = run_cli("lobes", "milling-insperger", "--target-depth-mm", "0.5")
    assert code == 0
    assert without_timing(str(lobes)) == without_timing(out)
    assert lobes.report["target_depth_mm"] == 0.5
    pandas = pytest.importorskip("pandas")
    frame = lobes.to_pandas()
    assert isinstance(frame, pandas.DataFrame)
    assert np.array_equal(frame["critical_depth_mm"].to_numpy(), lobes.critical_depth_mm)


@pytest.mark.parametrize("name,rpm,depth", [("milling-insperger", 10000, 0.5),
                                           ("milling-insperger", 10000, 0.05),
                                           ("turning-conventional", 1500, 2.0),
                                           ("turning-ultrasonic", 1500, 2.0)])
def test_check_is_the_command_lines(name, rpm, depth, tmp):
    code, out, err = run_cli("check", name, "--rpm", str(rpm), "--depth-mm", str(depth),
                             "--json", str(tmp / "c.json"))
    assert code == 0, err
    report = cli_json(tmp / "c.json")
    result = cutdyn.check(cutdyn.example(name), rpm=rpm, depth_mm=depth)
    assert result.report == report
    assert result.stable == report["stable"]
    # The command line's text, without the line that names the file --json wrote.
    assert str(result) == "".join(l for l in out.splitlines(True) if "wrote " not in l)


@pytest.mark.parametrize("method", ["zero-order", "multi-frequency", "full-discretization"])
def test_methods_by_name(method, tmp):
    code, _, err = run_cli("lobes", "milling-insperger", "--method", method, "--out",
                           str(tmp / "l.csv"))
    assert code == 0, err
    cli = cli_csv(tmp / "l.csv")
    lobes = cutdyn.lobes(cutdyn.example("milling-insperger"), method=method)
    assert lobes.method == method
    assert [float(v) for v in cli["critical_depth_mm"]] == list(lobes.critical_depth_mm)


EXAMPLES_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples")


@pytest.mark.parametrize("name", cutdyn.examples())
def test_lobes_check_and_simulate_on_every_example(name, tmp):
    # Where the command line runs, the same report and text; where it refuses, the same
    # problems. (The lobes report states the seconds it took; the rest is the same.)
    def lobes(case):
        result = cutdyn.lobes(case)
        result.report.pop("seconds", None)
        return result

    code, out, err = run_cli("lobes", name, "--json", str(tmp / "l.json"))
    if code == 0:
        report = cli_json(tmp / "l.json")
        report.pop("seconds", None)
        result = lobes(cutdyn.example(name))
        assert result.report == report
        assert without_timing(str(result)) == without_timing(printed(out))
    else:
        same_as_cli("lobes", name, lobes, tmp)
    same_as_cli("check", name, lambda c: cutdyn.check(c, rpm=6000, depth_mm=0.5), tmp,
                "--rpm", "6000", "--depth-mm", "0.5")
    same_as_cli("simulate", name, lambda c: cutdyn.simulate(c, duration_s=0.05), tmp,
                "--duration-s", "0.05")


def test_a_case_with_measured_frfs(tmp):
    # The measured-FRF example reads its files relative to its own folder.
    path = os.path.join(EXAMPLES_DIR, "frf", "milling-measured.toml")
    code, out, err = run_cli("lobes", path, "--out", str(tmp / "l.csv"))
    assert code == 0, err
    lobes = cutdyn.lobes(cutdyn.Case.from_toml(path))
    assert_columns_equal(lobes.columns, cli_csv(tmp / "l.csv"))
