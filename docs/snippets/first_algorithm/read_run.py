# read_run.py: what happened, from the run folder
import mimics

run = mimics.load_run("runs/mine")
print(run.summary["reached_goal"], "of", run.summary["robots"], "reached their goal")
print(run.events[["time", "robot", "kind", "detail"]])

robot0 = run.robot(0)                     # robot 0's rows: time, x, y, theta, v, w, ...
print(robot0[["time", "x", "y", "v"]].tail())
