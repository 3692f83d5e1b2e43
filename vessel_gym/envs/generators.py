"""The vector environments' per-vessel random generators: vessel k's is ``gymnasium.utils.seeding.np_random``
of its seed, made when first drawn from, with the seed hashing of all vessels done in one numpy pass.

:func:`pcg64_seed_words` is numpy's ``SeedSequence(seed).generate_state(4, np.uint64)`` (the words PCG64 seeds
from) for many one-word seeds at once, in uint32 arithmetic over arrays; it follows numpy's
``numpy/random/bit_generator.pyx`` (the hash of M. E. O'Neill's seed_seq_fe, pool of 4 words) and is checked
bit for bit against numpy in tests/envs/test_batch_reset.py.

The PCG64 generator itself (M. E. O'Neill's PCG XSL RR 128/64, as numpy's ``numpy/random/src/pcg64/pcg64.h``
implements it: a 128-bit linear congruential step, state = state x MULT + inc, then the output permutation of
the new state) and numpy's ``next_double`` are compiled below over an (N, 4) array of states, so the vector
environments draw one number for many vessels in one call, each from its own stream: vessel k's numbers are
those its numpy Generator would give (checked bit for bit in tests/envs/test_batch_reset.py).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from gymnasium.utils import seeding
from numba import njit
from numpy.random.bit_generator import ISeedSequence

U = np.uint32
# numpy's SeedSequence constants (bit_generator.pyx)
INIT_A, MULT_A, INIT_B, MULT_B = U(0x43B0D7E5), U(0x931E8875), U(0x8B51F9DD), U(0x58F38DED)
MIX_L, MIX_R, XSHIFT = U(0xCA01F9DD), U(0x4973F715), U(16)
POOL = 4  # words in the entropy pool

# PCG64 (numpy's pcg64.h): the 128-bit multiplier PCG_DEFAULT_MULTIPLIER_128 as two 64-bit halves; a state row
# is (state high, state low, increment high, increment low)
U64 = np.uint64
MULT_HI, MULT_LO = U64(0x2360ED051FC65DA4), U64(0x4385DF649FCCF645)
S_HI, S_LO, I_HI, I_LO = 0, 1, 2, 3
_32, _MASK32, _ONE = U64(32), U64(0xFFFFFFFF), U64(1)
_ROT, _SIXTY_THREE, _64 = U64(58), U64(63), U64(64)
_DOUBLE_SHIFT = U64(11)  # next_double keeps the top 53 bits
_TWO_M53 = 1.0 / 9007199254740992.0  # 2**-53


@njit(cache=True)
def _mul_64x64(a, b):
    """(high, low) 64-bit halves of the 128-bit product of two uint64."""
    a0, a1 = a & _MASK32, a >> _32
    b0, b1 = b & _MASK32, b >> _32
    p00, p01, p10, p11 = a0 * b0, a0 * b1, a1 * b0, a1 * b1
    mid = (p00 >> _32) + (p01 & _MASK32) + (p10 & _MASK32)
    return p11 + (p01 >> _32) + (p10 >> _32) + (mid >> _32), (mid << _32) | (p00 & _MASK32)


@njit(cache=True)
def _step(st, k):
    """Row k's 128-bit LCG step: state = state x MULT + inc (mod 2**128)."""
    s_hi, s_lo = st[k, S_HI], st[k, S_LO]
    hi, lo = _mul_64x64(s_lo, MULT_LO)
    hi += s_hi * MULT_LO + s_lo * MULT_HI
    lo2 = lo + st[k, I_LO]
    hi += st[k, I_HI] + (_ONE if lo2 < lo else U64(0))
    st[k, S_HI], st[k, S_LO] = hi, lo2


@njit(cache=True)
def _next64(st, k):
    """Row k's next 64-bit output: step, then XSL RR of the new state (pcg_output_xsl_rr_128_64)."""
    _step(st, k)
    hi = st[k, S_HI]
    x = hi ^ st[k, S_LO]
    rot = hi >> _ROT
    return (x >> rot) | (x << ((_64 - rot) & _SIXTY_THREE))


@njit(cache=True)
def pcg64_seed_rows(words, st, rows):
    """Seed the state rows ``rows`` of ``st`` from their SeedSequence words (N, 4), as numpy's
    ``pcg64_set_seed``: initstate = words 0-1, initseq = words 2-3 (high first), inc = 2 initseq + 1,
    state = 0, step, state += initstate, step."""
    for j in range(rows.shape[0]):
        k = rows[j]
        w = words[j]
        st[k, I_HI] = (w[2] << _ONE) | (w[3] >> _SIXTY_THREE)
        st[k, I_LO] = (w[3] << _ONE) | _ONE
        st[k, S_HI] = U64(0)
        st[k, S_LO] = U64(0)
        _step(st, k)
        lo = st[k, S_LO] + w[1]
        st[k, S_HI] = st[k, S_HI] + w[0] + (_ONE if lo < w[1] else U64(0))
        st[k, S_LO] = lo
        _step(st, k)


@njit(cache=True)
def pcg64_doubles(st, idx, out):
    """``out[j]``: the next double in [0, 1) of row ``idx[j]`` (numpy's next_double: top 53 bits x 2**-53)."""
    for j in range(idx.shape[0]):
        out[j] = float(_next64(st, idx[j]) >> _DOUBLE_SHIFT) * _TWO_M53


def pcg64_seed_words(seeds: np.ndarray) -> np.ndarray:
    """(N, 4) uint64: ``SeedSequence(s).generate_state(4, np.uint64)`` of each seed 0 <= s < 2**32."""
    ent = np.asarray(seeds, dtype=np.uint64)
    if ((ent >> np.uint64(32)) != 0).any():
        raise ValueError("pcg64_seed_words takes seeds below 2**32 (one 32-bit word)")
    ent = ent.astype(np.uint32)
    with np.errstate(over="ignore"):  # uint32 products wrap, as in numpy's C
        h = INIT_A

        def hashmix(v: np.ndarray) -> np.ndarray:
            nonlocal h
            v = v ^ h
            h = U(h * MULT_A)
            v = v * h
            return v ^ (v >> XSHIFT)

        pool = [hashmix(ent)] + [hashmix(np.zeros_like(ent)) for _ in range(POOL - 1)]
        for i_src in range(POOL):
            for i_dst in range(POOL):
                if i_src != i_dst:
                    y = hashmix(pool[i_src])
                    r = MIX_L * pool[i_dst] - MIX_R * y
                    pool[i_dst] = r ^ (r >> XSHIFT)
        hb = INIT_B
        out = np.empty((len(ent), 2 * POOL), dtype=np.uint32)
        for i in range(2 * POOL):
            d = pool[i % POOL] ^ hb
            hb = U(hb * MULT_B)
            d = d * hb
            out[:, i] = d ^ (d >> XSHIFT)
    return out.astype("<u4").view("<u8").astype(np.uint64)


class _Words(ISeedSequence):
    """Seed words already hashed (:func:`pcg64_seed_words`), given to PCG64 as a seed sequence."""

    def __init__(self, words: np.ndarray) -> None:
        self.words = words

    def generate_state(self, n_words: int, dtype: Any = np.uint32) -> np.ndarray:
        if n_words != POOL or np.dtype(dtype) != np.uint64:
            raise ValueError("hashed seed words are PCG64's: 4 uint64")
        return self.words


def _check_seeds(seeds: Sequence[int | None]) -> None:
    """Refuse a seed that ``seeding.np_random`` refuses now, not at the generator's first use."""
    bad = [s for s in seeds if s is not None and not (isinstance(s, int) and s >= 0)]
    if bad:
        seeding.np_random(bad[0])  # raises gymnasium's error for it
        raise ValueError(f"seed must be None or an int >= 0, got {bad[0]!r}")


ONE_WORD, FRESH, BIG = 0, 1, 2  # a vessel's seed: below 2**32, None (fresh entropy), 2**32 or more


@dataclass(frozen=True)
class SeedRange:
    """The seeds first, first + 1, ..., first + n - 1 of n vessels (a vector environment's ``reset(seed=first)``),
    without a list of them."""

    first: int
    n: int


def _counting(seeds: Any) -> bool:
    return isinstance(seeds, SeedRange)


class _FirstUse:
    """Vessel k's generator, made when an attribute of it (a draw) is first asked for."""

    __slots__ = ("_gens", "_k")

    def __init__(self, gens: VesselGenerators, k: int) -> None:
        self._gens, self._k = gens, k

    def __getattr__(self, name: str) -> Any:
        return getattr(self._gens[self._k], name)


class VesselGenerators(Sequence):
    """The vessels' random generators: vessel k's stream is that of ``gymnasium.utils.seeding.np_random`` of its
    seed (None: fresh entropy), drawn from one vessel at a time (``gens[k]``, a numpy Generator) or for many
    vessels at once (:meth:`draws`).

    The streams live in an (N, 4) array of PCG64 states, seeded for all vessels at once (the SeedSequence hash
    of one-word seeds by :func:`pcg64_seed_words`, the rest by numpy) when first drawn from; a batch draw
    steps the rows in compiled code. ``gens[k]`` makes vessel k's numpy Generator at its state then (a
    Generator costs 20-100 us to make: a reset that draws nothing, or draws in batches, makes none); from then
    on that Generator holds vessel k's stream and a batch draw reads its state and writes it back, so the two
    ways of drawing always continue one stream. The Generators carry a stand-in for their SeedSequence
    (``spawn`` is unavailable on them); their streams are numpy's.
    """

    def __init__(self, seeds: Sequence[int | None] | SeedRange) -> None:
        """``seeds``: one per vessel, or a :class:`SeedRange`."""
        n = seeds.n if _counting(seeds) else len(seeds)
        self._kind = np.full(n, FRESH, dtype=np.int8)  # how vessel k is seeded: ONE_WORD, FRESH or BIG
        self._one_word = np.zeros(n, dtype=np.uint64)  # the seeds of the ONE_WORD vessels
        self._big: dict[int, int] = {}  # the seeds of the BIG vessels (>= 2**32)
        self._made: list[np.random.Generator | None] = [None] * n
        self._held = np.zeros(n, dtype=np.bool_)  # vessel k's stream is in its Generator _made[k]
        self._st: np.ndarray | None = None  # (N, 4) PCG64 states, seeded at the first draw
        self._set_seeds(seeds)

    def __len__(self) -> int:
        return len(self._made)

    def __getitem__(self, k):  # type: ignore[override]
        g = self._made[k]
        if g is None:
            st = self._states()
            bg = np.random.PCG64(_Words(_NO_WORDS))  # its state is set from vessel k's row at once
            bg.state = _row_state(st, k)
            g = self._made[k] = np.random.Generator(bg)
            self._held[k] = True
        return g

    def _set_seeds(self, seeds: Sequence[int | None] | SeedRange) -> np.ndarray:
        """Record the seeds that are not None (checked first); returns the vessels they are for."""
        if _counting(seeds):
            first, n = seeds.first, seeds.n
            _check_seeds([first])
            m = max(min(2**32 - first, n), 0)  # the vessels whose seed is one 32-bit word
            self._kind[:m] = ONE_WORD
            self._one_word[:m] = first + np.arange(m, dtype=np.uint64)
            self._kind[m:] = BIG  # numpy's hash, kept one by one
            self._big.update({k: first + k for k in range(m, n)})
            return np.arange(n)
        _check_seeds(seeds)
        rows = np.array([k for k, s in enumerate(seeds) if s is not None], dtype=np.int64)
        for k in rows.tolist():
            seed = seeds[k]
            self._kind[k] = ONE_WORD if seed < 2**32 else BIG
            if seed < 2**32:
                self._one_word[k] = seed
            else:
                self._big[k] = seed
        return rows

    def _states(self) -> np.ndarray:
        """The (N, 4) PCG64 state rows, seeded for all vessels on the first call."""
        if self._st is None:
            self._st = np.zeros((len(self), 4), dtype=np.uint64)
            self._seed_rows(np.arange(len(self)))
        return self._st

    def _seed_rows(self, rows: np.ndarray) -> None:
        """Seed the rows ``rows`` as ``seeding.np_random(seed)`` seeds PCG64, with the words
        ``SeedSequence(seed).generate_state(4, np.uint64)``: one-word seeds hashed at once, FRESH vessels
        from words of one new SeedSequence (fresh entropy), BIG seeds by numpy."""
        kind = self._kind[rows]
        words = np.zeros((len(rows), 4), dtype=np.uint64)
        one = kind == ONE_WORD
        words[one] = pcg64_seed_words(self._one_word[rows[one]])
        fresh = np.flatnonzero(kind == FRESH)
        if len(fresh):  # distinct streams from one entropy draw, hashed by numpy
            words[fresh] = np.random.SeedSequence().generate_state(4 * len(fresh), np.uint64).reshape(-1, 4)
        for j in np.flatnonzero(kind == BIG).tolist():
            words[j] = np.random.SeedSequence(self._big[int(rows[j])]).generate_state(4, np.uint64)
        pcg64_seed_rows(words, self._st, np.asarray(rows, dtype=np.int64))

    def doubles(self, idx: np.ndarray) -> np.ndarray:
        """The next double in [0, 1) of each vessel of ``idx`` (int64, distinct): what ``gens[k].random()``
        gives, for all of them in one compiled call."""
        st = self._states()
        held = idx[self._held[idx]].tolist()
        for k in held:  # streams in Generators: their states in, the draw, back out
            _set_row(st, k, self._made[k].bit_generator.state)
        out = np.empty(len(idx))
        pcg64_doubles(st, idx, out)
        for k in held:
            bg = self._made[k].bit_generator
            buffered = bg.state  # its buffered 32-bit half (integers of 32 bits or less) stays as it was
            bg.state = {**_row_state(st, k), "has_uint32": buffered["has_uint32"], "uinteger": buffered["uinteger"]}
        return out

    def draws(self, idx: np.ndarray) -> BatchDraws:
        """The draws of the vessels ``idx``, one number per vessel per call (:class:`BatchDraws`)."""
        return BatchDraws(self, np.asarray(idx, dtype=np.int64))

    def lazy(self, k: int) -> Any:
        """Vessel k's generator as a stand-in that makes it at its first draw (a reset that draws nothing makes
        none)."""
        return self._made[k] or _FirstUse(self, k)

    def reseed(self, seeds: Sequence[int | None] | SeedRange) -> None:
        """New streams for the vessels whose seed is not None (a :class:`SeedRange`: all of them)."""
        rows = self._set_seeds(seeds)
        if len(rows) == len(self):
            self._made = [None] * len(self)
        else:
            for k in rows.tolist():
                self._made[k] = None
        self._held[rows] = False
        if self._st is not None and len(rows):
            self._seed_rows(rows)


class BatchDraws:
    """Draws for the vessels ``idx`` of :class:`VesselGenerators`: each call gives one number per vessel (an
    array over ``idx``), each from the vessel's own stream, as its numpy Generator's ``random()`` and
    ``uniform(low, high)`` would (numpy's ``random_uniform``: low + (high - low) x next_double). A task's start
    written over these arrays is the same code for one vessel drawing from a numpy Generator."""

    __slots__ = ("gens", "idx")

    def __init__(self, gens: VesselGenerators, idx: np.ndarray) -> None:
        self.gens, self.idx = gens, idx

    def random(self) -> np.ndarray:
        return self.gens.doubles(self.idx)

    def uniform(self, low: float, high: float) -> np.ndarray:
        return low + (high - low) * self.gens.doubles(self.idx)

    def subset(self, which: np.ndarray) -> BatchDraws:
        """The draws of the vessels ``idx[which]`` (a boolean mask or positions: a rejection loop's redraws)."""
        return BatchDraws(self.gens, self.idx[which])


class OneVessel:
    """Draws of one vessel of a batch as a numpy Generator gives them (floats), for start code written one
    vessel at a time: ``random()`` and ``uniform(low, high)`` (numpy's low + (high - low) x next_double)."""

    __slots__ = ("gens", "idx")

    def __init__(self, gens: VesselGenerators, k: int) -> None:
        self.gens, self.idx = gens, np.array([k], dtype=np.int64)

    def random(self) -> float:
        return float(self.gens.doubles(self.idx)[0])

    def uniform(self, low: float, high: float) -> float:
        return low + (high - low) * self.random()


def vessels_draws(rngs: Any, idx: np.ndarray) -> Any:
    """The draws of the vessels ``idx`` of a task's generators: :class:`BatchDraws` of a vector environment's
    :class:`VesselGenerators`, the one vessel's numpy Generator of a single environment."""
    return rngs.draws(idx) if isinstance(rngs, VesselGenerators) else rngs[int(idx[0])]


def vessel_draws(rng: Any, j: int) -> Any:
    """The draws of the j-th vessel of ``rng`` (:class:`BatchDraws`) as floats; a numpy Generator (one vessel's
    own) as it is."""
    return OneVessel(rng.gens, int(rng.idx[j])) if isinstance(rng, BatchDraws) else rng


_NO_WORDS = np.zeros(POOL, dtype=np.uint64)
_MASK64 = (1 << 64) - 1


def _row_state(st: np.ndarray, k: int) -> dict:
    """Row k as numpy's PCG64 state dict (no buffered 32-bit half)."""
    row = st[k].tolist()
    return {
        "bit_generator": "PCG64",
        "state": {"state": (row[S_HI] << 64) | row[S_LO], "inc": (row[I_HI] << 64) | row[I_LO]},
        "has_uint32": 0,
        "uinteger": 0,
    }


def _set_row(st: np.ndarray, k: int, state: dict) -> None:
    """Row k from numpy's PCG64 state dict."""
    s, inc = state["state"]["state"], state["state"]["inc"]
    st[k] = (s >> 64, s & _MASK64, inc >> 64, inc & _MASK64)


__all__ = ["BatchDraws", "OneVessel", "SeedRange", "VesselGenerators", "pcg64_seed_words", "vessel_draws", "vessels_draws"]
