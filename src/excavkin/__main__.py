"""``python -m excavkin`` runs the command line."""

from excavkin.cli import main

main()
