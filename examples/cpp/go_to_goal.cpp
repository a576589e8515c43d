// go_to_goal.cpp: the go-to-goal algorithm as a C++ class behind the C entry point.
//
// Same logic as the built-in Python go_to_goal (mimics/algorithms/go_to_goal.py)
// and examples/c/go_to_goal.c: head for the goal at full speed when facing it,
// slower the more it is off. The class keeps how many steps the robot has driven
// in the robot's memory block, to show where per-robot state lives.
//
//   mimics run line examples/cpp/go_to_goal.cpp --robots 10
#include <algorithm>
#include <cmath>
#include <new>

#include "mimics.h"

namespace {

struct Command {
    double speed;
    double heading;
};

class GoToGoal {
public:
    Command step(const mimics_robot &robot) {
        ++steps_;
        const double x = robot.pose[0], y = robot.pose[1], theta = robot.pose[2];
        if (!robot.has_goal) return {0.0, theta};
        const double heading = std::atan2(robot.goal[1] - y, robot.goal[0] - x);
        const double alignment = std::cos(heading - theta);
        return {robot.max_speed * std::max(alignment, 0.0), heading};
    }

    long steps() const { return steps_; }

private:
    long steps_ = 0;
};

static_assert(sizeof(GoToGoal) <= MIMICS_MEMORY_BYTES, "GoToGoal must fit in the memory block");

// The robot's memory block holds its GoToGoal (built there by mimics_reset).
GoToGoal &controller_of(const mimics_robot *robot) {
    return *std::launder(reinterpret_cast<GoToGoal *>(robot->memory));
}

}  // namespace

extern "C" int mimics_reset(const mimics_robot *robot, mimics_output *) {
    new (robot->memory) GoToGoal();  // trivially destructible: nothing to clean up
    return 0;
}

extern "C" int mimics_step(const mimics_robot *robot, mimics_output *out) {
    try {  // no C++ exception may cross into C
        Command command = controller_of(robot).step(*robot);
        out->speed = command.speed;
        out->heading = command.heading;
        return 0;
    } catch (...) {
        mimics_log(out, "go_to_goal.cpp: unexpected C++ exception");
        return 1;
    }
}
