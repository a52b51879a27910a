"""Cases from TOML, from dicts and from the examples: the same case whichever way, and bad
input raises cutdyn.CaseError (a ValueError) with the command line's message, naming the key."""

import copy

import numpy as np
import pytest

import cutdyn
from conftest import run_cli

EXAMPLES_WITHOUT_FILES = [n for n in cutdyn.examples() if n != "bore-plan"]


def test_examples_are_the_command_lines_list():
    code, out, _ = run_cli("example", "--list")
    assert code == 0
    for name in cutdyn.examples():
        assert name in out


@pytest.mark.parametrize("name", cutdyn.examples())
def test_dict_and_toml_cases_agree(name, tmp):
    code, text, _ = run_cli("example", name)
    assert code == 0
    (tmp / "case.toml").write_text(text)
    from_toml = cutdyn.Case.from_toml(str(tmp / "case.toml"))
    from_example = cutdyn.example(name)
    as_dict = from_example.to_dict()
    if "frf" in as_dict:
        pytest.skip("its [[frf]] files are relative to the examples folder")
    assert from_toml.to_dict() == as_dict
    assert cutdyn.Case(as_dict).to_dict() == as_dict


def test_a_case_from_a_dict_gives_the_same_lobes(tmp):
    # A dict and the TOML file with the same values give the same numbers, to the last digit.
    d = cutdyn.example("milling-insperger").to_dict()
    toml = [f"process = {d['process']!r}".replace("'", '"')]
    for mode in d["modes"]:
        toml.append("[[modes]]")
        toml += [f"{k} = {v!r}".replace("'", '"') for k, v in mode.items()]
    for table in ("cutting", "tool", "operation", "lobes"):
        toml.append(f"[{table}]")
        toml += [f"{k} = {v!r}".replace("'", '"').replace("True", "true").replace("False", "false")
                 for k, v in d[table].items()]
    (tmp / "same.toml").write_text("\n".join(toml) + "\n")
    a = cutdyn.lobes(cutdyn.Case(d))
    b = cutdyn.lobes(cutdyn.Case.from_toml(str(tmp / "same.toml")))
    assert list(a.critical_depth_mm) == list(b.critical_depth_mm)
    # The echo (to_dict, like the --json case) rounds to 15 digits (natural_hz 228.8…): the
    # example itself agrees to 1e-9 (measured 8.4e-11: the depth search, whose own tolerance is
    # 1e-3, takes a slightly different path after a 1e-15 change of the modes).
    c = cutdyn.lobes(cutdyn.example("milling-insperger"))
    assert np.allclose(a.critical_depth_mm, c.critical_depth_mm, rtol=1e-9, atol=0)


def expect_case_error(call, *needles):
    with pytest.raises(cutdyn.CaseError) as info:
        call()
    assert isinstance(info.value, ValueError)
    for needle in needles:
        assert needle in str(info.value), str(info.value)
    return info.value


def test_bad_values_raise_naming_the_key():
    d = cutdyn.example("milling-insperger").to_dict()
    bad = copy.deepcopy(d)
    bad["modes"][0]["natural_hz"] = -3
    bad["tool"]["teeth"] = "four"
    e = expect_case_error(lambda: cutdyn.Case(bad), "dict: modes[0].natural_hz = -3",
                          "tool.teeth")
    assert e.where == "dict"
    assert len(e.problems) == 2
    unknown = copy.deepcopy(d)
    unknown["tool"]["colour"] = "red"
    expect_case_error(lambda: cutdyn.Case(unknown), "tool.colour")
    expect_case_error(lambda: cutdyn.Case({"process": "milling", "modes": [{"x": float("nan")}]}),
                      "not a case")
    # An int no double holds (JSON's reader overflows): a CaseError, not another exception.
    expect_case_error(lambda: cutdyn.Case({"process": "milling", "lobes": {"rpm_max": 10**400}}),
                      "not a case")


def test_file_errors_are_the_command_lines(tmp):
    path = tmp / "bad.toml"
    path.write_text('process = "milling"\n[[modes]]\ndirection = "x"\nnatural_hz = -3\n'
                    'damping_ratio = 0.01\nstiffness_n_per_m = 1e7\n')
    code, _, err = run_cli("lobes", str(path))
    assert code == 2
    e = expect_case_error(lambda: cutdyn.Case.from_toml(str(path)))
    # The command line prints "cutdyn: error: " before each of the same lines.
    assert [line.removeprefix("cutdyn: error: ") for line in err.strip().splitlines()] == \
        str(e).splitlines()
    expect_case_error(lambda: cutdyn.Case.from_toml(str(tmp / "missing.toml")), "missing.toml")
    expect_case_error(lambda: cutdyn.example("nope"), "no built-in example called")


def test_bad_requests_raise_naming_the_argument():
    case = cutdyn.example("milling-insperger")
    expect_case_error(lambda: cutdyn.lobes(case, method="nope"), "method")
    expect_case_error(lambda: cutdyn.check(case, rpm=-1, depth_mm=0.5), "rpm")
    expect_case_error(lambda: cutdyn.lobes(case, target_depth_mm=-1), "target_depth_mm")


def test_a_case_with_measured_frfs_round_trips_from_any_folder(tmp, monkeypatch):
    # The echo names the FRF files it read by their absolute paths: the dict of a case file
    # whose [[frf]] files are relative to it is the same case from any working folder.
    import os
    import shutil

    here = os.path.dirname(os.path.abspath(__file__))
    measured = os.path.join(here, "..", "..", "examples", "frf")
    for name in ("milling-measured.toml", "tool_x.csv", "tool_y.csv"):
        shutil.copy(os.path.join(measured, name), tmp / name)
    case = cutdyn.Case.from_toml(str(tmp / "milling-measured.toml"))
    d = case.to_dict()
    assert [f["file"] for f in d["frf"]] == [str(tmp / "tool_x.csv"), str(tmp / "tool_y.csv")]
    elsewhere = tmp / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)
    again = cutdyn.Case(d)
    assert again.to_dict() == d
    a = cutdyn.check(case, rpm=12000, depth_mm=0.2)
    b = cutdyn.check(again, rpm=12000, depth_mm=0.2)
    assert a.critical_depth_mm == b.critical_depth_mm


def test_results_have_a_readable_repr():
    case = cutdyn.example("milling-insperger")
    lobes = cutdyn.lobes(case, method="zero-order")
    text = repr(lobes)
    assert text.startswith("<cutdyn.Lobes: cutdyn lobes: example milling-insperger"), text
    assert f"{len(lobes.spindle_rpm)} rows of spindle_rpm, critical_depth_mm" in text, text
    assert lobes._repr_html_().startswith("<pre>cutdyn lobes: example milling-insperger")
    check = cutdyn.check(case, rpm=10000, depth_mm=0.05)
    assert repr(check).startswith("<cutdyn.Check: cutdyn check: example milling-insperger"), \
        repr(check)
