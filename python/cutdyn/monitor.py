"""The monitor: cutting force from servo-motor currents (``cutdyn monitor``; the model is in
docs/models/monitor.md).

A log is a file's path, or its columns: a mapping of column name to values (a dict of numpy
arrays or lists, a pandas DataFrame) with the columns of a log file — ``time_s``, ``axis``,
``iu_a``, ``iv_a``, ``iw_a``, ``speed_rad_s`` and optionally ``rotor_angle_rad`` (and the
reference force for calibration). ``axis`` may be one str for every row. Columns are read by
the same reader as a file, so the same rules hold; a log given as columns is named
``log`` (``idle[0]``, ``loaded[0]``, ``references[0]``) in messages, where its line N is row
N − 2 (line 1 is the header).

A calibration is a file's path, ``"zheng2012"`` (the source's preset), or the ``calibration``
of a :func:`calibrate` result; a band likewise a path or the ``band`` of a :func:`teach`
result.
"""

from __future__ import annotations

import os
from typing import Any, Dict, List, Mapping, Optional, Sequence, Union

from . import _cutdyn
from ._cutdyn import CaseError  # noqa: F401

#: A log: a file's path, or its columns (a mapping of column name to values).
Log = Union[str, "os.PathLike[str]", Mapping[str, Any]]
Logs = Union[Log, Sequence[Log]]

__all__ = ["Calibration", "Estimate", "Band", "calibrate", "estimate", "teach"]


class _Saved:
    """A result that is a file of the command line: ``save(path)`` writes that file."""

    warnings: List[str]

    def __init__(self, native: Dict[str, Any]) -> None:
        self._text = native["text"]
        self._file_text = native["file_text"]
        self.warnings = list(native["warnings"])

    def __str__(self) -> str:
        return self._text

    def save(self, path: Union[str, "os.PathLike[str]"]) -> None:
        """Writes the file the command line's ``--out`` writes."""
        with open(path, "w") as f:
            f.write(self._file_text)


class Calibration(_Saved):
    """The calibration of each axis (``cutdyn monitor calibrate``): ``calibration`` is the
    calibration file's document (a dict), usable wherever a calibration file is."""

    calibration: Dict[str, Any]

    def __init__(self, native: Dict[str, Any]) -> None:
        super().__init__(native)
        self.calibration = native["report"]


class Band(_Saved):
    """The taught band of each axis (``cutdyn monitor teach``): ``band`` is the band file's
    document (a dict), usable wherever a band file is."""

    band: Dict[str, Any]

    def __init__(self, native: Dict[str, Any]) -> None:
        super().__init__(native)
        self.band = native["report"]


class Estimate:
    """The estimated cutting force (``cutdyn monitor estimate``).

    Arrays, one value per good sample in the order read (the columns of the estimate's CSV, at
    full precision): ``time_s``, ``axis`` (list of str), ``force_n``, ``force_sigma_n`` (NaN
    where the calibration's uncertainty is unknown), ``speed_rad_s``, ``accel_rad_s2``; with a
    band also ``level_n``, ``upper_n``, ``lower_n`` and ``alarm`` (list of str). ``alarms``:
    the alarm events as ``--alarms`` writes them; ``report``: the summary ``--json`` writes
    (the filter of each axis, what force_sigma_n covers); ``warnings``.
    """

    report: Dict[str, Any]
    columns: Dict[str, Any]
    alarms: List[Dict[str, Any]]
    warnings: List[str]

    def __init__(self, native: Dict[str, Any]) -> None:
        self.report = native["report"]
        self._text = native["text"]
        self.columns = dict(native["columns"])
        for name, values in self.columns.items():
            setattr(self, name, values)
        self.alarms = list(native["alarms"])
        self.warnings = list(native["warnings"])

    def __str__(self) -> str:
        return self._text

    def to_pandas(self) -> Any:
        """The estimate as a pandas DataFrame (pandas must be installed)."""
        import pandas

        return pandas.DataFrame(self.columns)


CalibrationLike = Union[str, "os.PathLike[str]", Mapping[str, Any], Calibration]


def _calibration(calib: CalibrationLike) -> Any:
    return calib.calibration if isinstance(calib, Calibration) else calib


def calibrate(idle: Optional[Logs] = None, loaded: Optional[Logs] = None, base: str = "",
              kt: Union[None, float, Mapping[str, float]] = None,
              inertia: Union[None, float, Mapping[str, float]] = None, measure: str = "",
              force_column: str = "force_n", window_s: Optional[float] = None,
              steady_tolerance: Optional[float] = None,
              standstill_rad_s: Optional[float] = None,
              on_bad_line: str = "stop") -> Calibration:
    """Calibrates the axes (``cutdyn monitor calibrate``): Tnzm and X from the ``idle`` logs
    (no cut, constant speeds), KBlf from the ``loaded`` logs (with the reference force column
    ``force_column``), on top of ``base`` (a calibration file or "zheng2012"). ``kt`` and
    ``inertia`` (N·m/A, kg·m²): a number for every axis or {axis: number}. ``measure``:
    "space-vector" or "rms". ``on_bad_line``: "stop" or "skip". Each log a path or columns."""
    return Calibration(_cutdyn.monitor_calibrate(idle, loaded, base, kt, inertia, measure,
                                                 force_column, window_s, steady_tolerance,
                                                 standstill_rad_s, on_bad_line))


def estimate(log: Log, calib: CalibrationLike,
             band: Union[None, str, "os.PathLike[str]", Mapping[str, Any], Band] = None,
             bandwidth_hz: Optional[float] = None, standstill_rad_s: Optional[float] = None,
             tooth_frequency_hz: float = 0.0, persist_s: Optional[float] = None,
             wear_fraction: Optional[float] = None,
             wear_time_constant_s: Optional[float] = None,
             on_bad_line: str = "stop") -> Estimate:
    """Estimates the cutting force of each axis from a current ``log`` (a path or columns)
    with the calibration ``calib`` (``cutdyn monitor estimate``); with a ``band``, watches it
    and raises alarms. ``bandwidth_hz``: f_b of the estimate's filter (default 50).
    Releases the GIL; Ctrl-C stops it."""
    if isinstance(band, Band):
        band = band.band
    return Estimate(_cutdyn.monitor_estimate(log, _calibration(calib), band, bandwidth_hz,
                                             standstill_rad_s, tooth_frequency_hz, persist_s,
                                             wear_fraction, wear_time_constant_s, on_bad_line))


def teach(references: Logs, calib: CalibrationLike, bandwidth_hz: Optional[float] = None,
          standstill_rad_s: Optional[float] = None, bin_s: Optional[float] = None,
          rpm: Optional[float] = None, teeth: Optional[int] = None,
          smoothing_s: Optional[float] = None, k_sigma: Optional[float] = None,
          relative_margin: Optional[float] = None, absolute_margin_n: Optional[float] = None,
          peak_margin: Optional[float] = None, phase_tolerance_s: Optional[float] = None,
          average_s: Optional[float] = None, cutting_fraction: Optional[float] = None,
          on_bad_line: str = "stop") -> Band:
    """Teaches the band of the estimated force from reference runs (``cutdyn monitor
    teach``), each a path or columns; ``rpm`` with ``teeth`` average the level over the
    tooth period."""
    return Band(_cutdyn.monitor_teach(references, _calibration(calib), bandwidth_hz,
                                      standstill_rad_s, bin_s, rpm, teeth, smoothing_s, k_sigma,
                                      relative_margin, absolute_margin_n, peak_margin,
                                      phase_tolerance_s, average_s, cutting_fraction,
                                      on_bad_line))
