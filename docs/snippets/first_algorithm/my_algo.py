# my_algo.py: head for the goal; when something is close in front, turn away from it
import numpy as np

SAFE = 0.8  # m: closer than this in front and we turn


def step(robot):
    x, y, theta = robot.pose              # measured pose (m, m, rad)
    gx, gy = robot.goal                   # this robot's goal (m)
    ranges = robot.scan.ranges            # one distance per laser beam (m)
    angles = robot.scan.angles            # beam angles, relative to the heading (rad)

    front = np.abs(angles) < np.radians(30)
    if ranges[front].min() < SAFE:
        # something ahead: slow down and turn toward the side that reads farther
        left = ranges[angles > 0].mean()
        right = ranges[angles < 0].mean()
        turn = 0.6 if left > right else -0.6
        robot.log("avoiding")
        return 0.05, theta + turn
    return robot.type.max_speed, np.arctan2(gy - y, gx - x)
