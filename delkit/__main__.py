"""``python -m delkit``: the ``delkit`` command."""

from delkit.cli import run

if __name__ == "__main__":
    run()
