mimics run corridor my_algo.py --robots 4 --time 40 --out runs/corridor
mimics run corridor my_algo.py --param robots=6 --param width=4.0 --time 40 --out runs/wide
