"""The explorer's server as a user starts it: `cutdyn serve --port 0`, on 127.0.0.1, read the
port it prints; requests go straight to it (no proxy)."""

import json
import os
import re
import subprocess
import urllib.error
import urllib.request

import pytest

CUTDYN = os.environ.get("CUTDYN", "cutdyn")
# Time limits grow with this factor (ctest sets it to 5 in a sanitized build, where the server
# runs several times slower).
TIMEOUT_SCALE = float(os.environ.get("CUTDYN_TIMEOUT_SCALE", "1"))
NO_PROXY = urllib.request.build_opener(urllib.request.ProxyHandler({}))


class Served:
    def __init__(self, process, url):
        self.process = process
        self.url = url

    def request(self, path, body=None, query=None, headers=None, raw=None, timeout=120):
        """(status, parsed JSON or text) of one request; body: a dict sent as JSON."""
        timeout *= TIMEOUT_SCALE
        url = self.url + path
        if query:
            url += "?" + urllib.parse.urlencode(query)
        data = raw if raw is not None else (None if body is None else json.dumps(body).encode())
        req = urllib.request.Request(url, data=data, headers=headers or {},
                                     method="POST" if data is not None else "GET")
        if data is not None:
            req.add_header("Content-Type", "application/json")
        try:
            with NO_PROXY.open(req, timeout=timeout) as r:
                status, text, kind = r.status, r.read().decode(), r.headers["Content-Type"]
        except urllib.error.HTTPError as e:
            status, text, kind = e.code, e.read().decode(), e.headers["Content-Type"]
        return status, json.loads(text) if kind and "json" in kind else text

    def rss_kb(self):
        with open(f"/proc/{self.process.pid}/status") as f:
            return int(re.search(r"VmRSS:\s+(\d+)", f.read()).group(1))

    def alive(self):
        return self.process.poll() is None


def start(*args):
    p = subprocess.Popen([CUTDYN, "serve", "--port", "0", "--quiet", *args],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    line = p.stdout.readline()
    m = re.search(r"http://127\.0\.0\.1:(\d+)/", line)
    assert m, (line, p.stderr.read() if p.poll() is not None else "")
    return Served(p, f"http://127.0.0.1:{m.group(1)}")


@pytest.fixture(scope="module")
def server():
    s = start()
    yield s
    s.process.terminate()
    s.process.wait(timeout=20)


def run_cli(*args):
    p = subprocess.run([CUTDYN, *args], capture_output=True, text=True, check=False)
    return p.returncode, p.stdout, p.stderr
