"""`cutdyn sweep` under `mpirun --oversubscribe -n 2`: the file equals the single-process
file byte for byte; a failing variant is reported and the rest complete; a sweep stopped by
a signal is finished by `--resume` (under MPI too) to the same file. Skipped when mpirun is
missing (./run installs openmpi-bin)."""

import os
import shutil
import signal
import subprocess
import time

import pytest

CUTDYN = os.environ.get("CUTDYN", "cutdyn")
MPIRUN = shutil.which("mpirun")
pytestmark = pytest.mark.skipif(not MPIRUN, reason="needs mpirun (openmpi-bin)")
# As root (a container, CI), OpenMPI wants to be told that is meant.
ENV = {**os.environ, "OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
       "OMPI_MCA_rmaps_base_oversubscribe": "1"}
SWEEP = ["sweep", "--vary", "modes[0].damping_ratio=-0.01:0.01:0.04", "--vary",
         "tool.teeth=2:1:3", "--method", "zero-order", "--threads", "1"]


# In a sanitized build (./run test --sanitize) the ranks under mpirun run without leak
# detection: OpenMPI's plugins are opened with dlopen and closed before the process ends, so
# the allocations they keep for the process's life are reported from an unknown module, which
# no suppression can name. The same sweeps run in one process (no mpirun) keep it.
MPI_ENV = {**ENV, "ASAN_OPTIONS": ENV.get("ASAN_OPTIONS", "") + ":detect_leaks=0"}


def run(*args, mpi=0):
    command = ([MPIRUN, "--oversubscribe", "-n", str(mpi)] if mpi else []) + [CUTDYN, *args]
    p = subprocess.run(command, capture_output=True, text=True, env=MPI_ENV if mpi else ENV,
                       timeout=600)
    return p.returncode, p.stdout, p.stderr


@pytest.fixture(scope="module")
def serial(tmp_path_factory):
    path = tmp_path_factory.mktemp("serial") / "s.csv"
    code, out, err = run(*SWEEP, "--out", str(path))
    assert code == 0, err
    return path.read_bytes()


def test_mpi_file_is_the_serial_file(serial, tmp_path):
    code, out, err = run(*SWEEP, "--out", str(tmp_path / "m.csv"), mpi=2)
    assert code == 0, err
    assert "on 2 ranks" in out
    assert (tmp_path / "m.csv").read_bytes() == serial
    # One rank is the serial run.
    code, out, err = run(*SWEEP, "--out", str(tmp_path / "one.csv"), mpi=1)
    assert code == 0, err
    assert (tmp_path / "one.csv").read_bytes() == serial


def test_full_discretization_on_default_threads_is_the_serial_file(tmp_path):
    # Each rank takes its share of the cores (here 1 thread under -n 2, 2 threads alone): the
    # warm-started lobes must not depend on the threads (they did before 2026-11-24).
    sweep = ["sweep", "--vary", "tool.teeth=2:1:3", "--vary", "lobes.rpm_steps=60:20:80",
             "--method", "full-discretization"]
    code, out, err = run(*sweep, "--out", str(tmp_path / "s.csv"))
    assert code == 0, err
    code, out, err = run(*sweep, "--out", str(tmp_path / "m.csv"), mpi=2)
    assert code == 0, err
    assert "on 2 ranks" in out
    assert (tmp_path / "m.csv").read_bytes() == (tmp_path / "s.csv").read_bytes()
    code, out, err = run(*sweep, "--threads", "1", "--out", str(tmp_path / "t.csv"))
    assert code == 0, err
    assert (tmp_path / "t.csv").read_bytes() == (tmp_path / "s.csv").read_bytes()


def test_a_failing_variant_is_reported_and_the_rest_complete(serial, tmp_path):
    code, out, err = run(*SWEEP, "--out", str(tmp_path / "m.csv"), mpi=2)
    assert code == 0, err
    assert "4 failed" in out and "4 variants failed" in err  # damping -0.01 and 0 (none to damp)
    lines = (tmp_path / "m.csv").read_text().splitlines()
    failed = [l for l in lines if l.startswith("-0.01,")]
    assert len(failed) == 2 and all("damping_ratio" in l for l in failed)
    assert len([l for l in lines if l.startswith("0,")]) == 2
    assert sum(l.startswith("0.04,3,") for l in lines) > 100  # the last variant is complete
    assert err.count("cutdyn: error") == 0


def test_resume_finishes_a_stopped_mpi_sweep(serial, tmp_path):
    out_csv = tmp_path / "r.csv"
    partial = tmp_path / "r.csv.partial"
    # Enough full-discretization variants (62) that the run lasts seconds, to stop it midway.
    slow = [a if a != "zero-order" else "full-discretization" for a in SWEEP]
    slow[2] = "modes[0].damping_ratio=0.01:0.001:0.04"
    p = subprocess.Popen([MPIRUN, "--oversubscribe", "-n", "2", CUTDYN, *slow, "--out",
                          str(out_csv)], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         env=MPI_ENV, start_new_session=True)
    # Stop it once a few variants are written.
    deadline = time.monotonic() + 120
    while time.monotonic() < deadline:
        if partial.exists() and partial.read_text().count("\n") > 400:
            break
        time.sleep(0.05)
    os.killpg(p.pid, signal.SIGTERM)
    p.wait(timeout=60)
    assert partial.exists() and not out_csv.exists()
    code, out, err = run(*slow, "--out", str(out_csv), "--resume", mpi=2)
    assert code == 0, err
    assert "from the stopped run" in out
    code, _, err = run(*slow, "--out", str(tmp_path / "full.csv"))
    assert code == 0, err
    assert out_csv.read_bytes() == (tmp_path / "full.csv").read_bytes()
