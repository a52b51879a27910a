"""Every function of the module called with hostile arguments, in a child interpreter: each call
either returns or raises a Python exception, and the interpreter survives all of them.

The calls run one after the other in one child that prints the number of each call before it
makes it; a child that dies (a signal, an abort in native code) names the call that killed it.
A few of the calls must be refused with CaseError quickly (the limits the command line has)."""

import os
import subprocess
import sys
import textwrap

import pytest

EXAMPLES = os.path.join(os.path.dirname(__file__), "..", "..", "examples")
FRF = os.path.abspath(os.path.join(EXAMPLES, "frf", "tool_x.csv"))

# Values that are wrong in every way a Python caller can make them wrong.
NUMBERS = ["-1", "0", "float('nan')", "float('inf')", "-float('inf')", "1e308", "2**31",
           "2**63", "-2**63", "'7'", "None", "[]", "True"]
SEQUENCES = ["[]", "[float('nan')]", "[1e308]", "None", "'abc'", "[[]]", "range(0)"]
TEXTS = ["''", "'\\x00'", "'x' * 100000", "None", "7", "'../' * 50 + 'etc/passwd'",
         "'/proc/self/stat'", "'/'"]

SETUP = textwrap.dedent(f"""
    import cutdyn, cutdyn.monitor, sys
    milling = cutdyn.example('milling-insperger')
    turning = cutdyn.example('turning-ultrasonic')
    drive_case = cutdyn.example('ermolaev2020')
    FRF = {FRF!r}
""")


def hostile_calls():
    """(expression, must_raise) for every function and every hostile argument in turn."""
    calls = []
    for n in NUMBERS:
        calls += [
            (f"cutdyn.lobes(milling, threads={n})", False),
            (f"cutdyn.lobes(milling, target_depth_mm={n})", False),
            (f"cutdyn.check(milling, rpm={n}, depth_mm=0.1)", False),
            (f"cutdyn.check(milling, rpm=9000, depth_mm={n})", False),
            (f"cutdyn.check(turning, rpm={n}, depth_mm=1)", False),
            (f"cutdyn.simulate(milling, rpm={n})", False),
            (f"cutdyn.simulate(milling, depth_mm={n})", False),
            (f"cutdyn.simulate(milling, duration_s={n})", False),
            (f"cutdyn.simulate(turning, duration_s={n})", False),
            (f"cutdyn.sweep(milling, 'simulate.rpm', [9000], threads={n})", False),
            (f"cutdyn.drive(drive_case, rpm={n})", False),
            (f"cutdyn.drive(drive_case, seed={n})", False),
            (f"cutdyn.drive_sweep(drive_case, 'simulate.rpm', [9000], threads={n})", False),
            (f"cutdyn.plan(cutdyn.example('bore-plan'), axial_feed_mm={n})", False),
            (f"cutdyn.fit(FRF, modes={n})", False),
            (f"cutdyn.fit(FRF, band=({n}, 1000))", False),
            (f"cutdyn.monitor.estimate('x', 'zheng2012', bandwidth_hz={n})", False),
        ]
    for s in SEQUENCES:
        calls += [
            (f"cutdyn.sweep(milling, 'simulate.rpm', {s})", False),
            (f"cutdyn.drive_sweep(drive_case, 'simulate.rpm', {s})", False),
            (f"cutdyn.identify(milling, {s})", False),
            (f"cutdyn.monitor.calibrate(idle={s})", False),
            (f"cutdyn.monitor.calibrate(loaded={s})", False),
            (f"cutdyn.monitor.teach({s}, 'zheng2012')", False),
            (f"cutdyn.Case({{'process': 'milling', 'modes': {s}}})", False),
        ]
    for t in TEXTS:
        calls += [
            (f"cutdyn.example({t})", False),
            (f"cutdyn.Case.from_toml({t})", False),
            (f"cutdyn.lobes(milling, method={t})", False),
            (f"cutdyn.sweep(milling, {t}, [1])", False),
            (f"cutdyn.sweep(milling, 'simulate.rpm', [9000], metric={t})", False),
            (f"cutdyn.drive_sweep(drive_case, {t}, [1])", False),
            (f"cutdyn.fit({t})", False),
            (f"cutdyn.fit(FRF, direction={t})", False),
            (f"cutdyn.fit(FRF, format={t})", False),
            (f"cutdyn.fit(FRF, units={t})", False),
            (f"cutdyn.identify(milling, {t})", False),
            (f"cutdyn.monitor.estimate({t}, 'zheng2012')", False),
            (f"cutdyn.monitor.estimate('x', {t})", False),
            (f"cutdyn.monitor.calibrate(base={t})", False),
            (f"cutdyn.Case({{'process': {t}}})", False),
        ]
    # The limits the command line has, refused the same way.
    calls += [
        ("cutdyn.sweep(milling, 'simulate.rpm', [])", True),
        ("cutdyn.drive_sweep(drive_case, 'simulate.rpm', [])", True),
        ("cutdyn.lobes(milling, threads=100000)", True),
        ("cutdyn.lobes(milling, threads=-1)", True),
        ("cutdyn.sweep(milling, 'simulate.rpm', [9000], threads=5000)", True),
        ("cutdyn.drive_sweep(drive_case, 'simulate.rpm', [9000], threads=5000)", True),
        ("cutdyn.fit(FRF, modes=50)", True),
        ("cutdyn.sweep(milling, 'simulate.rpm', [9000.0] * 10001)", True),
    ]
    return calls


RUNNER = textwrap.dedent("""
    import sys, time
    calls = eval(sys.stdin.read())
    for i, (expression, must_raise) in enumerate(calls):
        print(f"call {i}", flush=True)
        start = time.monotonic()
        try:
            eval(expression)
            outcome = "returned"
        except cutdyn.CaseError:
            outcome = "CaseError"
        except (TypeError, ValueError, OverflowError, KeyError, AttributeError) as e:
            outcome = type(e).__name__
        print(f"done {i} {outcome} {time.monotonic() - start:.2f}", flush=True)
""")


def test_the_interpreter_survives_every_hostile_call():
    calls = hostile_calls()
    p = subprocess.run([sys.executable, "-c", SETUP + RUNNER], input=repr(calls),
                       capture_output=True, text=True, timeout=1200, check=False)
    lines = p.stdout.splitlines()
    started = [line for line in lines if line.startswith("call ")]
    last = int(started[-1].split()[1]) if started else 0
    assert p.returncode == 0, (
        f"the interpreter died (exit {p.returncode}) in {calls[last][0]}\n{p.stderr[-3000:]}")
    done = {int(line.split()[1]): line.split()[2:] for line in lines if line.startswith("done ")}
    assert len(done) == len(calls)
    for i, (expression, must_raise) in enumerate(calls):
        outcome, seconds = done[i][0], float(done[i][1])
        if must_raise:
            assert outcome == "CaseError", f"{expression}: {outcome}"
            assert seconds < 10, f"{expression}: refused only after {seconds} s"


@pytest.mark.parametrize("expression,fragment", [
    ("cutdyn.sweep(milling, 'simulate.rpm', [])", "values: none given"),
    ("cutdyn.lobes(milling, threads=100000)", "threads = 1e+05: must be 0 (all cores) to 1024"),
    ("cutdyn.fit(FRF, modes=50)", "modes = 50: must be 0 (automatic) to 40"),
])
def test_the_limits_are_named(expression, fragment):
    p = subprocess.run([sys.executable, "-c", SETUP + textwrap.dedent(f"""
        try:
            {expression}
        except cutdyn.CaseError as e:
            print(e)
    """)], capture_output=True, text=True, timeout=120, check=False)
    assert p.returncode == 0, p.stderr
    assert fragment in p.stdout, p.stdout
