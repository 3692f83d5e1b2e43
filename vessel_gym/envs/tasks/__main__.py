"""``python -m vessel_gym.envs.tasks FILE``: rewrite the tables generated from the task declarations in FILE
(docs/envs.md); without FILE, print them."""

from __future__ import annotations

import sys

from vessel_gym.envs.tasks import docs_block, write_docs

if __name__ == "__main__":
    if len(sys.argv) > 1:
        print("updated" if write_docs(sys.argv[1]) else "unchanged")
    else:
        print(docs_block())
