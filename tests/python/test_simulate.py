"""cutdyn.simulate against `cutdyn simulate` on the simulation examples: the traces are the
--out CSV's columns to the last printed digit, the report is its --json, the text its text."""

import numpy as np
import pytest

import cutdyn
from conftest import cli_csv, cli_json, run_cli


@pytest.mark.parametrize("name,args", [("milling-insperger", {}),
                                       ("milling-insperger", {"rpm": 9000, "depth_mm": 0.08}),
                                       ("ermolaev2020", {}),
                                       ("ermolaev2020-fig6a", {}),
                                       ("turning-conventional", {}),
                                       ("turning-ultrasonic", {"duration_s": 0.2})])
def test_simulate_is_the_command_lines(name, args, tmp):
    flags = []
    for key, value in args.items():
        flags += ["--" + key.replace("_", "-"), str(value)]
    code, out, err = run_cli("simulate", name, *flags, "--out", str(tmp / "s.csv"), "--json",
                             str(tmp / "s.json"))
    assert code == 0, err
    cli = cli_csv(tmp / "s.csv")
    sim = cutdyn.simulate(cutdyn.example(name), **args)
    assert list(sim.columns) == list(cli)
    for column, values in sim.columns.items():
        if isinstance(values, np.ndarray):
            assert values.dtype == np.float64, column
            assert [float(v) for v in cli[column]] == [float(v) for v in values], column
        else:
            assert list(values) == cli[column], column
    assert sim.report == cli_json(tmp / "s.json")
    assert str(sim) == "".join(l for l in out.splitlines(True) if "wrote " not in l)


def test_simulation_summary_and_verdict():
    sim = cutdyn.simulate(cutdyn.example("milling-insperger"), depth_mm=0.08)
    assert sim.summary["chatter"] is True
    assert "CHATTER" in str(sim)
    turning = cutdyn.simulate(cutdyn.example("turning-ultrasonic"), duration_s=0.2)
    assert [r["process"] for r in turning.results] == ["vibration-assisted", "conventional"]
    assert set(turning.process) == {"vibration-assisted", "conventional"}


def test_bad_simulation_requests_raise():
    case = cutdyn.example("milling-insperger")
    with pytest.raises(cutdyn.CaseError, match="rpm"):
        cutdyn.simulate(case, rpm=-5)
    with pytest.raises(cutdyn.CaseError, match="depth_mm"):
        cutdyn.simulate(case, depth_mm=0)


@pytest.mark.parametrize("name,spec,metric", [
    ("ermolaev2020-fig6a", "force_law.t2_s=0:0.1:0.5", "cutting_force_pulsation"),
    ("milling-insperger", "simulate.depth_mm=0.02:0.02:0.1", "vibration_pp_x_um"),
])
def test_sweep_is_the_command_lines(name, spec, metric, tmp):
    code, out, err = run_cli("simulate", name, "--sweep", spec, "--metric", metric, "--out",
                             str(tmp / "w.csv"), "--json", str(tmp / "w.json"))
    assert code == 0, err
    cli = cli_csv(tmp / "w.csv")
    key, rng = spec.split("=")
    start, step, stop = (float(x) for x in rng.split(":"))
    values = np.round(np.arange(start, stop + step / 2, step), 12)
    result = cutdyn.sweep(cutdyn.example(name), key, values, metric=metric)
    assert list(result.columns) == list(cli)
    for column, array in result.columns.items():
        expected = [float(v) if v != "" else np.nan for v in cli[column]]
        assert np.array_equal(np.asarray(expected), array, equal_nan=True), column
    assert result.report == cli_json(tmp / "w.json")
    assert list(result.values) == list(values)
    assert str(result) == "".join(l for l in out.splitlines(True) if "wrote " not in l)


def test_bad_sweeps_raise_naming_what():
    case = cutdyn.example("milling-insperger")
    with pytest.raises(cutdyn.CaseError, match="nope"):
        cutdyn.sweep(case, "tool.nope", [1, 2])
    with pytest.raises(cutdyn.CaseError, match="metric"):
        cutdyn.sweep(case, "tool.teeth", [2, 3], metric="colour")
    with pytest.raises(cutdyn.CaseError, match="milling"):
        cutdyn.sweep(cutdyn.example("turning-conventional"), "simulate.rpm", [1000])
