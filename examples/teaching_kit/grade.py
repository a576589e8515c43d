"""Marks for "Crossing without collisions", out of 10, one row per submitted file.

Per run: 6 points times the fraction of robots that reached their goal, plus
4 points if no robot collided. A run that did not finish (an exception under
the abort policy, a time-out, a crash) scores 0. The mark is the mean over
all the runs of the submission, rounded to a tenth.
"""

import pandas as pd


def grade(runs: pd.DataFrame) -> pd.DataFrame:
    """One row per submitted file: runs, goals reached, collisions, and the mark."""
    finished = runs["state"] == "done"
    robots = runs["robots"].fillna(0).astype(float)
    reached = runs["reached_goal"].fillna(0).astype(float)
    collided = runs["collisions"].fillna(0).astype(float)
    goal_points = 6.0 * (reached / robots.where(robots > 0, 1.0))
    safety_points = 4.0 * (collided == 0)
    runs = runs.assign(points=(goal_points + safety_points).where(finished, 0.0),
                       student=runs["algorithm"])  # the submitted file's name, no .py
    table = runs.groupby("student").agg(runs=("points", "size"),
                                         reached=("reached_goal", "sum"),
                                         collisions=("collisions", "sum"),
                                         mark=("points", "mean"))
    table["mark"] = table["mark"].round(1)
    return table.sort_values("mark", ascending=False)
