"""Errors for bad input: each names the file, key or argument and what was expected."""


class MimicsError(Exception):
    """Base of every error mimics raises on purpose; the CLI prints it in one line, exit 2."""


class ScenarioError(MimicsError, ValueError):
    """A scenario, robot type or map is malformed."""


class AlgorithmError(MimicsError, ValueError):
    """An algorithm cannot be found or does not follow the contract."""
