// The peer's controller: plain 2-D geometry, no DDS, so it reads like the contract.
#pragma once

#include <algorithm>
#include <cmath>

namespace peer {

constexpr double kMaxLinear = 0.5;   // m/s
constexpr double kMaxAngular = 1.5;  // rad/s
constexpr double kGoalTolerance = 0.1;  // m: stop (and count as arrived) inside this

struct Pose2D {
  double x = 0.0;
  double y = 0.0;
  double yaw = 0.0;
};

struct Command {
  double linear = 0.0;
  double angular = 0.0;
};

inline double wrap_angle(double angle) { return std::atan2(std::sin(angle), std::cos(angle)); }

inline double yaw_of(double qx, double qy, double qz, double qw) {
  return std::atan2(2.0 * (qw * qz + qx * qy), 1.0 - 2.0 * (qy * qy + qz * qz));
}

// The pose in `map` of a pose given in the robot's odom frame, whose origin is `start` in map.
inline Pose2D compose(const Pose2D& start, const Pose2D& in_odom) {
  const double c = std::cos(start.yaw), s = std::sin(start.yaw);
  return {start.x + c * in_odom.x - s * in_odom.y, start.y + s * in_odom.x + c * in_odom.y,
          wrap_angle(start.yaw + in_odom.yaw)};
}

inline double distance(const Pose2D& pose, double gx, double gy) {
  return std::hypot(gx - pose.x, gy - pose.y);
}

// Turn toward the goal, drive forward only while roughly facing it, stop inside the tolerance.
inline Command go_to_goal(const Pose2D& pose, double gx, double gy) {
  const double remaining = distance(pose, gx, gy);
  if (remaining < kGoalTolerance) return {};
  const double heading_error = wrap_angle(std::atan2(gy - pose.y, gx - pose.x) - pose.yaw);
  const double facing = std::max(0.0, std::cos(heading_error));
  return {std::clamp(0.8 * remaining, 0.0, kMaxLinear) * facing,
          std::clamp(2.0 * heading_error, -kMaxAngular, kMaxAngular)};
}

}  // namespace peer
