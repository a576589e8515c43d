from mimics.batteries import runs_table
from mimics.batteries.comparison import cell_intervals, paired_comparison

table = runs_table("compare")  # one row per run, one column per metric
pairs = paired_comparison(table, "go_to_goal", ["path_length", "success"])  # a DataFrame
print(pairs[["algorithm", "metric", "pairs", "mean_difference", "ci95_low", "ci95_high",
             "p_value", "note"]])
print(cell_intervals(table, ["path_length"]))
