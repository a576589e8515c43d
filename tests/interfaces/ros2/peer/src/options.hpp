// The peer's command line: `--robots N [--domain D] [--steps S] [--timeout SECONDS] [--echo ...]`.
#pragma once

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <set>
#include <string>

namespace {

struct Options {
  int robots = 1;
  int domain = 0;
  long steps = 0;          // 0: no limit
  double timeout = 300.0;  // wall-clock seconds
  bool echo = false;
  int echo_count = 3;
  std::set<std::string> echo_topics{"odom", "scan", "clock", "tf", "goal"};
};

constexpr const char* kUsage =
    "usage: mimics_ros2_peer --robots N [--domain D] [--steps S] [--timeout SECONDS]"
    " [--echo [--echo-count K] [--echo-topics odom,scan,clock,tf,goal,tf_static]]";

// One line on stderr, status 2: bad arguments or a set-up that cannot work.
[[noreturn]] void usage_error(const std::string& message) {
  std::cerr << "mimics_ros2_peer: error: " << message << std::endl;
  std::exit(2);
}

long parse_integer(const std::string& option, const char* text, long lowest) {
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  if (*text == '\0' || *end != '\0' || value < lowest)
    usage_error(option + " expects an integer >= " + std::to_string(lowest) + ", got '" + text +
                "'");
  return value;
}

Options parse(int argc, char** argv) {
  Options options;
  if (const char* domain = std::getenv("ROS_DOMAIN_ID"); domain && *domain)
    options.domain = static_cast<int>(parse_integer("ROS_DOMAIN_ID", domain, 0));
  for (int i = 1; i < argc; ++i) {
    const std::string option = argv[i];
    if (option == "--help") {
      std::cout << kUsage << std::endl;
      std::exit(0);
    }
    if (option == "--echo") {
      options.echo = true;
      continue;
    }
    if (i + 1 >= argc) usage_error("unknown option or missing value: " + option + " (--help)");
    const char* value = argv[++i];
    if (option == "--robots") {
      options.robots = static_cast<int>(parse_integer(option, value, 1));
    } else if (option == "--domain") {
      options.domain = static_cast<int>(parse_integer(option, value, 0));
    } else if (option == "--steps") {
      options.steps = parse_integer(option, value, 1);
    } else if (option == "--timeout") {
      options.timeout = static_cast<double>(parse_integer(option, value, 1));
    } else if (option == "--echo-count") {
      options.echo_count = static_cast<int>(parse_integer(option, value, 1));
    } else if (option == "--echo-topics") {
      options.echo_topics.clear();
      std::string list = value;
      for (size_t start = 0; start <= list.size();) {
        const size_t comma = std::min(list.find(',', start), list.size());
        const std::string name = list.substr(start, comma - start);
        if (name != "odom" && name != "scan" && name != "clock" && name != "tf" &&
            name != "goal" && name != "tf_static")
          usage_error("--echo-topics: unknown topic '" + name +
                      "' (expected odom, scan, clock, tf, goal, tf_static)");
        options.echo_topics.insert(name);
        start = comma + 1;
      }
    } else {
      usage_error("unknown option: " + option + " (--help)");
    }
  }
  if (options.domain > 232) usage_error("--domain expects 0 to 232 (UDP ports run out above)");
  return options;
}

}  // namespace
