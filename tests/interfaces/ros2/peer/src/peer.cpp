// mimics_ros2_peer: an independent ROS 2 node for the tests of `mimics ros2`, written with
// Debian's Fast DDS and types that fastddsgen generates from ROS 2's message definitions.
//
// Per robot i it reads rt/robot_i/odom, rt/robot_i/scan and rt/robot_i/goal (plus rt/clock,
// rt/tf, rt/tf_static) and answers every odometry message with exactly one Twist on
// rt/robot_i/cmd_vel that steers toward the goal (lockstep: the simulator waits for it).
// The robot's pose in `map` is its odometry pose composed with the transform
// map -> robot_i/odom that rt/tf (or rt/tf_static) carries: the odometry frame starts at the
// robot's start pose, so that transform is the start pose. An odometry message that arrives
// before that transform or before the goal waits, unanswered, until both are known.
//
// It ends with status 0 after --steps clock ticks, once every robot has stayed within 0.1 m
// of its goal for 1 s of sim time, once --echo has printed what it was asked for, or on
// SIGINT/SIGTERM; with status 1 after --timeout wall-clock seconds; with status 2 (one line
// on stderr) on bad arguments or set-up. It prints `robot i final x y goal gx gy` (map) per
// robot, and on stderr how many odometry messages and Twists each robot had.
// --echo prints `echo TOPIC TYPE field=value ...` for the first --echo-count messages of each
// topic (the latched goal and tf_static: the first one), and `writer TOPIC TYPE` for every
// writer it discovers, with the type name that writer announced.
//
// It runs only with a Fast DDS XML profile (FASTRTPS_DEFAULT_PROFILES_FILE) whose default
// participant turns the built-in transports off: the tests' profile keeps traffic on loopback.

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/domain/DomainParticipantListener.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include <chrono>
#include <cmath>
#include <condition_variable>
#include <csignal>
#include <cstdio>
#include <deque>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <vector>

#include "ClockPubSubTypes.h"
#include "LaserScanPubSubTypes.h"
#include "OdometryPubSubTypes.h"
#include "PoseStampedPubSubTypes.h"
#include "TFMessagePubSubTypes.h"
#include "TwistPubSubTypes.h"
#include "echo.hpp"
#include "go_to_goal.hpp"
#include "options.hpp"

using namespace eprosima::fastdds::dds;

namespace {

volatile std::sig_atomic_t stop_requested = 0;

extern "C" void request_stop(int) { stop_requested = 1; }

// Hands each valid sample of one reader to a handler.
template <typename Message>
class Inbox : public DataReaderListener {
 public:
  explicit Inbox(std::function<void(const Message&)> handler) : handler_(std::move(handler)) {}
  void on_data_available(DataReader* reader) override {
    Message message;
    SampleInfo info;
    while (reader->take_next_sample(&message, &info) == ReturnCode_t::RETCODE_OK)
      if (info.valid_data) handler_(message);
  }

 private:
  std::function<void(const Message&)> handler_;
};

// Prints every remote writer's topic and type: the type names the other side announces.
class Discovery : public DomainParticipantListener {
 public:
  explicit Discovery(std::mutex& print_lock) : print_lock_(print_lock) {}
  void on_publisher_discovery(DomainParticipant*,
                              eprosima::fastrtps::rtps::WriterDiscoveryInfo&& info) override {
    if (info.status != eprosima::fastrtps::rtps::WriterDiscoveryInfo::DISCOVERED_WRITER) return;
    std::lock_guard<std::mutex> guard(print_lock_);
    std::cout << "writer " << info.info.topicName() << " " << info.info.typeName() << std::endl;
  }

 private:
  std::mutex& print_lock_;
};

struct Robot {
  bool has_start = false;
  bool has_goal = false;
  bool has_pose = false;
  peer::Pose2D start;
  double goal_x = NAN;
  double goal_y = NAN;
  peer::Pose2D pose;                   // latest, in map
  std::deque<peer::Pose2D> unanswered;  // odometry poses (odom frame) still owed a Twist
  long odometry_count = 0;
  long twist_count = 0;
  DataWriter* cmd_vel = nullptr;
};

double seconds(const builtin_interfaces::msg::Time& t) { return t.sec() + t.nanosec() * 1e-9; }

std::string without_leading_slash(const std::string& frame) {
  return !frame.empty() && frame[0] == '/' ? frame.substr(1) : frame;
}

class Peer {
 public:
  explicit Peer(const Options& options) : options_(options), robots_(options.robots) {}

  int run() {
    if (!std::getenv("FASTRTPS_DEFAULT_PROFILES_FILE"))
      usage_error("FASTRTPS_DEFAULT_PROFILES_FILE is not set (the peer runs only with an XML "
                  "profile that chooses its transports)");
    auto* factory = DomainParticipantFactory::get_instance();
    if (factory->load_profiles() != ReturnCode_t::RETCODE_OK)
      usage_error("cannot load the XML profile in FASTRTPS_DEFAULT_PROFILES_FILE");
    DomainParticipantQos qos = factory->get_default_participant_qos();
    if (qos.transport().use_builtin_transports)
      usage_error("the default participant profile keeps Fast DDS's built-in transports on "
                  "(expected useBuiltinTransports=false)");
    qos.name("mimics_ros2_peer");
    discovery_ = std::make_unique<Discovery>(print_lock_);
    participant_ = factory->create_participant(
        // no statuses: the readers' own listeners keep their data callbacks
        options_.domain, qos, options_.echo ? discovery_.get() : nullptr, StatusMask::none());
    if (!participant_) usage_error("Fast DDS could not create a participant");
    subscriber_ = participant_->create_subscriber(SUBSCRIBER_QOS_DEFAULT);
    publisher_ = participant_->create_publisher(PUBLISHER_QOS_DEFAULT);
    subscribe_all();
    const auto deadline = std::chrono::steady_clock::now() +
                          std::chrono::milliseconds(static_cast<long>(options_.timeout * 1000));
    bool finished;
    {
      std::unique_lock<std::mutex> lock(state_lock_);
      // a signal (SIGINT, SIGTERM) ends the run as done: the report is still printed
      while (!done_ && !stop_requested && std::chrono::steady_clock::now() < deadline)
        changed_.wait_for(lock, std::chrono::milliseconds(50));
      finished = done_ || stop_requested;
      done_ = true;
      report();
    }
    participant_->delete_contained_entities();
    factory->delete_participant(participant_);
    if (!finished) {
      std::cerr << "mimics_ros2_peer: error: not done within --timeout " << options_.timeout
                << " s" << std::endl;
      return 1;
    }
    return 0;
  }

 private:
  template <typename Message, typename PubSub>
  DataReader* subscribe(const std::string& topic_name, ReliabilityQosPolicyKind reliability,
                        DurabilityQosPolicyKind durability, const std::string& short_name,
                        std::function<void(const Message&)> handler) {
    Topic* topic = make_topic<PubSub>(topic_name);
    DataReaderQos qos = DATAREADER_QOS_DEFAULT;
    qos.reliability().kind = reliability;
    qos.durability().kind = durability;
    qos.history().kind = KEEP_LAST_HISTORY_QOS;
    qos.history().depth = 10;
    // fastddsgen sizes unbounded sequences for 100 items: scans may be longer
    qos.endpoint().history_memory_policy =
        eprosima::fastrtps::rtps::DYNAMIC_REUSABLE_MEMORY_MODE;
    const bool echoed = options_.echo && options_.echo_topics.count(short_name);
    if (echoed) echo_left_[topic_name] = latched(short_name) ? 1 : options_.echo_count;
    auto inbox = std::make_unique<Inbox<Message>>(
        [this, handler, topic_name, echoed, type = topic->get_type_name()](const Message& m) {
          std::unique_lock<std::mutex> lock(state_lock_);
          if (done_) return;  // nothing more once done: the report stays true
          if (echoed) echo(topic_name, type, m);
          handler(m);
          check_done();
        });
    DataReader* reader = subscriber_->create_datareader(topic, qos, inbox.get());
    if (!reader) usage_error("cannot create a reader for " + topic_name);
    inboxes_.push_back(std::move(inbox));
    return reader;
  }

  template <typename PubSub>
  Topic* make_topic(const std::string& name) {
    TypeSupport type(new PubSub());
    type.register_type(participant_);  // once per type: later calls are no-ops
    Topic* topic = participant_->create_topic(name, type.get_type_name(), TOPIC_QOS_DEFAULT);
    if (!topic) usage_error("cannot create topic " + name);
    return topic;
  }

  static bool latched(const std::string& short_name) {
    return short_name == "goal" || short_name == "tf_static";
  }

  void subscribe_all() {
    const auto reliable = RELIABLE_RELIABILITY_QOS, best_effort = BEST_EFFORT_RELIABILITY_QOS;
    const auto is_volatile = VOLATILE_DURABILITY_QOS, transient = TRANSIENT_LOCAL_DURABILITY_QOS;
    for (int i = 0; i < options_.robots; ++i) {
      const std::string ns = "rt/robot_" + std::to_string(i) + "/";
      Topic* cmd_topic = make_topic<geometry_msgs::msg::TwistPubSubType>(ns + "cmd_vel");
      DataWriterQos qos = DATAWRITER_QOS_DEFAULT;
      qos.reliability().kind = reliable;
      qos.durability().kind = is_volatile;  // Fast DDS's default is transient local
      qos.history().kind = KEEP_LAST_HISTORY_QOS;
      qos.history().depth = 10;
      qos.representation().m_value = {XCDR_DATA_REPRESENTATION};  // XCDR1, as ROS 2 sends
      robots_[i].cmd_vel = publisher_->create_datawriter(cmd_topic, qos);
      if (!robots_[i].cmd_vel) usage_error("cannot create a writer for " + ns + "cmd_vel");
      subscribe<nav_msgs::msg::Odometry, nav_msgs::msg::OdometryPubSubType>(
          ns + "odom", reliable, is_volatile, "odom",
          [this, i](const nav_msgs::msg::Odometry& m) { on_odometry(i, m); });
      subscribe<sensor_msgs::msg::LaserScan, sensor_msgs::msg::LaserScanPubSubType>(
          ns + "scan", best_effort, is_volatile, "scan", [](const auto&) {});
      subscribe<geometry_msgs::msg::PoseStamped, geometry_msgs::msg::PoseStampedPubSubType>(
          ns + "goal", reliable, transient, "goal",
          [this, i](const geometry_msgs::msg::PoseStamped& m) {
            robots_[i].goal_x = m.pose().position().x();
            robots_[i].goal_y = m.pose().position().y();
            robots_[i].has_goal = true;
            answer(i);
          });
    }
    subscribe<rosgraph_msgs::msg::Clock, rosgraph_msgs::msg::ClockPubSubType>(
        "rt/clock", best_effort, is_volatile, "clock", [this](const rosgraph_msgs::msg::Clock& m) {
          ++clock_ticks_;
          sim_time_ = std::max(sim_time_, seconds(m.clock()));
        });
    auto on_tf = [this](const tf2_msgs::msg::TFMessage& m) { on_transforms(m); };
    subscribe<tf2_msgs::msg::TFMessage, tf2_msgs::msg::TFMessagePubSubType>(
        "rt/tf", reliable, is_volatile, "tf", on_tf);
    subscribe<tf2_msgs::msg::TFMessage, tf2_msgs::msg::TFMessagePubSubType>(
        "rt/tf_static", reliable, transient, "tf_static", on_tf);
  }

  void on_odometry(int i, const nav_msgs::msg::Odometry& m) {
    const auto& p = m.pose().pose();
    const auto& q = p.orientation();
    robots_[i].unanswered.push_back(
        {p.position().x(), p.position().y(), peer::yaw_of(q.x(), q.y(), q.z(), q.w())});
    ++robots_[i].odometry_count;
    sim_time_ = std::max(sim_time_, seconds(m.header().stamp()));
    answer(i);
  }

  // map -> robot_i/odom: robot i's start pose
  void on_transforms(const tf2_msgs::msg::TFMessage& m) {
    for (const auto& t : m.transforms()) {
      if (without_leading_slash(t.header().frame_id()) != "map") continue;
      for (int i = 0; i < options_.robots; ++i) {
        if (without_leading_slash(t.child_frame_id()) != "robot_" + std::to_string(i) + "/odom")
          continue;
        const auto& r = t.transform().rotation();
        robots_[i].start = {t.transform().translation().x(), t.transform().translation().y(),
                            peer::yaw_of(r.x(), r.y(), r.z(), r.w())};
        robots_[i].has_start = true;
        answer(i);
      }
    }
  }

  // One Twist per odometry message, once the start pose and the goal are known.
  void answer(int i) {
    Robot& robot = robots_[i];
    if (!robot.has_start || !robot.has_goal) return;
    while (!robot.unanswered.empty()) {
      robot.pose = peer::compose(robot.start, robot.unanswered.front());
      robot.has_pose = true;
      robot.unanswered.pop_front();
      const peer::Command command = peer::go_to_goal(robot.pose, robot.goal_x, robot.goal_y);
      geometry_msgs::msg::Twist twist;
      twist.linear().x(command.linear);
      twist.angular().z(command.angular);
      robot.cmd_vel->write(&twist);
      ++robot.twist_count;
    }
  }

  template <typename Message>
  void echo(const std::string& topic, const std::string& type, const Message& m) {
    auto left = echo_left_.find(topic);
    if (left == echo_left_.end() || left->second == 0) return;
    --left->second;
    peer::echo::Line line;
    peer::echo::put(line, m);
    std::lock_guard<std::mutex> guard(print_lock_);
    std::cout << "echo " << topic << " " << type << line.str() << std::endl;
  }

  // Called with state_lock_ held after every message.
  void check_done() {
    bool all_arrived = true;
    for (const Robot& robot : robots_)
      all_arrived = all_arrived && robot.has_pose &&
                    peer::distance(robot.pose, robot.goal_x, robot.goal_y) < peer::kGoalTolerance;
    if (!all_arrived) {
      arrived_since_ = NAN;
    } else if (std::isnan(arrived_since_)) {
      arrived_since_ = sim_time_;
    }
    bool echoed_all = options_.echo;
    for (const auto& [topic, left] : echo_left_) echoed_all = echoed_all && left == 0;
    const bool stayed = !std::isnan(arrived_since_) && sim_time_ - arrived_since_ >= 1.0;
    if ((options_.steps > 0 && clock_ticks_ >= options_.steps) || stayed || echoed_all) {
      done_ = true;
      changed_.notify_all();
    }
  }

  void report() {
    std::lock_guard<std::mutex> guard(print_lock_);
    for (int i = 0; i < options_.robots; ++i) {
      const Robot& robot = robots_[i];
      std::printf("robot %d final %.6f %.6f goal %.6f %.6f\n", i,
                  robot.has_pose ? robot.pose.x : NAN, robot.has_pose ? robot.pose.y : NAN,
                  robot.goal_x, robot.goal_y);
      std::fprintf(stderr, "mimics_ros2_peer: robot %d answered %ld odometry messages with %ld "
                   "twists\n", i, robot.odometry_count, robot.twist_count);
    }
    std::fflush(stdout);
  }

  Options options_;
  std::vector<Robot> robots_;
  std::mutex state_lock_;
  std::mutex print_lock_;
  std::condition_variable changed_;
  bool done_ = false;
  long clock_ticks_ = 0;
  double sim_time_ = 0.0;
  double arrived_since_ = NAN;
  std::map<std::string, int> echo_left_;
  std::unique_ptr<Discovery> discovery_;
  std::vector<std::unique_ptr<DataReaderListener>> inboxes_;
  DomainParticipant* participant_ = nullptr;
  Subscriber* subscriber_ = nullptr;
  Publisher* publisher_ = nullptr;
};

}  // namespace

int main(int argc, char** argv) {
  const Options options = parse(argc, argv);
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
  return Peer(options).run();
}
