"""The physics core: components, composition, integration. Imports no gymnasium, pygame or sockets.

numba caches compiled kernels per source file, but a kernel inlines functions and layout constants from
other files of this package, so its cache would go stale when only those change. The whole package's cache
is therefore keyed by a hash of all its sources: on a mismatch the cached machine code is discarded.
"""

from __future__ import annotations

import hashlib
from pathlib import Path


def _invalidate_stale_numba_cache() -> None:
    here = Path(__file__).parent
    digest = hashlib.sha256()
    for src in sorted(here.glob("*.py")):
        digest.update(src.name.encode())
        digest.update(src.read_bytes())
    stamp_dir = here / "__pycache__"
    stamp = stamp_dir / "numba-sources.sha256"
    current = digest.hexdigest()
    try:
        if stamp.exists() and stamp.read_text() == current:
            return
        stamp_dir.mkdir(exist_ok=True)
        for f in list(stamp_dir.glob("*.nbi")) + list(stamp_dir.glob("*.nbc")):
            f.unlink()
        stamp.write_text(current)
    except OSError:  # read-only install: numba then caches elsewhere or compiles in memory
        pass


_invalidate_stale_numba_cache()
