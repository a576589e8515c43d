mimics battery report night --csv night.csv
mimics battery plot night --out night-plots
