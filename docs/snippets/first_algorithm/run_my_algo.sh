mimics run circle_swap my_algo.py --robots 6 --time 40 --out runs/mine
mimics plot runs/mine --out mine.png
