"""The simulation: state, step and kernels (knows nothing of files, terminals or screens).

Numba is set up for the engine before any kernel loads (``numba_setup``): a warm
run's kernels come from the disk cache without the parts of Numba only a compile
needs.
"""

from mimics.engine.numba_setup import set_up_numba

set_up_numba()
