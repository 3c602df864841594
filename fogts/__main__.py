"""``python -m fogts`` runs the command line."""

from fogts.cli import main

main()
