mimics run two_robots.toml my_algo.py --out runs/two
