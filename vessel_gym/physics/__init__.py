"""The physics core: components, composition, integration. Imports no gymnasium, pygame or sockets.

numba caches compiled kernels per source file, but a kernel inlines functions and layout constants from
other files of this package, so its cache would go stale when only those change. The whole package's cache
is therefore keyed by a hash of all its sources: on a mismatch the cached machine code is discarded.
"""

from __future__ import annotations

import hashlib
from pathlib import Path


def invalidate_stale_numba_cache(cache_dir: Path, sources: list[Path]) -> None:
    """Discard numba's cached machine code in ``cache_dir`` (a ``__pycache__``) unless ``sources`` are
    unchanged since it was written (their hash is stored beside the cache)."""
    digest = hashlib.sha256()
    for src in sources:
        digest.update(src.name.encode())
        digest.update(src.read_bytes())
    stamp = cache_dir / "numba-sources.sha256"
    current = digest.hexdigest()
    try:
        if stamp.exists() and stamp.read_text() == current:
            return
        cache_dir.mkdir(exist_ok=True)
        for f in list(cache_dir.glob("*.nbi")) + list(cache_dir.glob("*.nbc")):
            f.unlink()
        stamp.write_text(current)
    except OSError:  # read-only install: numba then caches elsewhere or compiles in memory
        pass


PHYSICS_SOURCES = sorted(Path(__file__).parent.glob("*.py"))
invalidate_stale_numba_cache(Path(__file__).parent / "__pycache__", PHYSICS_SOURCES)
