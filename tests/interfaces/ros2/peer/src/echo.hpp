// `--echo`: one line per message, `topic type field=value ...`, with every field of the
// ROS 2 layout spelled out so a test can compare the values it sent, bit for bit:
// floats print with 9 significant digits and doubles with 17 (both round-trip exactly).
#pragma once

#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include "Clock.h"
#include "LaserScan.h"
#include "Odometry.h"
#include "PoseStamped.h"
#include "TFMessage.h"

namespace peer::echo {

class Line {
 public:
  void number(const std::string& key, double value) { field(key, exact(value, 17)); }
  void number(const std::string& key, float value) { field(key, exact(value, 9)); }
  void integer(const std::string& key, long long value) { field(key, std::to_string(value)); }
  void text(const std::string& key, const std::string& value) { field(key, '"' + value + '"'); }
  template <typename Number>
  void numbers(const std::string& key, const Number* values, size_t count, int digits) {
    std::string joined = "[";
    for (size_t i = 0; i < count; ++i) joined += (i ? "," : "") + exact(values[i], digits);
    field(key, joined + "]");
  }
  std::string str() const { return out_.str(); }

 private:
  static std::string exact(double value, int digits) {
    char buffer[40];
    std::snprintf(buffer, sizeof buffer, "%.*g", digits, value);
    return buffer;
  }
  void field(const std::string& key, const std::string& value) { out_ << ' ' << key << '=' << value; }
  std::ostringstream out_;
};

inline void put(Line& line, const std::string& key, const builtin_interfaces::msg::Time& t) {
  line.integer(key + ".sec", t.sec());
  line.integer(key + ".nanosec", t.nanosec());
}

inline void put(Line& line, const std::string& key, const std_msgs::msg::Header& h) {
  put(line, key + ".stamp", h.stamp());
  line.text(key + ".frame_id", h.frame_id());
}

inline void put(Line& line, const std::string& key, const geometry_msgs::msg::Vector3& v) {
  line.number(key + ".x", v.x());
  line.number(key + ".y", v.y());
  line.number(key + ".z", v.z());
}

inline void put(Line& line, const std::string& key, const geometry_msgs::msg::Point& p) {
  line.number(key + ".x", p.x());
  line.number(key + ".y", p.y());
  line.number(key + ".z", p.z());
}

inline void put(Line& line, const std::string& key, const geometry_msgs::msg::Quaternion& q) {
  line.number(key + ".x", q.x());
  line.number(key + ".y", q.y());
  line.number(key + ".z", q.z());
  line.number(key + ".w", q.w());
}

inline void put(Line& line, const std::string& key, const geometry_msgs::msg::Pose& p) {
  put(line, key + ".position", p.position());
  put(line, key + ".orientation", p.orientation());
}

inline void put(Line& line, const nav_msgs::msg::Odometry& m) {
  put(line, "header", m.header());
  line.text("child_frame_id", m.child_frame_id());
  put(line, "pose.pose", m.pose().pose());
  line.numbers("pose.covariance", m.pose().covariance().data(), 36, 17);
  put(line, "twist.twist.linear", m.twist().twist().linear());
  put(line, "twist.twist.angular", m.twist().twist().angular());
  line.numbers("twist.covariance", m.twist().covariance().data(), 36, 17);
}

inline void put(Line& line, const sensor_msgs::msg::LaserScan& m) {
  put(line, "header", m.header());
  line.number("angle_min", m.angle_min());
  line.number("angle_max", m.angle_max());
  line.number("angle_increment", m.angle_increment());
  line.number("time_increment", m.time_increment());
  line.number("scan_time", m.scan_time());
  line.number("range_min", m.range_min());
  line.number("range_max", m.range_max());
  line.numbers("ranges", m.ranges().data(), m.ranges().size(), 9);
  line.numbers("intensities", m.intensities().data(), m.intensities().size(), 9);
}

inline void put(Line& line, const rosgraph_msgs::msg::Clock& m) { put(line, "clock", m.clock()); }

inline void put(Line& line, const geometry_msgs::msg::PoseStamped& m) {
  put(line, "header", m.header());
  put(line, "pose", m.pose());
}

inline void put(Line& line, const tf2_msgs::msg::TFMessage& m) {
  line.integer("transforms.size", static_cast<long long>(m.transforms().size()));
  for (size_t i = 0; i < m.transforms().size(); ++i) {
    const auto& t = m.transforms()[i];
    const std::string key = "transforms[" + std::to_string(i) + "]";
    put(line, key + ".header", t.header());
    line.text(key + ".child_frame_id", t.child_frame_id());
    put(line, key + ".transform.translation", t.transform().translation());
    put(line, key + ".transform.rotation", t.transform().rotation());
  }
}

}  // namespace peer::echo
