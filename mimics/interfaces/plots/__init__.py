"""Static plots: one run's trajectories, and a battery's outcomes and timings.

``plot_run`` draws every robot's path over the map, coloured by its final state,
with a mark where each robot was deactivated (or stood at the end) and a star
where a livelock was detected. ``battery_plots`` writes a battery folder's
figures: robot outcomes and run statuses per algorithm x scenario x parameter
point, the time to goal of each run (its restricted mean: robots that never
arrived counted at the horizon) and the arrival curves (Kaplan-Meier fraction
of goal robots arrived against time), a panel per parameter point, and the
paper's Figure 2 (wall time against number of robots, from the runs of the
``line`` scenario).

>>> from mimics.interfaces.plots import FINAL_MARKS
>>> FINAL_MARKS[1]
('o', 'reached goal')

The figures are in :mod:`~mimics.interfaces.plots.run_plot` (one run),
:mod:`~mimics.interfaces.plots.battery_table` (a battery's runs as a table) and
:mod:`~mimics.interfaces.plots.battery_figures` (a battery's figures, with
:mod:`~mimics.interfaces.plots.battery_time_to_goal` and
:mod:`~mimics.interfaces.plots.battery_arrivals`), sharing
:mod:`~mimics.interfaces.plots.figures`.
"""

from mimics.interfaces.plots.battery_arrivals import plot_arrivals
from mimics.interfaces.plots.battery_figures import (
    OUTCOMES,
    RUN_STATUS_COLORS,
    battery_plots,
    plot_outcomes,
    plot_wall_time_vs_robots,
)
from mimics.interfaces.plots.battery_table import battery_table
from mimics.interfaces.plots.battery_time_to_goal import plot_time_to_goal
from mimics.interfaces.plots.figures import _new_figure, _save
from mimics.interfaces.plots.run_plot import FINAL_MARKS, plot_run

__all__ = ["FINAL_MARKS", "OUTCOMES", "RUN_STATUS_COLORS", "_new_figure", "_save",
           "battery_plots", "battery_table", "plot_arrivals", "plot_outcomes", "plot_run",
           "plot_time_to_goal", "plot_wall_time_vs_robots"]
