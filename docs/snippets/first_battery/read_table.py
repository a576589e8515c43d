# read_table.py: the battery's table with pandas
import pandas as pd

table = pd.read_csv("night.csv")
print(table[["algorithm", "param_robots", "seed", "state", "reached_goal", "collisions"]])

# mean collisions per algorithm and crowd size
means = table.groupby(["algorithm", "param_robots"])["collisions"].mean()
print(means)

# mean robots home per algorithm and crowd size
reached = table.groupby(["algorithm", "param_robots"])["reached_goal"].mean()
print(reached)
