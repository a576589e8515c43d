"""The simulation: state, step and kernels (knows nothing of files, terminals or screens).

At this level, the step and its physics: ``simulation`` (the step), ``state``,
``dynamics``, ``sensors``, ``collision``, ``motion_checks``, ``stall``, ``deactivations``,
``outcome``, ``messages``, ``edits`` and the indexes. Beside them, in folders with one
face each: ``ranging/`` (the lasers, cast), ``helper_threads/`` (the step's work split
over threads), ``user_code/`` (calling the user's algorithm: its views, time limit and
failures) and ``compiling/`` (compiling and loading the kernels; importing it sets Numba
up first, so a warm run's kernels come from the disk cache without the parts of Numba
only a compile needs).
"""

import mimics.engine.compiling  # noqa: F401  (Numba set up before any kernel loads)
