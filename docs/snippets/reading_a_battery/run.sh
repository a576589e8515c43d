mimics battery run line.toml --out line --workers 2
mimics battery compare line --metric success --metric time_to_goal --metric time_to_goal_arrived
mimics battery plot line
