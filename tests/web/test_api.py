"""The explorer's JSON API against the command line: for every example, the case the page
starts from gives the CLI's numbers exactly (the reports of --json, the CSV of --out byte for
byte) when the CLI runs the same case; bad input is refused with the CLI's message and status
400, and the server stays up."""

import json
import os
import re
import signal
import threading
import time

import pytest

from conftest import TIMEOUT_SCALE, run_cli, start

EXAMPLES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "examples")


def examples(server):
    return server.request("/api/examples")[1]["examples"]


def cli_report(tmp, toml, command, *flags):
    """`cutdyn COMMAND case.toml FLAGS --json`: (exit code, report or stderr)."""
    (tmp / "case.toml").write_text(toml)
    code, out, err = run_cli(command, str(tmp / "case.toml"), *flags, "--json",
                             str(tmp / "r.json"))
    if code != 0:
        return code, err
    return code, json.loads((tmp / "r.json").read_text())


def without(report, *keys):
    return {k: v for k, v in report.items() if k not in keys}


def problems_of(err):
    """The problems the command line named, without where ("FILE: " or "command line: ") and
    with its flags named as the API's parameters (--depth-mm → depth_mm)."""
    out = []
    for line in err.splitlines():
        if line.startswith("cutdyn: error: "):
            problem = line[len("cutdyn: error: "):].split(": ", 1)[1]
            out.append(re.sub(r"--([a-z][a-z-]*)", lambda m: m.group(1).replace("-", "_"),
                              problem))
    return out


def test_every_example_gives_the_command_lines_numbers(server, tmp_path):
    for name in examples(server):
        status, doc = server.request("/api/case", query={"example": name})
        assert status == 200, doc
        case = doc["case"]
        # The case as the page holds it, written as a case file (the server's TOML of it).
        status, echo = server.request("/api/case", body=case)
        assert status == 200 and echo["case"] == case, name
        for command, query, flags in [
                ("lobes", {}, []),
                ("check", {"rpm": 6000, "depth_mm": 0.5}, ["--rpm", "6000", "--depth-mm", "0.5"]),
                ("simulate", {"duration_s": 0.05}, ["--duration-s", "0.05"])]:
            code, cli = cli_report(tmp_path, echo["toml"], command, *flags)
            status, api = server.request("/api/" + command, body=case, query=query)
            if code == 0:
                assert status == 200, (name, command, api)
                extra = ("source", "seconds", "traces", "spectrum")
                assert without(api, *extra) == without(cli, *extra), (name, command)
            else:
                assert status == 400, (name, command, api)
                assert api["problems"] == problems_of(cli), (name, command)
        if server.request("/api/lobes", body=case)[0] == 200:
            (tmp_path / "case.toml").write_text(echo["toml"])
            code, _, err = run_cli("lobes", str(tmp_path / "case.toml"), "--out",
                                   str(tmp_path / "l.csv"))
            assert code == 0, err
            status, csv = server.request("/api/lobes", body=case, query={"format": "csv"})
            assert status == 200 and csv == (tmp_path / "l.csv").read_text(), name


def test_bad_requests_are_refused_and_the_server_stays_up(server):
    case = server.request("/api/case")[1]["case"]
    cases = [
        # (path, body bytes, query, status, a word of the message)
        ("/api/lobes", b"{not json", None, 400, "not JSON"),
        ("/api/lobes", b"[1, 2]", None, 400, "table of keys"),
        ("/api/lobes", json.dumps({**case, "modes": 3}).encode(), None, 400, "modes"),
        ("/api/lobes", json.dumps({**case, "nope": 1}).encode(), None, 400, "nope"),
        ("/api/lobes", json.dumps(case).encode(), {"method": "guess"}, 400, "method"),
        ("/api/lobes", json.dumps(case).encode(), {"colour": "red"}, 400, "colour"),
        ("/api/check", json.dumps(case).encode(), {"rpm": "fast", "depth_mm": 1}, 400, "rpm"),
        ("/api/check", json.dumps(case).encode(), {"depth_mm": 1}, 400, "rpm: missing"),
        ("/api/check", json.dumps(case).encode(), {"rpm": 1e4, "depth_mm": -1}, 400, "depth"),
        ("/api/simulate", json.dumps(case).encode(), {"points": 3}, 400, "points"),
        ("/api/simulate", json.dumps(case).encode(), {"duration_s": "nan"}, 400, "duration_s"),
        ("/api/nothing", b"{}", None, 404, "no such"),
        ("/api/lobes", b" " * (2 << 20), None, 413, "too large"),
        ("/api/lobes", "{\"process\": \"mill\u00e9\"}".encode(), None, 400, "process"),
        ("/api/lobes", b"\xff\xfe\x00", None, 400, "JSON"),
    ]
    for path, raw, query, status, word in cases:
        got, body = server.request(path, raw=raw, query=query)
        assert got == status, (path, query, body)
        assert word in body["error"], (path, query, body)
        assert server.alive()
    assert server.request("/api/lobes", body=case)[0] == 200


def test_a_newer_request_from_the_same_page_cancels_the_older(server):
    case = server.request("/api/case")[1]["case"]
    # The older request must still be running when the newer one arrives: 100 000 speeds take
    # seconds even on a fast machine (4000 once finished within the 0.5 s wait).
    slow = {**case, "lobes": {**case["lobes"], "rpm_steps": 100000, "refine": False}}
    results = {}

    def run(name, body, page):
        start_s = time.monotonic()
        results[name] = server.request("/api/lobes", body=body, query={"method": "full-discretization"},
                                       headers={"X-Cutdyn-Page": page}), time.monotonic() - start_s

    first = threading.Thread(target=run, args=("first", slow, "page-1"))
    first.start()
    time.sleep(0.5)
    run("second", case, "page-1")
    first.join()
    (status, body), seconds = results["first"]
    assert status == 409 and "cancelled" in body["error"], body
    assert results["second"][0][0] == 200
    # Another page's request is not cancelled by it.
    other = threading.Thread(target=run, args=("other", {**slow, "lobes": {**slow["lobes"],
                                                         "rpm_steps": 600}}, "page-2"))
    other.start()
    time.sleep(0.2)
    run("third", case, "page-3")
    other.join()
    assert results["other"][0][0] == 200


def test_200_concurrent_lobes_requests(tmp_path):
    # A fresh server: 200 lobes requests at once, all answered with the same numbers as one
    # alone; the server stays up and its memory returns to what it was after the first.
    s = start()
    try:
        case = s.request("/api/case")[1]["case"]
        status, reference = s.request("/api/lobes", body=case)
        assert status == 200
        for _ in range(3):
            s.request("/api/lobes", body=case)
        warm_kb = s.rss_kb()
        answers = [None] * 200

        def ask(i):
            answers[i] = s.request("/api/lobes", body=case, timeout=600)

        threads = [threading.Thread(target=ask, args=(i,)) for i in range(200)]
        started = time.monotonic()
        for t in threads:
            t.start()
        for t in threads:
            t.join(timeout=600 * TIMEOUT_SCALE)
        seconds = time.monotonic() - started
        assert all(a is not None and a[0] == 200 for a in answers), \
            [a for a in answers if a is None or a[0] != 200][:3]
        strip = lambda r: {k: v for k, v in r.items() if k != "seconds"}
        assert all(strip(a[1]) == strip(reference) for a in answers)
        assert s.alive()
        time.sleep(0.5)
        after_kb = s.rss_kb()
        print(f"200 concurrent lobes: {seconds:.1f} s; RSS warm {warm_kb} kB, after {after_kb} kB")
        assert after_kb < warm_kb + 20_000, (warm_kb, after_kb)
    finally:
        s.process.terminate()
        s.process.wait(timeout=20 * TIMEOUT_SCALE)


def test_sigterm_and_sigint_stop_the_server():
    for sig in (signal.SIGTERM, signal.SIGINT):
        s = start()
        assert s.request("/api/examples")[0] == 200
        s.process.send_signal(sig)
        assert s.process.wait(timeout=20) == 0
        assert "stopped" in s.process.stdout.read()


def test_a_port_in_use_is_refused_with_exit_2(server):
    port = server.url.rsplit(":", 1)[1]
    code, out, err = run_cli("serve", "--port", port)
    assert code == 2 and "cannot listen" in err and port in err, err
    code, out, err = run_cli("serve", "--port", "70000")
    assert code == 2 and "--port" in err, err


def test_a_case_file_with_measured_frfs(tmp_path):
    # Its [[frf]] files are relative to its folder: the page's case (as GET /api/case gives it)
    # reads them from there, and gives the command line's lobes on the file.
    path = os.path.join(EXAMPLES, "frf", "milling-measured.toml")
    s = start(path)
    try:
        case = s.request("/api/case")[1]["case"]
        status, csv = s.request("/api/lobes", body=case, query={"format": "csv"})
        assert status == 200, csv
        code, _, err = run_cli("lobes", path, "--out", str(tmp_path / "l.csv"))
        assert code == 0, err
        assert csv == (tmp_path / "l.csv").read_text()
    finally:
        s.process.terminate()
        s.process.wait(timeout=20)


def test_a_client_that_leaves_mid_request_does_not_stop_the_server(server):
    # A lobes request whose client hangs up before the answer: the server answers into a
    # closed socket and goes on.
    import socket

    case = json.dumps(server.request("/api/case")[1]["case"]).encode()
    host, port = server.url.rsplit("/", 1)[-1].split(":")
    for _ in range(5):
        s = socket.create_connection((host, int(port)))
        s.sendall(b"POST /api/lobes HTTP/1.1\r\nHost: x\r\nContent-Type: application/json\r\n"
                  b"Content-Length: " + str(len(case)).encode() + b"\r\n\r\n" + case)
        s.close()
    time.sleep(1.0)
    assert server.alive()
    assert server.request("/api/examples")[0] == 200
