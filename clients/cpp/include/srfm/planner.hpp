// The C++ client of srfm's external planner protocol (docs/planners-any-language.md).
//
// Write a class derived from srfm::Planner, then hand it to srfm::run from main():
//
//     int main(int argc, char** argv) {
//         return srfm::run([] { return std::make_unique<MyPlanner>(); }, argc, argv);
//     }
//
// Started by srfm (--external NAME=PROGRAM), the program connects to the socket srfm
// names in SRFM_PLANNER_ADDRESS and answers until srfm closes the connection. Started
// with --listen unix:PATH or --listen tcp:HOST:PORT, it listens there and answers every
// connection (one per benchmark worker) in a child process with a planner of its own.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace srfm {

// The protocol version this client speaks (srfm/planners/external/protocol.toml, `version`).
constexpr int kProtocolVersion = 1;

// What srfm says about an episode at its start (the reset message).
struct Episode {
    std::string scenario;
    std::int64_t seed = 0;  // seed any random generator from this, and from nothing else
    double dt_s = 0.0;
    std::int64_t horizon_steps = 0;
    std::string kinematics;  // "unicycle" (v, omega) or "holonomic" (vx, vy)
    double radius_m = 0.0;
    double max_speed_mps = 0.0;
    double max_angular_speed_radps = 0.0;
    double max_accel_mps2 = 0.0;
    double max_angular_accel_radps2 = 0.0;
    double goal_radius_m = 0.0;
    std::array<double, 2> goal{};
    std::array<double, 4> world{};  // x_min, y_min, x_max, y_max
    std::vector<std::array<double, 4>> walls;    // x1, y1, x2, y2
    std::vector<std::array<double, 3>> pillars;  // x, y, radius

    bool holonomic() const { return kinematics == "holonomic"; }
};

// One observed pedestrian.
struct Pedestrian {
    std::int64_t id = 0;
    double x = 0.0, y = 0.0, vx = 0.0, vy = 0.0, radius = 0.0;
};

// What the robot sees at one step (the observe message).
struct Step {
    std::int64_t step = 0;
    double time_s = 0.0;
    double x = 0.0, y = 0.0, theta = 0.0;  // pose (m, rad)
    double vx = 0.0, vy = 0.0;             // world-frame velocity in the last step (m/s)
    double v = 0.0, omega = 0.0;           // speed and turn rate (m/s, rad/s)
    std::array<double, 2> goal{};          // the goal or the route's next waypoint (m)
    std::vector<Pedestrian> pedestrians;
};

// The command of one step: (v, omega) for a unicycle, world-frame (vx, vy) for a
// holonomic robot. Finite and within the episode's limits, or srfm ends the episode.
using Command = std::array<double, 2>;

class Planner {
public:
    virtual ~Planner() = default;
    // Only pedestrians closer than this (m) to the robot are observed; nullopt: all.
    virtual std::optional<double> detection_range_m() const { return std::nullopt; }
    // A new episode begins; forget the last one.
    virtual void reset(const Episode& episode) { (void)episode; }
    // The command for this step.
    virtual Command act(const Step& step, const Episode& episode) = 0;
};

using PlannerFactory = std::function<std::unique_ptr<Planner>()>;

// Answer one connected socket until srfm says bye or closes it; 0 on a normal end.
int serve_connection(int fd, Planner& planner);

// Connect to $SRFM_PLANNER_ADDRESS, or with --listen ADDRESS serve every connection;
// the exit status for main().
int run(const PlannerFactory& factory, int argc, char** argv);

}  // namespace srfm
