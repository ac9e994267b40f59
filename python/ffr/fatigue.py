"""Fatigue post-processing: rainflow cycles and damage-equivalent loads.

The damage-equivalent load (DEL) of a load history ``L(t)`` for an S-N
(Wöhler) slope ``m`` is the range of the constant-amplitude load that, cycled
``N_eq`` times, does the same Palmgren-Miner damage as the history::

    DEL_m = ( sum_i n_i * S_i**m / N_eq ) ** (1/m)

- ``S_i`` are the **ranges** (peak to valley, not amplitudes) of the cycles
  a rainflow count finds (ASTM E1049-85, section 5.4.4, by the PyPI package
  ``rainflow``); ``n_i`` is 1 for a full cycle and 0.5 for each half cycle,
  among them the half cycles of the residue (the ranges left unclosed at the
  end of the history). No mean-load correction unless ``ultimate`` is
  given (Goodman, as MLife: ``S_i (L_ult - |L_MF|) / (L_ult - |mean_i|)``).
- ``N_eq = T / t_eq``: ``T = t[-1] - t[0]`` the history's duration and
  ``t_eq`` (default 1 s) the period of the equivalent cycle, i.e. an
  equivalent frequency ``f_eq = 1 / t_eq`` of 1 Hz, the convention of
  OpenFAST's MLife and of IEC 61400 load reports (short-term DEL, 1 Hz).
  ``n_eq`` gives ``N_eq`` directly instead.

Command line: ``python -m ffr.fatigue RUN.csv --column NAME [--m 3,4,10]
[--t-eq 1] [--n-eq N] [--json]``, also ``ffr fatigue …`` (which runs this).
``rainflow`` is an optional dependency: ``pip install "ffr[fatigue]"``.
See docs/fatigue.md.
"""

from __future__ import annotations

import math
import os
import stat
import sys
from array import array
from dataclasses import dataclass
from typing import Dict, Iterable, Optional, Sequence, Union

import numpy as np

__all__ = [
    "Cycles",
    "DEFAULT_M",
    "MAX_CSV_BYTES",
    "MAX_CSV_LINE",
    "MAX_CSV_COLUMNS",
    "MAX_CSV_ROWS",
    "CsvError",
    "cycles",
    "equivalent_load",
    "read_column",
    "main",
]

#: The S-N slopes of :func:`equivalent_load` unless told (steel 3 and 4,
#: glass-fibre composite 10).
DEFAULT_M = (3.0, 4.0, 10.0)

#: The most bytes of a CSV that :func:`read_column` reads (64 MiB, as
#: ``ffr run --reference``).
MAX_CSV_BYTES = 64 << 20

#: The longest line of a CSV, in bytes.
MAX_CSV_LINE = 1 << 20

#: The most columns of a CSV (``t`` included).
MAX_CSV_COLUMNS = 4096

#: The most rows of a CSV (2^22). Measured: ``ffr fatigue`` on a 60 MB
#: file of 3 514 414 rows of random values (every sample a reversal) takes
#: 14 s and 0.5 GB of RSS; ``equivalent_load`` of 1e6 random samples 1.5 s.
MAX_CSV_ROWS = 1 << 22


class CsvError(ValueError):
    """A CSV that cannot be read; the message names ``file:line``."""


def _rainflow():
    try:
        import rainflow
    except ModuleNotFoundError as e:
        raise ModuleNotFoundError(
            'ffr.fatigue needs the package `rainflow`: pip install "ffr[fatigue]" '
            '(or pip install "rainflow>=3")',
            name="rainflow",
        ) from e
    return rainflow


def _series(x, what: str) -> np.ndarray:
    """A 1-D finite float array from `x`, or a TypeError/ValueError."""
    if isinstance(x, (str, bytes)):
        raise TypeError(f"{what} must be a sequence of numbers, not a string")
    try:
        a = np.asarray(x, dtype=float)
    except (TypeError, ValueError) as e:
        raise TypeError(f"{what} must be a sequence of numbers ({e})") from None
    if a.ndim != 1:
        raise ValueError(f"{what} must be one-dimensional (its shape is {a.shape})")
    bad = np.flatnonzero(~np.isfinite(a))
    if bad.size:
        raise ValueError(f"{what}[{bad[0]}] = {a[bad[0]]} is not finite")
    return a


@dataclass(frozen=True)
class Cycles:
    """The rainflow cycles of a history (ASTM E1049-85), in the order the
    count closes them: ``range[i]`` (peak to valley, ≥ 0), ``mean[i]``
    (half the sum of its two reversals) and ``count[i]`` (1.0 a full
    cycle, 0.5 a half cycle)."""

    range: np.ndarray
    mean: np.ndarray
    count: np.ndarray


def cycles(signal) -> Cycles:
    """The rainflow cycles of ``signal`` (a 1-D sequence of finite numbers;
    ASTM E1049-85 by ``rainflow.extract_cycles``; half cycles, among them
    those of the residue, have count 0.5)."""
    y = _series(signal, "signal")
    rf = _rainflow()
    if y.size == 2:
        # rainflow 3.2 drops the last point of a two-point series; its one
        # range is a half cycle.
        if y[0] == y[1]:
            z = np.zeros(0)
            return Cycles(z, z.copy(), z.copy())
        return Cycles(
            np.array([abs(y[1] - y[0])]), np.array([0.5 * (y[0] + y[1])]), np.array([0.5])
        )
    rows = list(rf.extract_cycles(y.tolist()))
    if not rows:
        z = np.zeros(0)
        return Cycles(z, z.copy(), z.copy())
    a = np.array([r[:3] for r in rows], dtype=float)
    return Cycles(a[:, 0].copy(), a[:, 1].copy(), a[:, 2].copy())


def _slopes(m) -> list:
    if isinstance(m, (str, bytes)):
        raise TypeError("m must be a number or a sequence of numbers")
    ms = [m] if np.ndim(m) == 0 else list(m)
    if not ms:
        raise ValueError("m is empty: give at least one S-N slope")
    out = []
    for v in ms:
        if isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating)):
            raise TypeError(f"m must be numbers (got {v!r})")
        v = float(v)
        if not (math.isfinite(v) and v > 0):
            raise ValueError(f"m = {v} must be a finite number > 0")
        out.append(v)
    return out


def _positive(x, what: str) -> float:
    if isinstance(x, bool) or not isinstance(x, (int, float, np.integer, np.floating)):
        raise TypeError(f"{what} must be a number (got {x!r})")
    x = float(x)
    if not (math.isfinite(x) and x > 0):
        raise ValueError(f"{what} = {x} must be a finite number > 0")
    return x


def equivalent_load(
    t,
    signal,
    m: Union[float, Iterable[float]] = DEFAULT_M,
    t_eq: float = 1.0,
    n_eq: Optional[float] = None,
    ultimate: Optional[float] = None,
    fixed_mean: Optional[float] = None,
) -> Dict[float, float]:
    """Damage-equivalent loads of ``signal`` sampled at times ``t``.

    ``DEL_m = (sum_i n_i S_i**m / N_eq)**(1/m)`` over the rainflow cycles of
    :func:`cycles` (ranges ``S_i``; ``n_i`` 1 or 0.5, the residue's half
    cycles counted 0.5; no mean correction), with ``N_eq = (t[-1] - t[0]) /
    t_eq`` (equivalent frequency ``1/t_eq``, 1 Hz by default), or ``n_eq``
    if given.

    Parameters
    ----------
    t, signal : 1-D sequences of finite numbers of the same length (≥ 2),
        ``t`` strictly increasing (s).
    m : an S-N slope or a sequence of them (each finite, > 0).
    t_eq : the equivalent cycle's period (s, finite, > 0).
    n_eq : the number of equivalent cycles (finite, > 0); replaces
        ``T / t_eq``.
    ultimate : with it, the Goodman mean-load correction of MLife: each
        range becomes ``S_i (ultimate - |fixed_mean|) / (ultimate -
        |mean_i|)``, ``mean_i`` the cycle's mean (finite, > 0, larger than
        every ``|mean_i|`` and ``|fixed_mean|``). Without it (the default),
        no correction.
    fixed_mean : the mean load the corrected ranges refer to (default:
        the mean of the signal's samples); only with ``ultimate``.

    Returns
    -------
    dict mapping each ``float(m)`` (in the order given) to its DEL, in the
    units of ``signal``. A constant signal has DEL 0.

    Raises TypeError for non-numeric input, ValueError for the rest (the
    message says which value), ModuleNotFoundError without ``rainflow``.
    """
    tt = _series(t, "t")
    y = _series(signal, "signal")
    if tt.size != y.size:
        raise ValueError(f"t has {tt.size} samples and signal {y.size}: give them the same length")
    if tt.size < 2:
        raise ValueError(f"{tt.size} sample(s): a load history needs at least 2")
    step = np.diff(tt)
    bad = np.flatnonzero(~(step > 0))
    if bad.size:
        i = bad[0] + 1
        raise ValueError(f"t[{i}] = {tt[i]} does not come after t[{i - 1}] = {tt[i - 1]}: t must increase")
    ms = _slopes(m)
    if n_eq is None:
        t_eq = _positive(t_eq, "t_eq")
        duration = float(tt[-1] - tt[0])
        neq = duration / t_eq
        if not (math.isfinite(neq) and neq > 0):
            raise ValueError(f"N_eq = T / t_eq = {duration} / {t_eq} is not a finite number > 0")
    else:
        neq = _positive(n_eq, "n_eq")
    c = cycles(y)
    if ultimate is not None:
        c = _goodman(c, y, ultimate, fixed_mean)
    elif fixed_mean is not None:
        raise ValueError("fixed_mean is the Goodman correction's reference mean: give ultimate too")
    out: Dict[float, float] = {}
    for mv in ms:
        out[mv] = _del(c, mv, neq)
    return out


def _goodman(c: Cycles, y: np.ndarray, ultimate, fixed_mean) -> Cycles:
    ult = _positive(ultimate, "ultimate")
    if fixed_mean is None:
        lmf = float(np.mean(y))
    else:
        if isinstance(fixed_mean, bool) or not isinstance(
            fixed_mean, (int, float, np.integer, np.floating)
        ):
            raise TypeError(f"fixed_mean must be a number (got {fixed_mean!r})")
        lmf = float(fixed_mean)
        if not math.isfinite(lmf):
            raise ValueError(f"fixed_mean = {lmf} is not finite")
    if not abs(lmf) < ult:
        raise ValueError(f"|fixed_mean| = {abs(lmf)} is not below ultimate = {ult}")
    if c.mean.size and not float(np.max(np.abs(c.mean))) < ult:
        i = int(np.argmax(np.abs(c.mean)))
        raise ValueError(
            f"a cycle's mean load {c.mean[i]} is not below ultimate = {ult} in magnitude: "
            "the Goodman correction needs |mean| < ultimate"
        )
    scaled = c.range * ((ult - abs(lmf)) / (ult - np.abs(c.mean)))
    return Cycles(scaled, c.mean, c.count)


def _del(c: Cycles, m: float, neq: float) -> float:
    if c.range.size == 0:
        return 0.0
    # Scaled by the largest range so that S**m neither overflows nor
    # underflows for large m; exact when every range equals the largest.
    smax = float(np.max(c.range))
    if smax == 0.0:
        return 0.0
    damage = float(np.sum(c.count * (c.range / smax) ** m))
    return smax * (damage / neq) ** (1.0 / m)


# ---------------------------------------------------------------- CSV input


def _file_text(path: str) -> str:
    return repr(path)[1:-1] if any(ch in path for ch in "\n\r\t\x1b") else path


def read_column(path, column: str):
    """``(t, values)`` of ``column`` from a CSV as ``ffr run --csv`` writes
    it: a header ``t,NAME,…`` (names distinct), then rows of as many fields,
    every ``t`` and ``column`` cell a finite number, ``t`` strictly
    increasing, at least 2 rows. A regular file of at most
    :data:`MAX_CSV_BYTES` bytes, lines of at most :data:`MAX_CSV_LINE`
    bytes, at most :data:`MAX_CSV_ROWS` rows. Raises :class:`CsvError` (a
    ValueError) naming ``file:line``."""
    name = _file_text(os.fspath(path))

    def err(msg, line=None):
        return CsvError(f"{name}:{line}: {msg}" if line else f"{name}: {msg}")

    try:
        st = os.stat(path)
    except OSError as e:
        raise err(e.strerror or str(e)) from None
    if stat.S_ISDIR(st.st_mode):
        raise err("is a directory, not a CSV file")
    if not stat.S_ISREG(st.st_mode):
        raise err("is not a regular file (a FIFO, device or socket): not read")
    if st.st_size > MAX_CSV_BYTES:
        raise err(f"larger than {MAX_CSV_BYTES} bytes (MAX_CSV_BYTES): not read")

    def text(raw, i):
        if len(raw.rstrip(b"\r\n")) > MAX_CSV_LINE:
            raise err(f"longer than {MAX_CSV_LINE} bytes (MAX_CSV_LINE)", i)
        try:
            return raw.decode("utf-8").rstrip("\r\n")
        except UnicodeDecodeError:
            raise err("not UTF-8 text", i) from None

    t, y = array("d"), array("d")
    read = 0
    try:
        with open(path, "rb") as f:
            # Line by line, each read through a bound (a line longer than
            # MAX_CSV_LINE is refused without being held whole), the whole
            # file through MAX_CSV_BYTES; the numbers go to arrays of f64.
            first = f.readline(MAX_CSV_LINE + 3)
            read += len(first)
            if first == b"":
                raise err("empty: no header `t,NAME,…`")
            header = [h.strip() for h in text(first, 1).split(",")]
            if len(header) < 2 or header[0] != "t":
                raise err("the header must be `t` and one name per column (`t,tip_y`)", 1)
            if len(header) > MAX_CSV_COLUMNS:
                raise err(f"{len(header)} columns, more than {MAX_CSV_COLUMNS} (MAX_CSV_COLUMNS)", 1)
            seen = {}
            for j, h in enumerate(header):
                if h in seen:
                    raise err(f"column `{_snip(h)}` appears twice (columns {seen[h] + 1} and {j + 1})", 1)
                seen[h] = j
            if column not in seen or column == "t":
                shown = ", ".join(_snip(h) for h in header[1:9]) + (", …" if len(header) > 9 else "")
                raise err(f"no column `{_snip(column)}` (its columns: {shown})", 1)
            k = seen[column]
            i = 1
            while True:
                raw = f.readline(MAX_CSV_LINE + 3)
                if raw == b"":
                    break
                i += 1
                read += len(raw)
                if read > MAX_CSV_BYTES:
                    raise err(f"larger than {MAX_CSV_BYTES} bytes (MAX_CSV_BYTES): not read")
                row = text(raw, i)
                if row.strip() == "":
                    continue
                if len(t) == MAX_CSV_ROWS:
                    raise err(f"more than {MAX_CSV_ROWS} rows (MAX_CSV_ROWS)", i)
                cells = row.split(",")
                if len(cells) != len(header):
                    raise err(f"{len(cells)} fields, the header has {len(header)}", i)
                for idx, out in ((0, t), (k, y)):
                    cell = cells[idx].strip()
                    try:
                        v = float(cell)
                    except ValueError:
                        v = None
                    if v is None or not math.isfinite(v):
                        raise err(f"`{_snip(cell)}` in column `{_snip(header[idx])}` is not a finite number", i)
                    if idx == 0 and t and not (v > t[-1]):
                        raise err(f"t = {v!r} does not come after the previous time {t[-1]!r}", i)
                    out.append(v)
    except OSError as e:
        raise err(e.strerror or str(e)) from None
    if len(t) < 2:
        raise err(f"{len(t)} row(s) after the header: a load history needs at least 2")
    return np.frombuffer(t, dtype=float).copy(), np.frombuffer(y, dtype=float).copy()


def _snip(s: str, n: int = 40) -> str:
    s = s.encode("unicode_escape", "backslashreplace").decode("ascii")
    return s if len(s) <= n else s[: n - 1] + "…"


# ---------------------------------------------------------------- command line


def _parse_args(argv: Sequence[str]):
    import argparse

    class Parser(argparse.ArgumentParser):
        def error(self, message):  # one line, no usage block
            raise _Usage(message)

    p = Parser(
        prog="ffr fatigue",
        allow_abbrev=False,
        description="Damage-equivalent loads of a column of a `ffr run --csv` file "
        "(rainflow, ASTM E1049-85; DEL_m = (sum n_i S_i^m / N_eq)^(1/m), N_eq = T / t_eq).",
    )
    p.add_argument("csv", help="the CSV (header `t,NAME,…`)")
    p.add_argument("--column", required=True, help="the column to count")
    p.add_argument("--m", default=",".join(f"{v:g}" for v in DEFAULT_M), help="S-N slopes, comma-separated (default 3,4,10)")
    p.add_argument("--t-eq", default="1", help="the equivalent cycle's period in s (default 1: 1 Hz)")
    p.add_argument("--n-eq", default=None, help="the number of equivalent cycles (instead of T / t_eq)")
    p.add_argument("--ultimate", default=None, help="the ultimate load: Goodman mean-load correction")
    p.add_argument("--fixed-mean", default=None, help="the Goodman correction's reference mean (default: the column's mean)")
    p.add_argument("--json", action="store_true", help="print one JSON object")
    return p.parse_args(list(argv))


class _Usage(Exception):
    pass


def _number(s: str, flag: str) -> float:
    try:
        v = float(s)
    except ValueError:
        raise _Usage(f"{flag} `{_snip(s)}` is not a number") from None
    if not (math.isfinite(v) and v > 0):
        raise _Usage(f"{flag} {_snip(s)} must be a finite number > 0")
    return v


def main(argv: Optional[Sequence[str]] = None) -> int:
    """The command line (``python -m ffr.fatigue``, ``ffr fatigue``): the
    DELs printed, one line per slope (or one JSON object with ``--json``);
    errors as one line on stderr and exit status 2 (3 without ``rainflow``),
    never a traceback."""
    import json

    argv = sys.argv[1:] if argv is None else argv
    try:
        a = _parse_args(argv)
        ms = [_number(s.strip(), "--m") for s in a.m.split(",")]
        t_eq = _number(a.t_eq, "--t-eq")
        n_eq = None if a.n_eq is None else _number(a.n_eq, "--n-eq")
        ultimate = None if a.ultimate is None else _number(a.ultimate, "--ultimate")
        fixed_mean = None
        if a.fixed_mean is not None:
            if ultimate is None:
                raise _Usage("--fixed-mean is the Goodman correction's reference mean: give --ultimate too")
            try:
                fixed_mean = float(a.fixed_mean)
            except ValueError:
                raise _Usage(f"--fixed-mean `{_snip(a.fixed_mean)}` is not a number") from None
            if not math.isfinite(fixed_mean):
                raise _Usage(f"--fixed-mean {_snip(a.fixed_mean)} is not finite")
        _rainflow()
        t, y = read_column(a.csv, a.column)
        dels = equivalent_load(t, y, m=ms, t_eq=t_eq, n_eq=n_eq, ultimate=ultimate, fixed_mean=fixed_mean)
        neq = n_eq if n_eq is not None else float(t[-1] - t[0]) / t_eq
        if a.json:
            out = {
                "file": os.fspath(a.csv),
                "column": a.column,
                "rows": int(t.size),
                "duration": float(t[-1] - t[0]),
                "t_eq": None if n_eq is not None else t_eq,
                "n_eq": neq,
                "ultimate": ultimate,
                "fixed_mean": (float(np.mean(y)) if fixed_mean is None else fixed_mean) if ultimate else None,
                "del": [{"m": mv, "del": v} for mv, v in dels.items()],
            }
            print(json.dumps(out))
        else:
            print(
                f"{_snip(a.column, 64)}: {t.size} rows, T = {float(t[-1] - t[0])!r} s, N_eq = {neq!r}"
                + ("" if n_eq is not None else f" (t_eq = {t_eq!r} s)")
                + (
                    ""
                    if ultimate is None
                    else f", Goodman: ultimate {ultimate!r}, fixed mean "
                    f"{(float(np.mean(y)) if fixed_mean is None else fixed_mean)!r}"
                )
            )
            for mv, v in dels.items():
                print(f"  DEL(m={mv:g}) = {v!r}")
        return 0
    except _Usage as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    except ModuleNotFoundError as e:
        print(f"error: {e}", file=sys.stderr)
        return 3
    except (ValueError, TypeError, OSError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
    except Exception as e:  # never a traceback on the terminal
        print(f"error: ffr.fatigue failed: {type(e).__name__}: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
