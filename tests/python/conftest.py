"""Shared helpers: the cutdyn executable built beside the module (CUTDYN), run as a user would."""

import csv
import json
import os
import re
import subprocess

import numpy as np
import pytest

import cutdyn

CUTDYN = os.environ.get("CUTDYN", "cutdyn")


def run_cli(*args, cwd=None):
    """Runs the command line; returns (exit code, stdout, stderr)."""
    p = subprocess.run([CUTDYN, *args], capture_output=True, text=True, cwd=cwd, check=False)
    return p.returncode, p.stdout, p.stderr


def cli_csv(path):
    """A CSV file the command line wrote, as {column: [str, ...]}."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return {name: [row[name] for row in rows] for name in rows[0]}


def cli_json(path):
    with open(path) as f:
        return json.load(f)


def printed(out):
    """What a command printed, less the "wrote FILE" lines of its outputs."""
    return "".join(line for line in out.splitlines(True) if "wrote " not in line)


def cli_errors(err):
    """The problems the command line named, "where: problem" each (its stderr less the
    "cutdyn: error: " prefix)."""
    return [line[len("cutdyn: error: "):] for line in err.splitlines()
            if line.startswith("cutdyn: error: ")]


def as_python(report, flags):
    """The command line's report with its flags named as the Python arguments
    (--axial-feed-mm → axial_feed_mm), which the messages of a request name."""
    text = json.dumps(report)
    for flag in flags:
        if flag.startswith("--"):
            text = text.replace(flag, flag[2:].replace("-", "_"))
    return json.loads(text)


def same_as_cli(job, name, run, tmp, *flags):
    """Runs `cutdyn JOB NAME FLAGS --json` and `run(case)`; both succeed with the same report
    and text, or both refuse with the same problems."""
    code, out, err = run_cli(job, name, *flags, "--json", str(tmp / "r.json"))
    if code == 0:
        result = run(cutdyn.example(name))
        assert result.report == as_python(cli_json(tmp / "r.json"), flags)
        assert str(result) == as_python(printed(out), flags)
        return result
    assert code == 2, err
    with pytest.raises(cutdyn.CaseError) as raised:
        run(cutdyn.example(name))
    problems = str(raised.value).splitlines()
    # The problems are the same, but for names: the command line names the case "example
    # NAME", its flags "--depth-mm" and its request "command line"; Python names the arguments
    # "depth_mm" and the request "request".
    def named(p):
        p = p.replace(f"example {name}: ", "").replace("command line: ", "request: ")
        return re.sub(r"--([a-z][a-z-]*)", lambda m: m.group(1).replace("-", "_"), p)

    assert [named(p) for p in cli_errors(err)] == [named(p) for p in problems], (err, problems)
    return None


def toml_of(data):
    """A case dict as a case file (tables, arrays of tables, scalars: what to_dict gives)."""
    def value(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return json.dumps(v)
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        return repr(v)

    lines = [f"{k} = {value(v)}" for k, v in data.items() if not isinstance(v, (dict, list))
             or (isinstance(v, list) and not (v and isinstance(v[0], dict)))]
    for k, v in data.items():
        if isinstance(v, dict):
            lines.append(f"[{k}]")
            lines += [f"{kk} = {value(vv)}" for kk, vv in v.items()]
        elif isinstance(v, list) and v and isinstance(v[0], dict):
            for item in v:
                lines.append(f"[[{k}]]")
                lines += [f"{kk} = {value(vv)}" for kk, vv in item.items()]
    return "\n".join(lines) + "\n"


def assert_columns_equal(columns, cli):
    assert list(columns) == list(cli)
    for name, values in columns.items():
        if isinstance(values, np.ndarray):
            assert values.dtype in (np.float64, np.int64), name
            expected = np.asarray([float(v) if v != "" else np.nan for v in cli[name]])
            assert np.array_equal(expected, values, equal_nan=True), name
        else:
            assert list(values) == cli[name], name


@pytest.fixture
def tmp(tmp_path):
    return tmp_path
