"""``python -m flexlib``: the command line (:mod:`flexlib.cli`)."""

from flexlib.cli import main

main()
