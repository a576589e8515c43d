"""mimics in Jupyter: runs, batteries and a live view that show themselves in a cell.

:mod:`~mimics.interfaces.notebook.run` (``RunView``: what ``mimics.simulate``
and ``mimics.load_run`` return), :mod:`~mimics.interfaces.notebook.animation`
(the replay as an inline video), :mod:`~mimics.interfaces.notebook.battery`
(``BatteryView``: ``mimics.run_battery`` and ``mimics.load_battery``) and
:mod:`~mimics.interfaces.notebook.live` (``mimics.show``: a widget stepping a
simulation). Nothing here imports IPython or the widgets until a cell needs them.
"""
