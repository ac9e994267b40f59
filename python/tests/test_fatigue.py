"""ffr.fatigue: rainflow cycles and damage-equivalent loads, checked against
the ASTM E1049-85 example, closed forms, a hand count, and a second
implementation (fatpack's four-point rainflow); its command line
(`python -m ffr.fatigue`) on hostile CSVs."""

import os
import subprocess
import sys

import fatpack
import numpy as np
import pytest

from ffr import fatigue


def counts_by_range(c):
    out = {}
    for s, n in zip(c.range, c.count):
        out[float(s)] = out.get(float(s), 0.0) + float(n)
    return out


# ------------------------------------------------------------------ ASTM


ASTM_HISTORY = [-2, 1, -3, 5, -1, 3, -4, 4, -2]  # ASTM E1049-85 Fig. 6 (A..I)
# ASTM E1049-85 Table 4 (rainflow counting, 5.4.4): range -> cycles.
ASTM_TABLE = {3.0: 0.5, 4.0: 1.5, 6.0: 0.5, 8.0: 1.0, 9.0: 0.5}


def test_astm_e1049_example_cycles():
    c = fatigue.cycles(ASTM_HISTORY)
    assert counts_by_range(c) == ASTM_TABLE
    # Every count is a full or a half cycle; the means are those of the
    # reversals' pairs (e.g. the full cycle 4 between -1 and 3 has mean 1).
    assert set(c.count.tolist()) <= {0.5, 1.0}
    full = [(s, mu) for s, mu, n in zip(c.range, c.mean, c.count) if n == 1.0]
    assert full == [(4.0, 1.0)]


def test_astm_example_del_by_hand():
    # DEL_m = (sum n S^m / N_eq)^(1/m) with the table above; t from 0 to
    # 8 s, t_eq 2 s -> N_eq = 4.
    t = np.arange(9.0)
    for m in (1.0, 3.0, 4.0, 10.0):
        damage = 0.5 * 3**m + 1.5 * 4**m + 0.5 * 6**m + 1.0 * 8**m + 0.5 * 9**m
        hand = (damage / 4.0) ** (1 / m)
        got = fatigue.equivalent_load(t, ASTM_HISTORY, m=m, t_eq=2.0)
        assert list(got) == [m]
        assert got[m] == pytest.approx(hand, rel=1e-14, abs=0)
        # n_eq gives N_eq directly.
        assert fatigue.equivalent_load(t, ASTM_HISTORY, m=m, n_eq=4.0)[m] == got[m]


# ------------------------------------------------------------ closed forms


@pytest.mark.parametrize("amp,periods,period", [(1.5, 7, 2.0), (250.0, 40, 0.1), (0.375, 1, 5.0)])
def test_cosine_has_n_cycles_of_twice_the_amplitude(amp, periods, period):
    # A cosine over N whole periods, sampled on its peaks (cos is flat
    # there, so they are exactly ±A), offset by a mean (A dyadic, so 10 ± A
    # is exact too): 2N half cycles of
    # range 2A, so DEL_m = 2A (N / N_eq)^(1/m) exactly (no mean correction).
    t = np.linspace(0.0, periods * period, 64 * periods + 1)
    y = 10.0 + amp * np.cos(2 * np.pi * t / period)
    c = fatigue.cycles(y)
    assert np.all(c.range == 2 * amp) and c.count.sum() == periods
    n_eq = periods * period  # T / t_eq with t_eq = 1 s
    got = fatigue.equivalent_load(t, y, m=[3, 4, 10])
    assert list(got) == [3.0, 4.0, 10.0]
    for m, v in got.items():
        assert v == 2 * amp * (periods / n_eq) ** (1 / m)
    # t_eq = the period: N_eq = N, the DEL is the range itself.
    got = fatigue.equivalent_load(t, y, m=[3, 4, 10], t_eq=period)
    for v in got.values():
        assert v == pytest.approx(2 * amp, rel=1e-15, abs=0)


def test_two_frequencies_hand_count():
    # y = 2 cos(2πt) + cos(4πt): extrema y(0) = 3, y(1/2) = -1 and, where
    # cos(2πt) = -A/(4B) = -1/2 (t = 1/3, 2/3), y = -1.5. Per period the
    # rainflow count closes the small cycle -1.5 -> -1 -> -1.5 (range 0.5)
    # and leaves the big one 3 -> -1.5 -> 3 (range 4.5) as two half cycles:
    # N periods have N cycles of 4.5 and N of 0.5.
    periods = 5
    t = np.arange(0, 12 * periods + 1) / 12.0  # samples on 0, 1/3, 1/2, 2/3
    y = 2 * np.cos(2 * np.pi * t) + np.cos(4 * np.pi * t)
    c = fatigue.cycles(y)
    big = np.isclose(c.range, 4.5, rtol=0, atol=1e-14)
    small = np.isclose(c.range, 0.5, rtol=0, atol=1e-14)
    assert np.all(big | small)
    assert c.count[big].sum() == periods and c.count[small].sum() == periods
    n_eq = float(periods)  # T = 5 s, t_eq = 1 s
    for m, v in fatigue.equivalent_load(t, y, m=[3, 4, 10]).items():
        hand = ((periods * 4.5**m + periods * 0.5**m) / n_eq) ** (1 / m)
        # The samples' values carry cos's round-off (a few 1e-16).
        assert v == pytest.approx(hand, rel=1e-13, abs=0)


def test_constant_and_monotonic_signals():
    t = np.linspace(0, 1, 11)
    assert fatigue.equivalent_load(t, np.full(11, 4.0)) == {3.0: 0.0, 4.0: 0.0, 10.0: 0.0}
    # A ramp from 0 to 2: one half cycle of range 2.
    d = fatigue.equivalent_load(t, 2 * t, m=3, n_eq=0.5)
    assert d[3.0] == pytest.approx((0.5 * 8 / 0.5) ** (1 / 3), rel=1e-15)


def test_large_slope_neither_overflows_nor_underflows():
    t = np.linspace(0, 10, 2001)
    y = 1e30 * np.cos(2 * np.pi * t)
    v = fatigue.equivalent_load(t, y, m=[40])[40.0]
    assert v == 2e30 * (10 / 10) ** (1 / 40)
    y = 1e-30 * np.cos(2 * np.pi * t)
    assert fatigue.equivalent_load(t, y, m=[40])[40.0] == 2e-30


# ------------------------------------------------ a second implementation


def exact_reversals(y):
    """The reversals of `y` without load classes: repeats dropped, the first
    and last points kept, and every point where the slope changes sign."""
    y = np.asarray(y, dtype=float)
    z = y[np.concatenate(([True], np.diff(y) != 0))]
    if z.size < 3:
        return z
    d = np.diff(z)
    turn = np.flatnonzero(d[:-1] * d[1:] < 0) + 1
    return z[np.concatenate(([0], turn, [z.size - 1]))]


@pytest.mark.parametrize("seed", range(6))
def test_against_fatpack_four_point(seed):
    # fatpack's find_rainflow_cycles is the four-point method (ISO 12110-2,
    # Amzallag et al.): it closes the same full cycles as ASTM's
    # three-point method and leaves a residue (the reversals of the
    # unclosed ranges, kept whole); ASTM peels the residue's ranges off as
    # half cycles. So: the full cycles are the same multiset, and ASTM's
    # half cycles are the residue's successive ranges.
    rng = np.random.default_rng(seed)
    n = 3000
    t = np.cumsum(rng.uniform(0.01, 0.02, n))
    # A random walk plus a sine and white noise: cycles of every size.
    y = np.cumsum(rng.normal(size=n)) + 5 * np.sin(t) + rng.normal(size=n)
    if seed % 2:
        y = np.round(y, 1)  # ties and plateaus
    c = fatigue.cycles(y)
    full_fp, residue = fatpack.find_rainflow_cycles(exact_reversals(y))
    full_fp = np.abs(full_fp[:, 1] - full_fp[:, 0])
    half_fp = np.abs(np.diff(residue))
    assert np.array_equal(np.sort(c.range[c.count == 1.0]), np.sort(full_fp))
    assert np.array_equal(np.sort(c.range[c.count == 0.5]), np.sort(half_fp))
    T = t[-1] - t[0]
    for m in (3.0, 4.0, 10.0):
        ref = ((np.sum(full_fp**m) + 0.5 * np.sum(half_fp**m)) / T) ** (1 / m)
        got = fatigue.equivalent_load(t, y, m=m)[m]
        assert got == pytest.approx(ref, rel=1e-12, abs=0)


# ------------------------------------------------------------ input checks


@pytest.mark.parametrize(
    "t,y,kw,exc,msg",
    [
        ([0, 1, 2], [1, 2], {}, ValueError, "same length"),
        ([0], [1], {}, ValueError, "at least 2"),
        ([0, 1, 1], [1, 2, 3], {}, ValueError, "t[2] = 1.0 does not come after"),
        ([0, 2, 1], [1, 2, 3], {}, ValueError, "must increase"),
        ([0, 1, 2], [1, float("nan"), 3], {}, ValueError, "signal[1] = nan is not finite"),
        ([0, 1, float("inf")], [1, 2, 3], {}, ValueError, "t[2] = inf"),
        ([0, 1, 2], [[1, 2, 3]], {}, ValueError, "one-dimensional"),
        ([0, 1, 2], "abc", {}, TypeError, "not a string"),
        ([0, 1, 2], [1, "x", 3], {}, TypeError, "numbers"),
        ([0, 1, 2], [1, 2, 3], {"m": 0}, ValueError, "m = 0.0 must be"),
        ([0, 1, 2], [1, 2, 3], {"m": [3, -1]}, ValueError, "m = -1.0"),
        ([0, 1, 2], [1, 2, 3], {"m": []}, ValueError, "m is empty"),
        ([0, 1, 2], [1, 2, 3], {"m": "3"}, TypeError, "m must be"),
        ([0, 1, 2], [1, 2, 3], {"m": [True]}, TypeError, "m must be numbers"),
        ([0, 1, 2], [1, 2, 3], {"m": float("inf")}, ValueError, "m = inf"),
        ([0, 1, 2], [1, 2, 3], {"t_eq": 0}, ValueError, "t_eq = 0.0"),
        ([0, 1, 2], [1, 2, 3], {"n_eq": float("nan")}, ValueError, "n_eq = nan"),
        ([0, 1e-300], [1, 2], {"t_eq": 1e300}, ValueError, "N_eq = T / t_eq"),
    ],
)
def test_bad_input_is_refused(t, y, kw, exc, msg):
    with pytest.raises(exc) as e:
        fatigue.equivalent_load(t, y, **kw)
    assert msg in str(e.value)


# ----------------------------------------------------- python -m ffr.fatigue


def module(*args, **kw):
    return subprocess.run(
        [sys.executable, "-m", "ffr.fatigue", *map(str, args)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        **kw,
    )


def write(path, text):
    path.write_text(text)
    return path


def test_module_prints_the_function_s_values_bit_for_bit(tmp_path):
    import json

    t = np.linspace(0, 3, 301)
    y = np.sin(2 * np.pi * 1.3 * t) + 0.2 * np.cos(2 * np.pi * 7.1 * t)
    p = tmp_path / "run.csv"
    p.write_text("t,a,b\n" + "".join(f"{a!r},{b!r},{-b!r}\n" for a, b in zip(t.tolist(), y.tolist())))
    r = module(p, "--column", "b", "--m", "3,10", "--t-eq", "0.5", "--json")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    want = fatigue.equivalent_load(t, -y, m=[3, 10], t_eq=0.5)
    assert [(d["m"], d["del"]) for d in out["del"]] == list(want.items())
    assert out["rows"] == 301 and out["n_eq"] == 3 / 0.5
    r = module(p, "--column", "b", "--m", "3,10", "--t-eq", "0.5")
    assert r.returncode == 0 and f"DEL(m=10) = {want[10.0]!r}" in r.stdout


HOSTILE = [
    ("t,a\n0,1\n1,2\n", ["--column", "b"], ":1: no column `b` (its columns: a)"),
    ("t,a\n0,1\n1,x\n2,3\n", ["--column", "a"], ":3: `x` in column `a` is not a finite number"),
    ("t,a\n0,1\n1,nan\n", ["--column", "a"], ":3: `nan` in column `a` is not a finite number"),
    ("t,a\n0,1\n1,inf\n", ["--column", "a"], ":3: `inf` in column `a`"),
    ("t,a\n0,1\n", ["--column", "a"], ": 1 row(s) after the header"),
    ("t,a\n", ["--column", "a"], ": 0 row(s) after the header"),
    ("", ["--column", "a"], ": empty"),
    ("x,a\n0,1\n1,2\n", ["--column", "a"], ":1: the header must be `t`"),
    ("t,a,a\n0,1,1\n1,2,2\n", ["--column", "a"], ":1: column `a` appears twice"),
    ("t,a\n0,1\n0,2\n", ["--column", "a"], ":3: t = 0.0 does not come after the previous time 0.0"),
    ("t,a\n0,1\n1,2,3\n", ["--column", "a"], ":3: 3 fields, the header has 2"),
    ("t,a\n0,1\n1,\xff\n", ["--column", "a"], "1,2"),  # replaced below (not UTF-8)
    ("t,a\n0,1\n1,2\n", ["--column", "a", "--m", "3,0"], "--m 0 must be a finite number > 0"),
    ("t,a\n0,1\n1,2\n", ["--column", "a", "--m", "x"], "--m `x` is not a number"),
    ("t,a\n0,1\n1,2\n", ["--column", "a", "--t-eq", "-1"], "--t-eq -1 must be"),
    ("t,a\n0,1\n1,2\n", ["--column", "a", "--n-eq", "inf"], "--n-eq inf must be"),
    ("t,a\n0,1\n1,2\n", ["--colum", "a"], "required: --column"),
]


@pytest.mark.parametrize("text,args,msg", HOSTILE)
def test_module_refuses_hostile_csv_in_one_line(tmp_path, text, args, msg):
    p = tmp_path / "bad.csv"
    if "\xff" in text:
        p.write_bytes(b"t,a\n0,1\n1,\xff\n")
        msg = ":3: not UTF-8 text"
    else:
        p.write_text(text)
    r = module(p, *args)
    assert r.returncode == 2, (r.stdout, r.stderr)
    assert r.stdout == ""
    lines = r.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ") and msg in lines[0], r.stderr
    if not args[-1].startswith("-") and "--" not in msg and "required" not in msg:
        assert lines[0].startswith(f"error: {p}:")


def test_module_refuses_a_fifo_a_directory_a_missing_and_a_huge_file(tmp_path):
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    huge = tmp_path / "huge.csv"
    with open(huge, "wb") as f:
        f.write(b"t,a\n0,1\n")
        f.truncate(fatigue.MAX_CSV_BYTES + 1)  # sparse: nothing is written
    long_line = write(tmp_path / "long.csv", "t,a\n0," + "1" * (fatigue.MAX_CSV_LINE + 1) + "\n1,2\n")
    cases = [
        (fifo, "is not a regular file"),
        (tmp_path, "is a directory"),
        (tmp_path / "missing.csv", "No such file"),
        (huge, f"larger than {fatigue.MAX_CSV_BYTES} bytes"),
        (long_line, f":2: longer than {fatigue.MAX_CSV_LINE} bytes"),
    ]
    for path, msg in cases:
        r = module(path, "--column", "a", timeout=60)
        lines = r.stderr.splitlines()
        assert r.returncode == 2 and len(lines) == 1 and msg in lines[0], (path, r.stderr)
        assert "Traceback" not in r.stderr


def test_module_without_rainflow_says_what_to_install(tmp_path):
    # A `rainflow` module that cannot be imported, first on the path.
    shadow = tmp_path / "shadow"
    shadow.mkdir()
    (shadow / "rainflow.py").write_text("raise ModuleNotFoundError('no', name='rainflow')\n")
    p = write(tmp_path / "ok.csv", "t,a\n0,1\n1,2\n")
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(shadow), os.environ.get("PYTHONPATH", "")]))
    r = module(p, "--column", "a", env=env)
    lines = r.stderr.splitlines()
    assert r.returncode == 3 and len(lines) == 1, r.stderr
    assert 'pip install "ffr[fatigue]"' in lines[0]


def test_two_samples_are_one_half_cycle():
    c = fatigue.cycles([1.0, 3.0])
    assert (c.range.tolist(), c.mean.tolist(), c.count.tolist()) == ([2.0], [2.0], [0.5])
    assert fatigue.equivalent_load([0, 1], [1.0, 3.0], m=2)[2.0] == pytest.approx(2**0.5, rel=1e-15)  # (0.5 * 2^2 / 1)^(1/2)
    assert fatigue.cycles([1.0, 1.0]).range.size == 0


# ------------------------------------------------------------- ffr fatigue


def ffr_fatigue(ffr_bin, *args, python=sys.executable, env=None, cwd=None):
    e = dict(os.environ if env is None else env, FFR_PYTHON=python)
    return subprocess.run(
        [str(ffr_bin), "fatigue", *map(str, args)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        env=e,
        cwd=cwd,
        timeout=120,
    )


def test_cli_equals_the_function_bit_for_bit_on_a_run(ffr_bin, tmp_path):
    import json

    from conftest import SCENES, cli

    csv = tmp_path / "arm.csv"
    cli(ffr_bin, "run", SCENES / "two_link_arm.toml", "--csv", csv, "--svg", tmp_path / "arm.svg")
    # The CSV read by numpy, not by ffr.fatigue's reader.
    data = np.genfromtxt(csv, delimiter=",", names=True)
    t, y = data["t"], data["upper_tip_deflection"]
    assert t.size > 1000 and np.ptp(y) > 0
    want = fatigue.equivalent_load(t, y, m=[3, 10], t_eq=0.5)
    r = ffr_fatigue(ffr_bin, csv, "--column", "upper_tip_deflection", "--m", "3,10", "--t-eq", "0.5", "--json")
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)
    assert [(d["m"], d["del"]) for d in out["del"]] == list(want.items())
    assert out["rows"] == t.size and out["n_eq"] == (t[-1] - t[0]) / 0.5
    assert all(v > 0 for v in want.values())
    # The text form prints the same numbers (shortest round-trip repr).
    r = ffr_fatigue(ffr_bin, csv, "--column", "upper_tip_deflection", "--m", "3,10", "--t-eq", "0.5")
    assert r.returncode == 0 and r.stderr == ""
    assert [float(line.split("= ")[1]) for line in r.stdout.splitlines()[1:]] == list(want.values())
    # The default slopes and t_eq, and --n-eq.
    r = ffr_fatigue(ffr_bin, csv, "--column", "upper_tip_deflection", "--n-eq", "7", "--json")
    out = json.loads(r.stdout)
    assert [(d["m"], d["del"]) for d in out["del"]] == list(fatigue.equivalent_load(t, y, n_eq=7).items())


def test_cli_refuses_bad_input_in_one_located_line(ffr_bin, tmp_path):
    ok = write(tmp_path / "ok.csv", "t,a\n0,1\n1,2\n2,0\n")
    nan = write(tmp_path / "nan.csv", "t,a\n0,1\n1,NaN\n2,0\n")
    fifo = tmp_path / "pipe.csv"
    os.mkfifo(fifo)
    cases = [
        ([ok, "--column", "b"], f"error: {ok}:1: no column `b`"),
        ([nan, "--column", "a"], f"error: {nan}:3: `NaN` in column `a` is not a finite number"),
        ([fifo, "--column", "a"], f"error: {fifo}: is not a regular file"),
        ([ok, "--column", "a", "--m", "3,-1"], "error: --m -1 must be a finite number > 0"),
        ([ok, "--column", "a", "--t-eq", "nan"], "error: --t-eq nan must be"),
    ]
    for args, msg in cases:
        r = ffr_fatigue(ffr_bin, *args)
        lines = r.stderr.splitlines()
        assert r.returncode != 0 and r.stdout == "", (args, r.stderr)
        assert len(lines) == 1 and lines[0].startswith(msg), (args, r.stderr)


def test_cli_says_what_to_install(ffr_bin, tmp_path):
    ok = write(tmp_path / "ok.csv", "t,a\n0,1\n1,2\n2,0\n")
    # No such interpreter.
    r = ffr_fatigue(ffr_bin, ok, "--column", "a", python=str(tmp_path / "no-python"))
    lines = r.stderr.splitlines()
    assert r.returncode != 0 and len(lines) == 1
    assert "cannot start Python" in lines[0] and 'pip install "ffr[fatigue]"' in lines[0]
    # An interpreter that cannot import ffr (a broken `ffr` first on the path).
    broken = tmp_path / "broken"
    (broken / "ffr").mkdir(parents=True)
    (broken / "ffr" / "__init__.py").write_text("raise ModuleNotFoundError(\"No module named 'ffr'\", name='ffr')\n")
    env = dict(os.environ, PYTHONPATH=str(broken))
    r = ffr_fatigue(ffr_bin, ok, "--column", "a", env=env)
    lines = r.stderr.splitlines()
    assert r.returncode != 0 and len(lines) == 1, r.stderr
    assert "cannot import (ModuleNotFoundError: No module named 'ffr')" in lines[0]
    assert 'pip install ./python "rainflow>=3"' in lines[0]
    # Without rainflow.
    shadow = tmp_path / "shadow"
    shadow.mkdir()
    (shadow / "rainflow.py").write_text("raise ModuleNotFoundError('no', name='rainflow')\n")
    env = dict(os.environ, PYTHONPATH=str(shadow))
    r = ffr_fatigue(ffr_bin, ok, "--column", "a", env=env)
    lines = r.stderr.splitlines()
    assert r.returncode != 0 and len(lines) == 1 and 'pip install "ffr[fatigue]"' in lines[0], r.stderr
    # A directory `ffr/` where the command runs does not stand in for the
    # installed package.
    (tmp_path / "cwd" / "ffr").mkdir(parents=True)
    r = ffr_fatigue(ffr_bin, ok, "--column", "a", cwd=tmp_path / "cwd")
    assert r.returncode == 0 and "DEL(m=3)" in r.stdout, r.stderr


def test_read_column_bounds_the_rows(tmp_path, monkeypatch):
    p = write(tmp_path / "rows.csv", "t,a\n0,1\n1,2\n2,3\n3,4\n")
    t, y = fatigue.read_column(p, "a")
    assert t.tolist() == [0, 1, 2, 3] and y.tolist() == [1, 2, 3, 4]
    monkeypatch.setattr(fatigue, "MAX_CSV_ROWS", 3)
    with pytest.raises(fatigue.CsvError, match=r"rows.csv:5: more than 3 rows \(MAX_CSV_ROWS\)"):
        fatigue.read_column(p, "a")


# ------------------------------------------------------------ Goodman


def test_goodman_on_the_astm_example_by_hand():
    # The ASTM example's cycles with their means, written out from Fig. 6's
    # reversals A..I (range, mean, count): A-B, B-C, E-F, C-D, D-G, G-H, H-I.
    table = [(3, -0.5, 0.5), (4, -1, 0.5), (4, 1, 1.0), (8, 1, 0.5), (9, 0.5, 0.5), (8, 0, 0.5), (6, 1, 0.5)]
    t = np.arange(9.0)
    ult, lmf = 20.0, 0.25
    for m in (3.0, 10.0):
        damage = sum(n * (s * (ult - abs(lmf)) / (ult - abs(mu))) ** m for s, mu, n in table)
        hand = (damage / 8.0) ** (1 / m)
        got = fatigue.equivalent_load(t, ASTM_HISTORY, m=m, ultimate=ult, fixed_mean=lmf)[m]
        assert got == pytest.approx(hand, rel=1e-14, abs=0)
        # fixed_mean defaults to the samples' mean (-1/9 here).
        mean = sum(ASTM_HISTORY) / 9
        damage = sum(n * (s * (ult - abs(mean)) / (ult - abs(mu))) ** m for s, mu, n in table)
        got = fatigue.equivalent_load(t, ASTM_HISTORY, m=m, ultimate=ult)[m]
        assert got == pytest.approx((damage / 8.0) ** (1 / m), rel=1e-14, abs=0)


def test_goodman_cosine_closed_form():
    # Every cycle of M + A cos has mean M: with fixed mean 0 the ranges are
    # 2A L_ult / (L_ult - |M|); with fixed mean M, no change.
    periods, amp, mean, ult = 6, 1.5, -3.0, 12.0
    t = np.linspace(0, periods, 64 * periods + 1)
    y = mean + amp * np.cos(2 * np.pi * t)
    for m in (3.0, 10.0):
        got = fatigue.equivalent_load(t, y, m=m, ultimate=ult, fixed_mean=0.0)[m]
        assert got == pytest.approx(2 * amp * ult / (ult - abs(mean)), rel=1e-14, abs=0)
        got = fatigue.equivalent_load(t, y, m=m, ultimate=ult, fixed_mean=mean)[m]
        assert got == 2 * amp


@pytest.mark.parametrize(
    "kw,exc,msg",
    [
        ({"ultimate": 0}, ValueError, "ultimate = 0.0"),
        ({"ultimate": 0.9}, ValueError, "a cycle's mean load -1.0 is not below ultimate = 0.9 in magnitude"),
        ({"ultimate": 10.0, "fixed_mean": 10.0}, ValueError, "|fixed_mean| = 10.0 is not below"),
        ({"ultimate": 10.0, "fixed_mean": float("nan")}, ValueError, "fixed_mean = nan"),
        ({"ultimate": 10.0, "fixed_mean": "0"}, TypeError, "fixed_mean must be a number"),
        ({"fixed_mean": 1.0}, ValueError, "give ultimate too"),
    ],
)
def test_goodman_refusals(kw, exc, msg):
    with pytest.raises(exc) as e:
        fatigue.equivalent_load(np.arange(9.0), ASTM_HISTORY, **kw)
    assert msg in str(e.value)


def test_goodman_on_the_command_line(ffr_bin, tmp_path):
    import json

    t = np.arange(9.0)
    p = tmp_path / "astm.csv"
    p.write_text("t,a\n" + "".join(f"{a!r},{b!r}\n" for a, b in zip(t.tolist(), ASTM_HISTORY)))
    want = fatigue.equivalent_load(t, ASTM_HISTORY, m=[3, 10], ultimate=20.0, fixed_mean=0.25)
    for run in (ffr_fatigue, lambda _b, *a: module(*a)):
        r = run(ffr_bin, p, "--column", "a", "--m", "3,10", "--ultimate", "20", "--fixed-mean", "0.25", "--json")
        assert r.returncode == 0, r.stderr
        out = json.loads(r.stdout)
        assert [(d["m"], d["del"]) for d in out["del"]] == list(want.items())
        assert (out["ultimate"], out["fixed_mean"]) == (20.0, 0.25)
    r = ffr_fatigue(ffr_bin, p, "--column", "a", "--fixed-mean", "1")
    assert r.returncode != 0 and r.stderr.strip() == "error: --fixed-mean is the Goodman correction's reference mean: give --ultimate too"
    r = ffr_fatigue(ffr_bin, p, "--column", "a", "--ultimate", "0.9")
    assert r.returncode != 0 and "a cycle's mean load" in r.stderr and len(r.stderr.splitlines()) == 1
