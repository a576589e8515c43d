"""The numbers of ``scripted_node.py``, shared with the tests (no ROS import here)."""

DT = 0.1  # the line scenario's step
MALFORMED = {5: "nan", 8: "length"}  # step answered -> what goes wrong
TWIST_SPEED, TWIST_RATE = 0.4, 0.5  # robot 1's constant cmd_vel


def reference_speed(step):
    """Robot 0's speed reference answering step ``step``: a different one each step."""
    return 0.1 + 0.05 * (step % 7)


def reference_heading(step):
    """Robot 0's heading reference answering step ``step``."""
    return 0.01 * step
