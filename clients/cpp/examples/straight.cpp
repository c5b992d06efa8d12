// Straight to the goal at top speed, ignoring people: srfm's built-in `straight`
// planner in C++, the same formula in the same order, so the same episode record.
#include <algorithm>
#include <cmath>

#include "srfm/planner.hpp"

class Straight : public srfm::Planner {
public:
    std::optional<double> detection_range_m() const override { return 0.0; }

    srfm::Command act(const srfm::Step& s, const srfm::Episode& e) override {
        double dx = s.goal[0] - s.x;
        double dy = s.goal[1] - s.y;
        double vmax = e.max_speed_mps;
        if (e.holonomic()) {
            double dist = std::hypot(dx, dy);
            if (dist < 1e-12) return {0.0, 0.0};
            return {vmax * dx / dist, vmax * dy / dist};
        }
        double error = std::remainder(std::atan2(dy, dx) - s.theta, 2.0 * M_PI);
        double wmax = e.max_angular_speed_radps;
        double omega = std::max(-wmax, std::min(wmax, 2.0 * error));
        return {vmax * std::max(std::cos(error), 0.0), omega};
    }
};

int main(int argc, char** argv) {
    return srfm::run([] { return std::make_unique<Straight>(); }, argc, argv);
}
