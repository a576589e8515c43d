"""The states of a battery's runs, apart from the code that runs them.

``done``: the run ended normally (possibly with robots deactivated for
exceptions under the ``deactivate`` policy); ``error``: an exception under
``abort``, or the run could not start; ``timeout``: past the wall-clock limit;
``crashed``: the worker process died. The last three are failed runs.
"""

STATES = ("pending", "running", "done", "error", "timeout", "crashed")
FAILED_STATES = ("error", "timeout", "crashed")
UNFINISHED_STATES = ("pending", "running")
