"""Marks for "Crossing without collisions", out of 10, one row per submitted file.

Per run, with ``fraction`` the share of robots that reached their goal:
10 points times ``fraction`` if no robot collided, 6 points times ``fraction``
if any did. A robot team that never moves reaches no goal and scores 0, however
safe it stays. A run that did not finish (an exception under the abort policy,
a NaN or malformed output, a time-out, a crash) scores 0. The mark is the mean
over all the runs of the submission, rounded to a tenth.
"""

import pandas as pd


def grade(runs: pd.DataFrame) -> pd.DataFrame:
    """One row per submitted file: runs, runs finished, goals reached, collisions, the mark."""
    finished = runs["state"] == "done"
    robots = runs["robots"].fillna(0).astype(float)
    reached = runs["reached_goal"].fillna(0).astype(float)
    collided = runs["collisions"].fillna(0).astype(float)
    fraction = reached / robots.where(robots > 0, 1.0)
    points = fraction * (10.0 * (collided == 0) + 6.0 * (collided > 0))
    runs = runs.assign(points=points.where(finished, 0.0), finished=finished,
                       student=runs["algorithm"])  # the submitted file's name, no .py
    table = runs.groupby("student").agg(runs=("points", "size"),
                                         finished=("finished", "sum"),
                                         reached=("reached_goal", "sum"),
                                         collisions=("collisions", "sum"),
                                         mark=("points", "mean"))
    table["mark"] = table["mark"].round(1)
    return table.sort_values("mark", ascending=False)
