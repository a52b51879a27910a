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
