"""Long jobs release the GIL and stop on Ctrl-C (KeyboardInterrupt), promptly."""

import os
import signal
import subprocess
import sys
import time

import cutdyn

SCRIPT = """
import sys, threading, time
import cutdyn
d = cutdyn.example("milling-insperger").to_dict()
d["lobes"]["rpm_steps"] = 100000
d["lobes"]["refine"] = False
case = cutdyn.Case(d)
ticks = []
ticker = threading.Thread(target=lambda: [ticks.append(time.sleep(0.01)) for _ in range(50)])
print("start", flush=True)
t = time.time()
ticker.start()
try:
    cutdyn.lobes(case, method="full-discretization", threads=1)
    print("finished", time.time() - t, len(ticks))
except KeyboardInterrupt:
    print("interrupted", time.time() - t, len(ticks))
"""


def test_ctrl_c_stops_a_long_lobes_run():
    # 100 000 speeds by full discretization on one thread take about 17 s (5000 took less than
    # the 1 s below once the lobes got faster); SIGINT after 1 s must end it within a second or
    # two. Meanwhile another Python thread keeps running
    # (the GIL is released): its 50 ticks of 10 ms all happen.
    p = subprocess.Popen([sys.executable, "-c", SCRIPT], stdout=subprocess.PIPE, text=True,
                         env=os.environ)
    assert p.stdout.readline().strip() == "start"
    time.sleep(1.0)
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=120)
    words = out.split()
    assert words[0] == "interrupted", out
    assert float(words[1]) < 3.0, out
    assert int(words[2]) == 50, out


def test_the_gil_is_released_while_lobes_run():
    import threading

    ticks = []

    def tick():
        for _ in range(20):
            time.sleep(0.005)
            ticks.append(time.perf_counter())

    case = cutdyn.example("milling-insperger")
    t = threading.Thread(target=tick)
    start = time.perf_counter()
    t.start()
    cutdyn.lobes(case, threads=1)
    end = time.perf_counter()
    t.join()
    # Ticks kept coming while the job ran (with the GIL held they would wait for its end).
    assert sum(1 for x in ticks if start < x < end) >= 5


SIMULATE = """
import time
import cutdyn
case = cutdyn.example(%r)
print("start", flush=True)
t = time.time()
try:
    cutdyn.%s(case, %s)
    print("finished", time.time() - t)
except KeyboardInterrupt:
    print("interrupted", time.time() - t)
"""


def interrupted_after(delay_s, example, function, arguments):
    """Runs cutdyn.FUNCTION(case, ARGUMENTS) in a child, sends SIGINT after `delay_s`; returns
    what it printed: ("interrupted" or "finished", seconds from its start)."""
    p = subprocess.Popen([sys.executable, "-c", SIMULATE % (example, function, arguments)],
                         stdout=subprocess.PIPE, text=True, env=os.environ)
    assert p.stdout.readline().strip() == "start"
    time.sleep(delay_s)
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=120)
    return out.split()[0], float(out.split()[1])


def test_ctrl_c_stops_one_long_simulation():
    # 1000 s of the milling cut (166 000 revolutions) take about 9 s; the run reports its
    # progress a hundred times, so SIGINT at 0.5 s ends it well within a second after.
    what, seconds = interrupted_after(0.5, "milling-insperger", "simulate", "duration_s=1000")
    assert what == "interrupted" and seconds < 1.5, (what, seconds)
    # Turning too: 60 s of the vibration-assisted cut (about 3.4 s).
    what, seconds = interrupted_after(0.5, "turning-ultrasonic", "simulate", "duration_s=60")
    assert what == "interrupted" and seconds < 1.5, (what, seconds)


def test_progress_callback_counts_the_speeds_and_can_stop_the_run():
    # The callable is called on the calling thread with (done, total): counts that never
    # decrease, the last one the whole grid; it can stop the run by raising.
    d = cutdyn.example("milling-insperger").to_dict()
    d["lobes"]["rpm_steps"] = 3000
    d["lobes"]["refine"] = False
    case = cutdyn.Case(d)
    import threading

    calls = []
    caller = threading.get_ident()
    lobes = cutdyn.lobes(case, method="full-discretization", threads=1,
                         progress=lambda done, total: calls.append((done, total,
                                                                    threading.get_ident())))
    assert len(lobes.spindle_rpm) == 3000
    assert calls, "no progress reported"
    assert all(t == caller for _, _, t in calls)
    assert all(total == 3000 for _, total, _ in calls)
    dones = [done for done, _, _ in calls]
    assert dones == sorted(dones) and len(set(dones)) == len(dones)
    assert dones[-1] == 3000

    class Stop(Exception):
        pass

    def stop(done, total):
        if done >= 10:
            raise Stop()

    d["lobes"]["rpm_steps"] = 100000
    start = time.time()
    try:
        cutdyn.lobes(cutdyn.Case(d), method="full-discretization", threads=1, progress=stop)
        assert False, "the callback's exception was not raised"
    except Stop:
        pass
    assert time.time() - start < 10.0  # stopped, not run to the end (about 17 s)


def test_progress_callback_of_a_sweep():
    case = cutdyn.example("milling-insperger")
    calls = []
    cutdyn.sweep(case, "modes[0].damping_ratio", [0.011, 0.012, 0.013], rpm=9000, depth_mm=0.2,
                 progress=lambda done, total: calls.append((done, total)))
    assert calls and calls[-1] == (3, 3)
