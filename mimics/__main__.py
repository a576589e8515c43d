"""``python -m mimics`` runs the command line."""

from mimics.interfaces.cli.leave import console

console()
