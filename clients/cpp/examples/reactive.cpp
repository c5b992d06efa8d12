// A simple reactive planner: head for the goal, turned away from the pedestrians within
// 2 m by a repulsion that grows as they come closer, and slower the closer the nearest
// one is. A unicycle planner (a holonomic robot gets the same direction at that speed).
#include <algorithm>
#include <cmath>

#include "srfm/planner.hpp"

class Reactive : public srfm::Planner {
public:
    std::optional<double> detection_range_m() const override { return kRange; }

    srfm::Command act(const srfm::Step& s, const srfm::Episode& e) override {
        double gx = s.goal[0] - s.x;
        double gy = s.goal[1] - s.y;
        double dist = std::hypot(gx, gy);
        if (dist < 1e-12) return {0.0, 0.0};
        double dx = gx / dist;  // unit vector to the goal, plus the repulsions
        double dy = gy / dist;
        double nearest = kRange;
        for (const auto& p : s.pedestrians) {
            double rx = s.x - p.x;
            double ry = s.y - p.y;
            double d = std::hypot(rx, ry);
            double gap = d - p.radius - e.radius_m;
            nearest = std::min(nearest, gap);
            if (d < 1e-9) continue;
            double push = std::exp(-std::max(gap, 0.0) / 0.5);  // 1 at contact
            dx += push * rx / d;
            dy += push * ry / d;
        }
        double slow = std::clamp(nearest / 1.0, 0.2, 1.0);  // full speed from 1 m of gap
        double vmax = e.max_speed_mps * slow;
        if (e.holonomic()) {
            double n = std::hypot(dx, dy);
            if (n < 1e-12) return {0.0, 0.0};
            return {vmax * dx / n, vmax * dy / n};
        }
        double error = std::remainder(std::atan2(dy, dx) - s.theta, 2.0 * M_PI);
        double wmax = e.max_angular_speed_radps;
        double omega = std::clamp(2.0 * error, -wmax, wmax);
        return {vmax * std::max(std::cos(error), 0.0), omega};
    }

private:
    static constexpr double kRange = 2.0;
};

int main(int argc, char** argv) {
    return srfm::run([] { return std::make_unique<Reactive>(); }, argc, argv);
}
