// A ROS 1 node (roscpp) that drives mimics robots to their goals.
//
// The same logic as mimics' built-in go_to_goal and as go_to_goal_node.py:
// head for the goal, at full speed when facing it, slower the more it is off.
// Build it with the system's compiler against Debian's libroscpp-dev:
//
//   g++ -O2 -o go_to_goal_node examples/ros/go_to_goal_node.cpp \
//       $(pkg-config --cflags --libs roscpp std_msgs nav_msgs geometry_msgs)
//
// and run it beside `mimics ros line --robots 5`:  ./go_to_goal_node 5
//
// It reads every robot's latched goal first, then answers each
// /robot_i/pose (the positioning sensor's pose in map; /robot_i/odom is the
// odometer, in the robot's odom frame) with one /robot_i/cmd: [speed_ref,
// heading_ref, stamp], the stamp being the pose's, so that in lockstep the
// bridge knows which step the reference answers. Stop it with Ctrl-C.

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <std_msgs/Float64MultiArray.h>

struct Robot {
  bool has_goal = false;
  double goal_x = 0.0, goal_y = 0.0;
  ros::Publisher cmd;
};

int main(int argc, char** argv) {
  ros::init(argc, argv, "go_to_goal_cpp");
  if (argc < 2) {
    ROS_ERROR("usage: go_to_goal_node ROBOTS [MAX_SPEED]");
    return 2;
  }
  const int count = std::atoi(argv[1]);
  const double max_speed = argc > 2 ? std::atof(argv[2]) : 1.0;  // the Pioneer 3-AT's
  ros::NodeHandle node;
  std::vector<Robot> robots(count);
  std::vector<ros::Subscriber> subscribers;

  for (int i = 0; i < count; ++i) {
    const std::string name = "/robot_" + std::to_string(i);
    subscribers.push_back(node.subscribe<geometry_msgs::PoseStamped>(
        name + "/goal", 1, [&robots, i](const geometry_msgs::PoseStamped::ConstPtr& goal) {
          robots[i].goal_x = goal->pose.position.x;
          robots[i].goal_y = goal->pose.position.y;
          robots[i].has_goal = true;
        }));
  }
  // goals are latched: they come as soon as we subscribe
  auto all_goals = [&robots] {
    for (const Robot& robot : robots)
      if (!robot.has_goal) return false;
    return true;
  };
  // wall time: with /use_sim_time set, simulated time starts only once we subscribe
  ros::WallRate poll(100);
  while (ros::ok() && !all_goals()) {
    ros::spinOnce();
    poll.sleep();
  }

  for (int i = 0; i < count; ++i) {
    const std::string name = "/robot_" + std::to_string(i);
    robots[i].cmd = node.advertise<std_msgs::Float64MultiArray>(name + "/cmd", 10);
    subscribers.push_back(node.subscribe<nav_msgs::Odometry>(
        name + "/pose", 10,
        [&robots, i, max_speed](const nav_msgs::Odometry::ConstPtr& odom) {
          const auto& pose = odom->pose.pose;
          const auto& q = pose.orientation;
          const double yaw = std::atan2(2.0 * (q.w * q.z + q.x * q.y),
                                        1.0 - 2.0 * (q.y * q.y + q.z * q.z));
          const Robot& robot = robots[i];
          const double heading = std::atan2(robot.goal_y - pose.position.y,
                                            robot.goal_x - pose.position.x);
          std_msgs::Float64MultiArray cmd;
          cmd.data = {max_speed * std::max(std::cos(heading - yaw), 0.0), heading,
                      odom->header.stamp.toSec()};
          robot.cmd.publish(cmd);
        },
        ros::VoidConstPtr(), ros::TransportHints().tcpNoDelay()));
  }
  ros::spin();
  return 0;
}
