"""The Python examples (examples/python) run as a user runs them. The script writes its figures
and prints numbers that are the module's and the command line's to the digits it prints; the
notebook, saved without outputs, runs top to bottom in a python3 Jupyter kernel and draws its
figures. Both run in a temporary directory, never in the source tree."""

import importlib.util
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import cutdyn
from conftest import cli_json, run_cli

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "python"
SCRIPT = EXAMPLES / "lobes_sweep_trace.py"
NOTEBOOK = EXAMPLES / "cutdyn_tour.ipynb"
FIGURES = ["lobes.png", "sweep.png", "trace.png"]
PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
NUMBER = r"([-+0-9.eE]+)"


def fmt(x):
    """A number as the examples print it (6 significant digits)."""
    return f"{x:.6g}"


def example_env(tmp):
    """The environment of a user who put the built package on PYTHONPATH: the folder this
    test imported cutdyn from first; matplotlib's and Jupyter's own files in tmp."""
    env = dict(os.environ)
    package_dir = str(Path(cutdyn.__file__).resolve().parents[1])
    env["PYTHONPATH"] = os.pathsep.join(p for p in [package_dir, env.get("PYTHONPATH")] if p)
    env["MPLCONFIGDIR"] = str(tmp / "matplotlib")
    env["IPYTHONDIR"] = str(tmp / "ipython")
    env["JUPYTER_RUNTIME_DIR"] = str(tmp / "jupyter-runtime")
    env["PYDEVD_DISABLE_FILE_VALIDATION"] = "1"  # the kernel's debugger warns about frozen modules
    return env


def assert_png(path, min_bytes=20_000):
    data = Path(path).read_bytes()
    assert data[:8] == PNG_SIGNATURE, path
    assert len(data) > min_bytes, (path, len(data))


def line(out, pattern):
    """The groups of the one printed line that matches pattern."""
    found = [m for m in (re.fullmatch(pattern, l) for l in out.splitlines()) if m]
    assert len(found) == 1, (pattern, out)
    return found[0].groups()


@pytest.fixture(scope="module")
def script_run(tmp_path_factory):
    """Runs the script once as `python3 lobes_sweep_trace.py OUT`; returns (OUT, stdout)."""
    tmp = tmp_path_factory.mktemp("script")
    out_dir = tmp / "figures"
    p = subprocess.run([sys.executable, str(SCRIPT), str(out_dir)], capture_output=True,
                       text=True, cwd=tmp, env=example_env(tmp), timeout=120, check=False)
    assert p.returncode == 0, p.stdout + p.stderr
    return out_dir, p.stdout


@pytest.fixture(scope="module")
def script_module():
    """The script as a module (its constants), without running main nor writing its bytecode
    into the source tree."""
    spec = importlib.util.spec_from_file_location("lobes_sweep_trace", SCRIPT)
    module = importlib.util.module_from_spec(spec)
    dont_write, sys.dont_write_bytecode = sys.dont_write_bytecode, True
    try:
        spec.loader.exec_module(module)
    finally:
        sys.dont_write_bytecode = dont_write
    return module


def test_script_writes_its_figures(script_run):
    out_dir, out = script_run
    for name in FIGURES:
        assert_png(out_dir / name)
    assert sorted(os.listdir(out_dir)) == sorted(FIGURES)
    assert f"wrote {', '.join(FIGURES)} in {out_dir}" in out


def test_script_lowest_depth_is_the_modules_and_the_command_lines(script_run, tmp):
    _, out = script_run
    depth, rpm = line(out, rf"lowest critical depth: {NUMBER} mm at {NUMBER} rpm")
    module = cutdyn.lobes(cutdyn.example("milling-insperger")).lowest
    code, _, err = run_cli("lobes", "milling-insperger", "--json", str(tmp / "l.json"))
    assert code == 0, err
    cli = cli_json(tmp / "l.json")["lowest"]
    for lowest in (module, cli):
        assert (depth, rpm) == (fmt(lowest["critical_depth_mm"]), fmt(lowest["spindle_rpm"]))


def test_script_check_is_the_command_lines(script_run, tmp):
    _, out = script_run
    rpm, depth, verdict, critical, margin = line(
        out, rf"check at {NUMBER} rpm, {NUMBER} mm: (stable|chatter) "
             rf"\(critical depth {NUMBER} mm, margin {NUMBER}\)")
    point = cutdyn.example("milling-insperger").to_dict()["simulate"]  # the operating point
    assert (rpm, depth) == (fmt(point["rpm"]), fmt(point["depth_mm"]))
    code, _, err = run_cli("check", "milling-insperger", "--rpm", repr(point["rpm"]),
                           "--depth-mm", repr(point["depth_mm"]), "--json", str(tmp / "c.json"))
    assert code == 0, err
    cli = cli_json(tmp / "c.json")
    assert verdict == ("stable" if cli["stable"] else "chatter")
    assert (critical, margin) == (fmt(cli["critical_depth_mm"]), fmt(cli["margin"]))


def test_script_sweep_is_the_command_lines(script_run, tmp):
    _, out = script_run
    depth, count, start, step, stop, chatter, metric, worst, worst_rpm = line(
        out, rf"sweep of simulate.rpm at {NUMBER} mm: {NUMBER} speeds {NUMBER}:{NUMBER}:{NUMBER}"
             rf" rpm, {NUMBER} chatter, largest (\w+) {NUMBER} at {NUMBER} rpm")
    code, _, err = run_cli("simulate", "milling-insperger", "--sweep",
                           f"simulate.rpm={start}:{step}:{stop}", "--depth-mm", depth,
                           "--metric", metric, "--json", str(tmp / "w.json"))
    assert code == 0, err
    points = cli_json(tmp / "w.json")["points"]
    assert len(points) == int(count) > 10
    assert int(chatter) == sum(p["chatter"] for p in points)
    largest = max(points, key=lambda p: p[metric])
    assert (worst, worst_rpm) == (fmt(largest[metric]), fmt(largest["value"]))


def test_script_traces_are_the_command_lines(script_run, script_module, tmp):
    _, out = script_run
    runs = re.findall(rf"simulate at {NUMBER} rpm, {NUMBER} mm: (\w+), vibration_pp_x_um "
                      rf"{NUMBER}, peak_force_n {NUMBER}", out)
    point = cutdyn.example("milling-insperger").to_dict()["simulate"]
    code, _, err = run_cli("check", "milling-insperger", "--rpm", repr(point["rpm"]),
                           "--depth-mm", repr(point["depth_mm"]), "--json", str(tmp / "c.json"))
    assert code == 0, err
    critical = cli_json(tmp / "c.json")["critical_depth_mm"]
    depths = [point["depth_mm"], script_module.CHATTER_FACTOR * critical]
    assert [(r[0], r[1]) for r in runs] == [(fmt(point["rpm"]), fmt(d)) for d in depths]
    verdicts = []
    for (_, _, verdict, vibration, peak), depth in zip(runs, depths):
        code, _, err = run_cli("simulate", "milling-insperger", "--rpm", repr(point["rpm"]),
                               "--depth-mm", repr(depth), "--json", str(tmp / "s.json"))
        assert code == 0, err
        summary = cli_json(tmp / "s.json")["summary"]
        assert (verdict, vibration, peak) == (summary["verdict"],
                                              fmt(summary["vibration_pp_x_um"]),
                                              fmt(summary["peak_force_n"]))
        verdicts.append(verdict)
    assert verdicts == ["stable", "chatter"]  # what the figure and its legend show


def test_notebook_is_saved_without_outputs():
    nbformat = pytest.importorskip("nbformat")
    nb = nbformat.read(NOTEBOOK, as_version=4)
    nbformat.validate(nb)
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert code and all(not c.outputs and c.execution_count is None for c in code)
    assert nb.metadata.kernelspec.name == "python3"


def test_notebook_runs_top_to_bottom(tmp):
    pytest.importorskip("nbconvert")
    pytest.importorskip("ipykernel")
    nbformat = pytest.importorskip("nbformat")
    # A copy in tmp: the kernel runs in the notebook's folder, and nbconvert writes beside it.
    source = tmp / NOTEBOOK.name
    shutil.copy(NOTEBOOK, source)
    p = subprocess.run([sys.executable, "-m", "nbconvert", "--to", "notebook", "--execute",
                        "--ExecutePreprocessor.timeout=120",
                        "--ExecutePreprocessor.kernel_name=python3",
                        "--output-dir", str(tmp / "executed"), "--output", "tour.ipynb",
                        str(source)],
                       capture_output=True, text=True, cwd=tmp, env=example_env(tmp),
                       timeout=300, check=False)
    assert p.returncode == 0, p.stderr[-3000:]
    nb = nbformat.read(tmp / "executed" / "tour.ipynb", as_version=4)
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs]
    errors = [o for o in outputs if o.output_type == "error"]
    assert not errors, [(o.ename, o.evalue) for o in errors]
    assert all(c.execution_count for c in nb.cells if c.cell_type == "code")
    images = [o for o in outputs if "image/png" in o.get("data", {})]
    assert len(images) >= 4
    text = "".join(o.get("text", "") for o in outputs if o.output_type == "stream")
    lowest = cutdyn.lobes(cutdyn.example("milling-insperger")).lowest
    assert (f"lowest critical depth: {fmt(lowest['critical_depth_mm'])} mm at "
            f"{fmt(lowest['spindle_rpm'])} rpm") in text
