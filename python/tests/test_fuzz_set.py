"""A fuzzer of `Scene.set` and `Scene.update` on the shipped scenes: seeded
random keys (the scenes' own, changed, new, hostile) and values (the
scenes' own perturbed, numbers at the edges of f64, strings with escape
sequences, nested lists and dicts, numpy scalars and arrays, objects
Python cannot write), applied one after another to a scene as a hostile
user would.

Asserted for every case: nothing but ffr's documented exceptions
(`ffr.FfrError` and its subclasses, `TypeError`, `ValueError`: never a
Rust `PanicException`), each with a message free of control and invisible
characters and of bounded length; a refused change leaves the scene as it
was; an accepted one reads back with `get`, keeps at most `MAX_OVERRIDES`
overrides, and the scene runs a few steps to a `RunResult` whose every
number is finite or raises `SimulationError`; the process's peak memory
grows by less than 512 MiB over the whole run.

`FFR_FUZZ_CASES=N` (default 400) and `FFR_FUZZ_SEED=S` (default 36) for
longer runs: `FFR_FUZZ_CASES=20000 pytest python/tests/test_fuzz_set.py`."""

import math
import os
import random
import resource
import unicodedata

import numpy as np
import pytest

import ffr
from conftest import SCENES

CASES = int(os.environ.get("FFR_FUZZ_CASES", "400"))
SEED = int(os.environ.get("FFR_FUZZ_SEED", "36"))
MAX_OVERRIDES = 256
DOCUMENTED = (ffr.FfrError, TypeError, ValueError)
TOP = ["description", "dimension", "gravity", "t_end", "dt", "integrator", "bodies", "joints", "forces", "outputs"]
FILES = sorted(SCENES.glob("*.toml"))


def keys_of(value, prefix, out):
    """Every dotted key inside a value `get` gave (tables and arrays too)."""
    out.append(prefix)
    if isinstance(value, dict):
        for k, v in value.items():
            keys_of(v, f"{prefix}.{k}", out)
    elif isinstance(value, list):
        for i, v in enumerate(value):
            keys_of(v, f"{prefix}.{i}", out)


def scene_keys(s):
    out = []
    for k in TOP:
        v = s.get(k)
        if v is not None:
            keys_of(v, k, out)
    return out


HOSTILE_TEXT = [
    "",
    " ",
    "\x1b]0;owned\x07\x1b[2J",
    "\u202eevil",
    "a\nb",
    "\x00",
    "é" * 3,
    "𝕏",
    "x" * 600,
    "beam@x=1e308",
    "ground@[nan, 0]",
    "ground@[1e308, -1e308]",
    "beam@x=-0.5",
    "bar@node=3",
]
EDGE_FLOATS = [0.0, -0.0, 1e-320, 5e-324, 1e-300, 1e300, 1.7976931348623157e308, -1e308, math.nan, math.inf, -math.inf, 1e15, 1e-15]
EDGE_INTS = [0, -1, 1, 2, 3, 257, 10**6, 2**31, 2**63 - 1, -(2**63), 2**64, -(2**70)]
PLAUSIBLE_TEXT = ["beam2", "beam3", "clamped", "pinned", "free", "revolute", "prismatic", "fixed", "ground", "spin-up",
                  "constant-rate", "harmonic", "constant", "position", "velocity", "deflection", "angle", "energy",
                  "x", "y", "z", "total", "kinetic", "generalized-alpha", "rk4", "consistent", "lumped", "point"]


def random_value(rng, depth=0):
    r = rng.random()
    if r < 0.12:
        return rng.choice(EDGE_FLOATS)
    if r < 0.27:
        return 10 ** rng.uniform(-6, 6) * rng.choice([1, -1, 1, 1])
    if r < 0.37:
        return rng.choice(EDGE_INTS)
    if r < 0.45:
        return rng.randint(-3, 20)
    if r < 0.50:
        return rng.random() < 0.5
    if r < 0.58:
        return rng.choice(PLAUSIBLE_TEXT + HOSTILE_TEXT)
    if r < 0.70 and depth < 3:
        return [random_value(rng, depth + 1) for _ in range(rng.randint(0, 4))]
    if r < 0.76 and depth < 3:
        return {rng.choice(PLAUSIBLE_TEXT + ["kind", "omega", "angle", "at", "e", "rho", "name"] + HOSTILE_TEXT[:5]): random_value(rng, depth + 1)
                for _ in range(rng.randint(0, 3))}
    if r < 0.86:
        return rng.choice([
            np.float64(rng.uniform(-10, 10)), np.int64(rng.randint(-5, 300)), np.float32(0.1), np.bool_(True),
            np.array(rng.uniform(0, 5)), np.array(3), np.array([1.0, 2.0]), np.array([[0.0, 1.0], [1.0, 2.0]]),
            np.array([]), np.array(1j), np.array("beam2"), np.array([1, 2, 3], dtype=np.int8), np.float64("nan"),
        ])
    if r < 0.92:
        deep = 1.0
        for _ in range(rng.choice([5, 31, 40])):
            deep = [deep]
        return deep
    return rng.choice([None, object(), 1j, b"bytes", {1, 2}, (1.0, 2.0), range(3), {1: 2}, float, [object()]])


def perturbed(rng, old):
    """A value near the scene's own (what a sweep would set)."""
    if isinstance(old, bool):
        return not old
    if isinstance(old, int):
        return old + rng.choice([-old, -1, 1, 2, old, 100])
    if isinstance(old, float):
        return old * rng.choice([0.0, -1.0, 0.5, 2.0, 10.0, 1e-3, 1e3, 10 ** rng.uniform(-8, 8)])
    if isinstance(old, list) and old:
        new = list(old)
        i = rng.randrange(len(new))
        new[i] = perturbed(rng, new[i])
        return new
    if isinstance(old, dict) and old:
        new = dict(old)
        k = rng.choice(list(new))
        if rng.random() < 0.3:
            del new[k]
        else:
            new[k] = perturbed(rng, new[k])
        return new
    return random_value(rng)


def random_key(rng, keys):
    r = rng.random()
    k = rng.choice(keys)
    segs = k.split(".")
    if r < 0.6:
        return k
    if r < 0.7:
        return k + "." + rng.choice(["x", "0", "00", "1", "e", "kind", "omega"])
    if r < 0.8:
        i = rng.randrange(len(segs))
        segs[i] = rng.choice(["0", "00", "007", "-1", "99999999999999999999", "1e3", " 0", "nope", "", "𝕏"] + HOSTILE_TEXT[:6])
        return ".".join(segs)
    if r < 0.9:
        return ".".join(segs[: rng.randint(1, len(segs))])
    return rng.choice(HOSTILE_TEXT + [".", "..", "a..b", "x." * 300, "t_end.", ".t_end"])


def plain(v):
    """A Python value as `get` reads it back, or None when the conversion is
    not a plain one (numpy values, tuples with objects)."""
    if isinstance(v, bool) or isinstance(v, (int, float, str)):
        return v
    if isinstance(v, (list, tuple)):
        items = [plain(x) for x in v]
        return None if any(x is None for x in items) else items
    if isinstance(v, dict):
        items = {k: plain(x) for k, x in v.items()}
        return None if any(x is None for x in items.values()) else items
    return None


def clean_message(e):
    m = str(e)
    assert len(m) <= 2100, (type(e), m[:300])
    bad = [c for c in m if unicodedata.category(c) in ("Cc", "Cf", "Zl", "Zp")]
    assert not bad, (type(e), m[:300], bad[:5])


def short_run(s, rng):
    """A few steps of the scene's copy: a RunResult with finite numbers, or
    a SimulationError."""
    copy = ffr.Scene.from_str(s.text, file=s.file, base=SCENES)
    dt = copy.get("dt")
    try:
        copy.set("t_end", 3 * dt)
    except DOCUMENTED as e:
        clean_message(e)
        return
    try:
        r = copy.run()
    except ffr.SimulationError as e:
        clean_message(e)
        # The samples before the failure (none if it failed before the
        # first), each finite.
        if e.run is not None:
            assert len(e.run.t) == e.run.steps + 1
            for name in e.run:
                assert np.isfinite(e.run[name][:-1]).all(), name
        return
    assert len(r.t) == r.steps + 1 and np.isfinite(r.t).all()
    for name in r:
        assert np.isfinite(r[name]).all(), name


def peak_rss_mib():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def test_fuzz_set_and_update():
    rng = random.Random(SEED)
    fresh = {p: ffr.Scene.load(p) for p in FILES}
    scenes = {p: ffr.Scene.load(p) for p in FILES}
    counts = {"refused": 0, "accepted": 0, "ran": 0}
    base_rss = None
    for case in range(CASES):
        if case == 20:
            base_rss = peak_rss_mib()
        path = rng.choice(FILES)
        s = scenes[path]
        if rng.random() < 0.02:
            s = scenes[path] = ffr.Scene.load(path)
        keys = scene_keys(s) or ["t_end"]
        changes = {}
        for _ in range(1 if rng.random() < 0.8 else rng.randint(1, 4)):
            key = random_key(rng, keys)
            old = s.get(key) if rng.random() < 0.6 else None
            changes[key] = perturbed(rng, old) if old is not None else random_value(rng)
        before = (s.text, s.overrides)
        where = f"case {case} (seed {SEED}) on {path.name}: {changes!r}"[:500]
        try:
            if len(changes) == 1 and rng.random() < 0.8:
                (k, v), = changes.items()
                s.set(k, v)
            else:
                s.update(changes)
        except DOCUMENTED as e:
            counts["refused"] += 1
            clean_message(e)
            assert (s.text, s.overrides) == before, where
            continue
        except BaseException as e:  # a PanicException is a BaseException
            if isinstance(e, KeyboardInterrupt):
                raise
            pytest.fail(f"{where}: {type(e).__name__}: {e}"[:2000])
        counts["accepted"] += 1
        assert len(s.overrides) <= MAX_OVERRIDES, where
        # The last key set reads back (an earlier one of an update may be
        # inside it, or the same place spelt otherwise).
        k, v = list(changes.items())[-1]
        p = plain(v)
        if p is not None:
            assert s.get(k) == p, (where, k, s.get(k))
        try:
            short_run(s, rng)
            counts["ran"] += 1
        except AssertionError as e:
            raise AssertionError(f"{where}: {e}") from e
        if len(s.overrides) > 200:
            scenes[path] = ffr.Scene.load(path)
    grown = peak_rss_mib() - (base_rss or peak_rss_mib())
    print(f"\nfuzz set/update: {CASES} cases, seed {SEED}: {counts}, peak RSS +{grown:.0f} MiB")
    assert grown < 512, grown
    # The fuzzer reaches both outcomes.
    assert counts["refused"] > CASES // 10 and counts["accepted"] > CASES // 20, counts
    # The scenes themselves were not changed by any of it.
    for p, s in fresh.items():
        assert s.overrides == [] and s.text == p.read_text()
