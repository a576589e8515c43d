"""The ``mimics`` command line: one module per group of commands, mounted in ``main``."""

from mimics.interfaces.cli.program import app, main

__all__ = ["app", "main"]
