"""cutdyn: machining-process dynamics from Python (docs/python.md).

The same jobs as the ``cutdyn`` command line, on the same case files, with the same
numbers: a case is read and checked by the same code, and every result carries the report
the command line writes with ``--json`` (``result.report``) and prints (``str(result)``).
Tables come back as numpy float64 arrays.

    import cutdyn
    case = cutdyn.example("milling-insperger")        # or cutdyn.Case.from_toml("my.toml")
    lobes = cutdyn.lobes(case)
    lobes.spindle_rpm, lobes.critical_depth_mm         # numpy arrays
    cutdyn.check(case, rpm=10000, depth_mm=0.5).stable

Bad input raises ``cutdyn.CaseError`` (a ``ValueError``) with the command line's message,
naming the key; ``.problems`` lists each problem.
"""

from __future__ import annotations

import os
from typing import Any, Callable, Dict, Iterable, List, Optional, Sequence, Tuple, Union

from . import _cutdyn
from ._cutdyn import Case, CaseError, example, examples

PathLike = Union[str, "os.PathLike[str]"]

__all__ = ["Case", "CaseError", "Lobes", "Check", "Simulation", "Sweep", "Drive", "DriveSweep",
           "Plan", "Force", "Fit", "Identify", "example", "examples", "lobes", "check", "simulate",
           "sweep", "drive", "drive_sweep", "plan", "force", "fit", "identify", "monitor"]


class _Result:
    """A job's result: ``report`` is the command line's --json document, ``str()`` its text."""

    report: Dict[str, Any]

    def __init__(self, native: Dict[str, Any]) -> None:
        self.report = native["report"]
        self._text = native["text"]

    def __str__(self) -> str:
        return self._text

    def _headline(self) -> str:
        lines = self._text.strip().splitlines()
        return lines[0].strip() if lines else ""

    def __repr__(self) -> str:
        """One line: the kind of result and the first line of its text."""
        return f"<cutdyn.{type(self).__name__}: {self._headline()}>"

    def _repr_html_(self) -> str:
        """Jupyter: the text the command line prints."""
        import html

        return f"<pre>{html.escape(self._text)}</pre>"

    @property
    def warnings(self) -> List[str]:
        """Where the method is weak, as the command line warns."""
        return list(self.report.get("warnings", []))


class _Table(_Result):
    """A result with a table: each column an attribute (numpy arrays; text as lists of str)."""

    columns: Dict[str, Any]

    def __init__(self, native: Dict[str, Any]) -> None:
        super().__init__(native)
        self.columns = dict(native["columns"])
        for name, values in self.columns.items():
            setattr(self, name, values)

    def __repr__(self) -> str:
        """The kind, the first line of the text, and the table's size and columns."""
        rows = len(next(iter(self.columns.values()))) if self.columns else 0
        return (f"<cutdyn.{type(self).__name__}: {self._headline()}; {rows} rows of "
                f"{', '.join(self.columns)}>")

    def to_pandas(self) -> Any:
        """The table as a pandas DataFrame (pandas must be installed)."""
        import pandas

        return pandas.DataFrame(self.columns)


class Lobes(_Table):
    """The lobe diagram of a case (``cutdyn lobes``).

    Arrays, one value per spindle speed (the columns of ``cutdyn lobes --out``):
    ``spindle_rpm``, ``critical_depth_mm``, ``chatter_hz``, ``lobe`` (int64),
    ``bifurcation`` (list of str), ``beyond_limit`` (int64, 1 where no boundary was found
    below the search limit), and for vibration-assisted turning ``duty_cycle``,
    ``conventional_depth_mm``, ``conventional_chatter_hz``.
    """

    @property
    def method(self) -> str:
        """The stability method used (never "auto")."""
        return self.report["method"]

    @property
    def lowest(self) -> Dict[str, float]:
        """The lowest critical depth: {"spindle_rpm": ..., "critical_depth_mm": ...}."""
        return self.report["lowest"]


class _Fields(_Result):
    """A result whose report's keys are also attributes (``result.stable`` for
    ``result.report["stable"]``)."""

    def __getattr__(self, name: str) -> Any:
        if name.startswith("_") or name == "report":
            raise AttributeError(name)
        try:
            return self.report[name]
        except KeyError:
            raise AttributeError(name) from None


class Check(_Fields):
    """One speed and depth (``cutdyn check``): the verdict and its margin."""


class Simulation(_Table):
    """A time-domain simulation (``cutdyn simulate``).

    Milling: the arrays ``time_s``, ``fx_n``, ``fy_n``, ``force_n``, ``x_um``, ``y_um``,
    ``teeth_in_cut``, ``cutting_force_n`` (the columns of ``cutdyn simulate --out``, thinned as
    recorded) and ``summary`` (force pulsation, vibration, growth, verdict …). Turning: the
    arrays ``process`` (the run of each row), ``time_s``, ``displacement_um``, ``force_n``,
    ``chip_thickness_um``, and ``results``, one summary per run.
    """

    @property
    def summary(self) -> Dict[str, Any]:
        """Milling: the summary of the last revolutions (as in the JSON)."""
        return self.report["summary"]

    @property
    def results(self) -> List[Dict[str, Any]]:
        """Turning: one summary per run (conventional, vibration-assisted)."""
        return self.report["results"]


def lobes(case: Case, method: str = "", target_depth_mm: Optional[float] = None,
          threads: int = 0,
          progress: Optional[Callable[[int, int], object]] = None) -> Lobes:
    """The lobe diagram of ``case`` (``cutdyn lobes``).

    ``method``: "auto", "zero-order", "closed-form", "multi-frequency",
    "full-discretization", "full-discretization-dense" (default: the case's [lobes] method);
    ``target_depth_mm``: also list the speed ranges stable at this depth and recommend a speed
    (in ``report``); ``threads``: 0 for all cores; ``progress``: called as ``progress(done,
    total)`` with the speeds done so far, on the calling thread, at most every 50 ms and once
    at the end (an exception it raises stops the run and is raised). Releases the GIL; Ctrl-C
    stops it.
    """
    return Lobes(_cutdyn.lobes(case, method, target_depth_mm, threads, progress))


def check(case: Case, rpm: float, depth_mm: float, method: str = "") -> Check:
    """Whether ``case`` cuts stably at ``rpm`` and ``depth_mm`` (``cutdyn check``): attributes
    ``stable``, ``critical_depth_mm``, ``margin``, ``chatter_hz``, ``method`` … as in the JSON."""
    return Check(_cutdyn.check(case, rpm, depth_mm, method))


def simulate(case: Case, rpm: Optional[float] = None, depth_mm: Optional[float] = None,
             duration_s: Optional[float] = None) -> Simulation:
    """Simulates the cut of ``case`` in time (``cutdyn simulate``): at ``rpm`` and
    ``depth_mm`` (default: the case's [simulate] table), for ``duration_s`` seconds (turning)
    or as many revolutions' time (milling: overrides [simulate] revolutions). Releases the GIL.
    """
    return Simulation(_cutdyn.simulate(case, rpm, depth_mm, duration_s))


class Sweep(_Table):
    """A milling simulation repeated over one case key (``cutdyn simulate --sweep``): the key's
    values as an array named after the key, every summary metric as a float64 array (NaN where a
    cut has none), and ``chatter`` (int64 0/1)."""

    @property
    def values(self) -> Any:
        """The swept key's values."""
        return self.columns[self.report["sweep"]]


def sweep(case: Case, key: str, values: Iterable[float], metric: str = "",
          rpm: Optional[float] = None, depth_mm: Optional[float] = None,
          duration_s: Optional[float] = None, threads: int = 0,
          progress: Optional[Callable[[int, int], object]] = None) -> Sweep:
    """Simulates a milling ``case`` at each of ``values`` of one case ``key`` ("force_law.t2_s",
    "modes[0].damping_ratio", "tool.teeth" …), as ``cutdyn simulate --sweep`` does; ``metric``
    names the one its text and report lead with. ``values`` may be any sequence of numbers;
    ``numpy.arange`` or ``numpy.linspace`` make the command line's FROM:STEP:TO. Every varied case
    is checked before any runs. ``progress``: called as ``progress(done, total)`` with the
    runs done, as in :func:`lobes`. Releases the GIL; Ctrl-C stops it between runs.
    """
    return Sweep(_cutdyn.sweep(case, key, [float(v) for v in values], metric, rpm, depth_mm,
                               duration_s, threads, progress))


class Drive(_Table):
    """The feed drives under the milling load (``cutdyn drive``).

    Arrays over the last summary revolutions, every axis one after the other (the columns of
    ``cutdyn drive --out``): ``axis`` (list of str), ``time_s``, ``axis_force_n``,
    ``load_torque_nm``, ``speed_rad_s``, ``position_error_um``, ``epsilon_um``; ``axes``, the
    summary of each axis (k_delta, static error, ripples, ε …) as in the JSON; with
    ``currents=True``, ``current_log``: the motor phase currents as ``--currents`` writes them
    (a log ``cutdyn.monitor.estimate`` reads).
    """

    current_log: Optional[str]

    def __init__(self, native: Dict[str, Any]) -> None:
        super().__init__(native)
        self.current_log = native.get("current_log")

    @property
    def axes(self) -> List[Dict[str, Any]]:
        return self.report["axes"]


def drive(case: Case, rpm: Optional[float] = None, depth_mm: Optional[float] = None,
          seed: Optional[int] = None, currents: bool = False) -> Drive:
    """The feed drives of a milling ``case`` with [[drives]] under its simulated cut
    (``cutdyn drive``): at ``rpm`` and ``depth_mm`` (default: the case's [simulate] table),
    with the current noise's ``seed`` for every axis. Releases the GIL."""
    return Drive(_cutdyn.drive(case, rpm, depth_mm, seed, currents))


class DriveSweep(_Table):
    """The drives over one case key (``cutdyn drive --sweep``): one row per value and axis —
    the key's values (an array named after the key), ``axis``, and every drive metric as a
    float64 array (NaN where a drive has none)."""


def drive_sweep(case: Case, key: str, values: Iterable[float], metric: str = "",
                rpm: Optional[float] = None, depth_mm: Optional[float] = None,
                seed: Optional[int] = None, threads: int = 0) -> DriveSweep:
    """Runs ``cutdyn drive`` at each of ``values`` of one case ``key`` ("simulate.rpm",
    "drives[0].inertia_kg_m2" …); ``metric`` names the one its text and report lead with
    (default epsilon_um). Every varied case is checked before any runs. Releases the GIL;
    Ctrl-C stops it between runs."""
    return DriveSweep(_cutdyn.drive_sweep(case, key, [float(v) for v in values], metric, rpm,
                                          depth_mm, seed, threads))


class Plan(_Fields):
    """Two-edge face milling of a large bore (``cutdyn plan``): every quantity of the JSON as
    an attribute (``result``, ``plan``, ``trade_off`` …)."""


def plan(case: Case, axial_feed_mm: Optional[float] = None) -> Plan:
    """Plans the bore-milling ``case`` (``cutdyn plan``): the largest axial feed for its
    straightness limit, or ``axial_feed_mm`` if given; with [limits], the optimum."""
    return Plan(_cutdyn.plan(case, axial_feed_mm))


class Force(_Fields):
    """The cutting and thrust forces of a turning cut (``cutdyn force``), with the duty cycle
    of vibration-assisted cutting: every quantity of the JSON as an attribute."""


def force(case: Case) -> Force:
    """The forces of the turning ``case`` (``cutdyn force``)."""
    return Force(_cutdyn.force(case))


class Fit(_Fields):
    """Modes fitted to a measured FRF (``cutdyn fit``): ``modes`` (natural_hz, damping_ratio,
    stiffness_n_per_m …) as in the JSON; ``modes_toml``, the [[modes]] tables ``--out``
    writes; the arrays ``frequency_hz`` and ``receptance_m_per_n`` (complex128) of the file,
    ``coherence`` where the file gives one, and ``fitted_frequency_hz``,
    ``fitted_receptance_m_per_n`` of the fitted model in the
    band."""

    modes_toml: str

    def __init__(self, native: Dict[str, Any]) -> None:
        super().__init__(native)
        self.modes_toml = native["modes_toml"]
        for name, values in native["columns"].items():
            setattr(self, name, values)


def fit(path: PathLike, modes: Union[int, str] = "auto",
        band: Optional[Tuple[float, float]] = None, direction: Optional[str] = None,
        format: Optional[str] = None, units: Optional[str] = None) -> Fit:
    """Fits modes to the FRF file at ``path`` (``cutdyn fit``): ``modes`` "auto" (chosen from
    the stabilisation diagram) or a number; ``band`` (lo_hz, hi_hz); ``direction`` "x" or
    "y" (default: a UFF file's response direction, else x); ``format`` "frf", "csv" or "uff"
    (default: from the content); ``units`` a CutPro text file's units in place of its
    header's, e.g. "kHz, mm/N"."""
    if modes == "auto" or modes is None:
        count = 0
    elif isinstance(modes, int) and not isinstance(modes, bool) and modes >= 1:
        count = modes
    else:
        raise CaseError(f"request: modes = {modes!r}: must be 'auto' or a whole number >= 1")
    lo, hi = (None, None) if band is None else band
    return Fit(_cutdyn.fit(os.fspath(path), count, lo, hi, direction or "", format or "",
                           units or ""))


class Identify(_Fields):
    """Cutting and edge coefficients from test cuts (``cutdyn identify``): ``coefficients``,
    ``samples``, ``fit`` … as in the JSON, and ``cutting_toml``, the [cutting] table
    ``--out`` writes."""

    cutting_toml: str

    def __init__(self, native: Dict[str, Any]) -> None:
        super().__init__(native)
        self.cutting_toml = native["cutting_toml"]


def identify(case: Case, force_files: Union[PathLike, Sequence[PathLike]]) -> Identify:
    """Identifies Kt, Kr, Kte, Kre (and Ka, Kae with fz) of the milling ``case``'s cutter and
    engagement from the ``force_files`` (``cutdyn identify``)."""
    if isinstance(force_files, (str, os.PathLike)):
        force_files = [force_files]
    return Identify(_cutdyn.identify(case, [os.fspath(f) for f in force_files]))


from . import monitor  # noqa: E402  (the monitor's jobs, cutdyn.monitor.calibrate …)
