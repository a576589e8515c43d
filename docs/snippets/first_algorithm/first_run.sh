mimics list scenarios
mimics run line go_to_goal --robots 10 --time 25 --seed 1 --out runs/first
