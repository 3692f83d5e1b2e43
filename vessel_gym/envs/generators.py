"""The vector environments' per-vessel random generators: vessel k's is ``gymnasium.utils.seeding.np_random``
of its seed, made when first drawn from, with the seed hashing of all vessels done in one numpy pass.

:func:`pcg64_seed_words` is numpy's ``SeedSequence(seed).generate_state(4, np.uint64)`` (the words PCG64 seeds
from) for many one-word seeds at once, in uint32 arithmetic over arrays; it follows numpy's
``numpy/random/bit_generator.pyx`` (the hash of M. E. O'Neill's seed_seq_fe, pool of 4 words) and is checked
bit for bit against numpy in tests/envs/test_batch_reset.py.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from gymnasium.utils import seeding
from numpy.random.bit_generator import ISeedSequence

U = np.uint32
# numpy's SeedSequence constants (bit_generator.pyx)
INIT_A, MULT_A, INIT_B, MULT_B = U(0x43B0D7E5), U(0x931E8875), U(0x8B51F9DD), U(0x58F38DED)
MIX_L, MIX_R, XSHIFT = U(0xCA01F9DD), U(0x4973F715), U(16)
POOL = 4  # words in the entropy pool


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


class _FirstUse:
    """Vessel k's generator, made when an attribute of it (a draw) is first asked for."""

    __slots__ = ("_gens", "_k")

    def __init__(self, gens: VesselGenerators, k: int) -> None:
        self._gens, self._k = gens, k

    def __getattr__(self, name: str) -> Any:
        return getattr(self._gens[self._k], name)


class VesselGenerators(Sequence):
    """The vessels' random generators, vessel k's made from its seed (``gymnasium.utils.seeding.np_random``,
    None: fresh entropy) when first used: a numpy Generator costs 20-100 us to make, and a reset that draws
    nothing (a fixed start) then makes none. Nothing draws from a generator before it is made, so its stream
    is the one a generator made at the reset gives. The seeds' hashing (numpy's SeedSequence, most of that
    cost) is done for all vessels at once (:func:`pcg64_seed_words`); the generators' bit generators then
    carry a :class:`_Words` instead of a SeedSequence (their streams are the same; ``spawn`` is unavailable)."""

    def __init__(self, seeds: Sequence[int | None]) -> None:
        _check_seeds(seeds)
        self._seeds = list(seeds)
        self._made: list[np.random.Generator | None] = [None] * len(self._seeds)
        self._words: np.ndarray | None = None  # (N, 4) PCG64 seed words, hashed at the first generator made

    def __len__(self) -> int:
        return len(self._seeds)

    def __getitem__(self, k):  # type: ignore[override]
        g = self._made[k]
        if g is None:
            g = self._made[k] = self._make(k)
        return g

    def _make(self, k: int) -> np.random.Generator:
        """Vessel k's generator: from its seed's PCG64 state words, hashed for all the vessels at once."""
        s = self._seeds[k]
        if s is None or s >= 2**32:  # fresh entropy, or a seed of more than one 32-bit word: numpy's own path
            return seeding.np_random(s)[0]
        if self._words is None:
            small = np.array([x if x is not None and x < 2**32 else 0 for x in self._seeds], dtype=np.uint64)
            self._words = pcg64_seed_words(small)
        return np.random.Generator(np.random.PCG64(_Words(self._words[k])))

    def lazy(self, k: int) -> Any:
        """Vessel k's generator as a stand-in that makes it at its first draw (a reset that draws nothing makes
        none)."""
        return self._made[k] or _FirstUse(self, k)

    def reseed(self, seeds: Sequence[int | None]) -> None:
        """New generators (made when used) for the vessels whose seed is not None."""
        _check_seeds(seeds)
        self._words = None
        for i, s in enumerate(seeds):
            if s is not None:
                self._seeds[i] = s
                self._made[i] = None


__all__ = ["VesselGenerators", "pcg64_seed_words"]
