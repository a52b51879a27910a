"""No partial output: every command that writes files, stopped by SIGTERM or SIGINT at a
random moment, leaves each output either as it was before (the previous run's complete file)
or as the complete new file, and no temporary beside it; a write to a full device (/dev/full)
or a full file system fails with exit status 1 and a message naming the file. The output
files appear by an atomic rename of a finished temporary (docs/output-files.md)."""

import json
import os
import random
import shutil
import signal
import subprocess
import time
from pathlib import Path

import pytest

CUTDYN = os.environ.get("CUTDYN", "cutdyn")
ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
PREVIOUS = b"previous complete file\n"

# name, arguments with {d} for the output folder, output files (relative to it)
COMMANDS = [
    ("lobes", ["lobes", "milling-insperger", "--out", "{d}/l.csv", "--json", "{d}/l.json",
               "--plot", "{d}/l.svg"], ["l.csv", "l.json", "l.svg", "l.dat", "l.gp"]),
    ("check", ["check", "milling-insperger", "--rpm", "10000", "--depth-mm", "0.05", "--json",
               "{d}/c.json"], ["c.json"]),
    ("simulate", ["simulate", "milling-insperger", "--out", "{d}/s.csv", "--json", "{d}/s.json"],
     ["s.csv", "s.json"]),
    ("drive", ["drive", "--out", "{d}/d.csv", "--json", "{d}/d.json"], ["d.csv", "d.json"]),
    ("plan", ["plan", "--json", "{d}/p.json"], ["p.json"]),
    ("force", ["force", "--json", "{d}/f.json", "--plot", "{d}/f.svg"],
     ["f.json", "f.svg", "f.dat", "f.gp"]),
    ("fit", ["fit", str(EXAMPLES / "frf" / "tool_x.frf"), "--json", "{d}/fit.json"],
     ["fit.json"]),
    ("sweep", ["sweep", "--vary", "tool.teeth=2:1:4", "--method", "zero-order", "--out",
               "{d}/sw.csv"], ["sw.csv"]),
]

TIMING_KEYS = {"seconds", "elapsed_s", "wall_s"}


def strip_timing(value):
    if isinstance(value, dict):
        return {k: strip_timing(v) for k, v in value.items() if k not in TIMING_KEYS}
    if isinstance(value, list):
        return [strip_timing(v) for v in value]
    return value


def same_output(name, data, reference):
    if name.endswith(".json"):
        return strip_timing(json.loads(data)) == strip_timing(json.loads(reference))
    return data == reference


def command(args, folder):
    return [CUTDYN] + [a.replace("{d}", str(folder)) for a in args]


@pytest.mark.parametrize("name,args,outputs", COMMANDS, ids=[c[0] for c in COMMANDS])
def test_killed_at_any_moment_leaves_the_old_or_the_new_file(name, args, outputs, tmp_path):
    reference = tmp_path / "reference"
    reference.mkdir()
    start = time.monotonic()
    done = subprocess.run(command(args, reference), capture_output=True, timeout=300)
    full_time = time.monotonic() - start
    assert done.returncode == 0, done.stderr.decode()
    expected = {o: (reference / o).read_bytes() for o in outputs}
    rng = random.Random(f"{name}-kill")
    outcomes = {"old": 0, "new": 0}
    for trial in range(6):
        folder = tmp_path / f"trial{trial}"
        folder.mkdir()
        for o in outputs:
            (folder / o).write_bytes(PREVIOUS)
        p = subprocess.Popen(command(args, folder), stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL)
        time.sleep(rng.uniform(0.0, 1.2 * full_time))
        p.send_signal(signal.SIGTERM if trial % 2 == 0 else signal.SIGINT)
        p.wait(timeout=60)
        for o in outputs:
            data = (folder / o).read_bytes()
            if data == PREVIOUS:
                outcomes["old"] += 1
            else:
                assert same_output(o, data, expected[o]), \
                    f"{name}: {o} is neither the previous nor the complete new file"
                outcomes["new"] += 1
        leftovers = [f.name for f in folder.iterdir() if f.name not in outputs]
        if name == "sweep" and leftovers == ["sw.csv.partial"]:
            # A stopped sweep keeps its finished variants for --resume, which completes it.
            args_resumed = command(args, folder) + ["--resume"]
            done = subprocess.run(args_resumed, capture_output=True, timeout=300)
            assert done.returncode == 0, done.stderr.decode()
            assert (folder / "sw.csv").read_bytes() == expected["sw.csv"]
            leftovers = [f.name for f in folder.iterdir() if f.name not in outputs]
        assert leftovers == [], f"{name}: left behind {leftovers}"
    assert sum(outcomes.values()) == 6 * len(outputs)


@pytest.mark.parametrize("name,args,outputs", COMMANDS, ids=[c[0] for c in COMMANDS])
def test_a_full_device_fails_with_a_message(name, args, outputs, tmp_path):
    if not Path("/dev/full").exists():
        pytest.skip("no /dev/full")
    # The first output option's file goes to /dev/full.
    first = next(i for i, a in enumerate(args) if "{d}" in a)
    full = list(args)
    full[first] = "/dev/full"
    done = subprocess.run(command(full, tmp_path), capture_output=True, timeout=300)
    assert done.returncode == 1, done.stderr.decode()
    assert "/dev/full" in done.stderr.decode()
    # Nothing else was written either: the transaction commits all files or none.
    assert [f.name for f in tmp_path.iterdir()] == []


def test_a_full_standard_output_fails_with_a_message():
    if not Path("/dev/full").exists():
        pytest.skip("no /dev/full")
    with open("/dev/full", "wb") as full:
        done = subprocess.run([CUTDYN, "lobes", "milling-insperger"], stdout=full,
                              stderr=subprocess.PIPE, timeout=300)
    assert done.returncode == 1
    assert "standard output" in done.stderr.decode()


def test_a_full_standard_output_is_reported_once(tmp_path):
    # `monitor estimate` streams to the standard output and reports its failed write itself;
    # the program adds no second message.
    if not Path("/dev/full").exists():
        pytest.skip("no /dev/full")
    log = tmp_path / "log.csv"
    log.write_text("time_s,axis,iu_a,iv_a,iw_a,speed_rad_s\n" +
                   "".join(f"{i / 1000:.3f},x,1,-0.5,-0.5,50\n" for i in range(2000)))
    with open("/dev/full", "wb") as full:
        done = subprocess.run([CUTDYN, "monitor", "estimate", "--calib", "zheng2012", str(log)],
                              stdout=full, stderr=subprocess.PIPE, timeout=300)
    errors = [line for line in done.stderr.decode().splitlines() if "error" in line]
    assert done.returncode == 1
    assert len(errors) == 1 and "standard output" in errors[0], errors
