"""Shared helpers: the cutdyn executable built beside the module (CUTDYN), run as a user would."""

import csv
import json
import os
import subprocess

import pytest

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


@pytest.fixture
def tmp(tmp_path):
    return tmp_path
