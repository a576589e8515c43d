mimics battery compare compare
mimics battery compare compare --baseline wall_aware --metric path_length --metric success --csv compare.csv
