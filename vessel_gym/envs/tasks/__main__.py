"""``python -m vessel_gym.envs.tasks FILE``: rewrite the tables generated from the registered tasks in FILE
(docs/envs.md); ``--check FILE``: exit 1 naming the file if its tables are stale (CI); without FILE, print
them."""

from __future__ import annotations

import sys

from vessel_gym.envs.tasks import docs_block, ids_block, render, write_docs


def main(argv: list[str]) -> int:
    check = "--check" in argv  # before or after the file
    files = [a for a in argv if a != "--check"]
    if check and len(files) == 1:
        text, new = render(files[0])
        if text != new:
            print(f"{files[0]}: generated tables are stale; run python -m vessel_gym.envs.tasks {files[0]}")
            return 1
        return 0
    if len(files) == 1:
        print("updated" if write_docs(files[0]) else "unchanged")
        return 0
    if not argv:
        print(ids_block() + "\n\n" + docs_block())
        return 0
    print("usage: python -m vessel_gym.envs.tasks [--check] [FILE]", file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
