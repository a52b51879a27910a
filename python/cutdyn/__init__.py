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

from . import _cutdyn
from ._cutdyn import Case, CaseError, example, examples

__all__ = ["Case", "CaseError", "Lobes", "Check", "Simulation", "example", "examples", "lobes",
           "check", "simulate", "Sweep", "sweep"]


class _Result:
    """A job's result: ``report`` is the command line's --json document, ``str()`` its text."""

    def __init__(self, native):
        self.report = native["report"]
        self._text = native["text"]

    def __str__(self):
        return self._text

    @property
    def warnings(self):
        """Where the method is weak, as the command line warns."""
        return list(self.report.get("warnings", []))


class _Table(_Result):
    """A result with a table: each column an attribute (numpy arrays; text as lists of str)."""

    def __init__(self, native):
        super().__init__(native)
        self.columns = dict(native["columns"])
        for name, values in self.columns.items():
            setattr(self, name, values)

    def to_pandas(self):
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
    def method(self):
        """The stability method used (never "auto")."""
        return self.report["method"]

    @property
    def lowest(self):
        """The lowest critical depth: {"spindle_rpm": ..., "critical_depth_mm": ...}."""
        return self.report["lowest"]


class Check(_Result):
    """One speed and depth (``cutdyn check``): the verdict and its margin."""

    def __getattr__(self, name):
        try:
            return self.report[name]
        except KeyError:
            raise AttributeError(name) from None


class Simulation(_Table):
    """A time-domain simulation (``cutdyn simulate``).

    Milling: the arrays ``time_s``, ``fx_n``, ``fy_n``, ``force_n``, ``x_um``, ``y_um``,
    ``teeth_in_cut``, ``cutting_force_n`` (the columns of ``cutdyn simulate --out``, thinned as
    recorded) and ``summary`` (force pulsation, vibration, growth, verdict …). Turning: the
    arrays ``process`` (the run of each row), ``time_s``, ``displacement_um``, ``force_n``,
    ``chip_thickness_um``, and ``results``, one summary per run.
    """

    @property
    def summary(self):
        """Milling: the summary of the last revolutions (as in the JSON)."""
        return self.report["summary"]

    @property
    def results(self):
        """Turning: one summary per run (conventional, vibration-assisted)."""
        return self.report["results"]


def lobes(case, method="", target_depth_mm=None, threads=0):
    """The lobe diagram of ``case`` (``cutdyn lobes``).

    ``method``: "auto", "zero-order", "closed-form", "multi-frequency",
    "full-discretization", "full-discretization-dense" (default: the case's [lobes] method);
    ``target_depth_mm``: also list the speed ranges stable at this depth and recommend a speed
    (in ``report``); ``threads``: 0 for all cores. Releases the GIL; Ctrl-C stops it.
    """
    return Lobes(_cutdyn.lobes(case, method, target_depth_mm, threads))


def check(case, rpm, depth_mm, method=""):
    """Whether ``case`` cuts stably at ``rpm`` and ``depth_mm`` (``cutdyn check``): attributes
    ``stable``, ``critical_depth_mm``, ``margin``, ``chatter_hz``, ``method`` … as in the JSON."""
    return Check(_cutdyn.check(case, rpm, depth_mm, method))


def simulate(case, rpm=None, depth_mm=None, duration_s=None):
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
    def values(self):
        """The swept key's values."""
        return self.columns[self.report["sweep"]]


def sweep(case, key, values, metric="", rpm=None, depth_mm=None, duration_s=None, threads=0):
    """Simulates a milling ``case`` at each of ``values`` of one case ``key`` ("force_law.t2_s",
    "modes[0].damping_ratio", "tool.teeth" …), as ``cutdyn simulate --sweep`` does; ``metric``
    names the one its text and report lead with. ``values`` may be any sequence of numbers;
    ``numpy.arange`` or ``numpy.linspace`` make the command line's FROM:STEP:TO. Every varied case
    is checked before any runs. Releases the GIL; Ctrl-C stops it between runs.
    """
    return Sweep(_cutdyn.sweep(case, key, [float(v) for v in values], metric, rpm, depth_mm,
                               duration_s, threads))
