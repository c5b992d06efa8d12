// JSON lines (nlohmann-json) over a stream socket: one observation per line in, one
// command per line out.
#include <nlohmann/json.hpp>

#include "peer_common.hpp"

int main(int argc, char** argv) {
    if (argc != 2) return 2;
    int fd = connect_to(argv[1]);
    std::string buffer;
    char chunk[65536];
    for (;;) {
        auto end = buffer.find('\n');
        while (end == std::string::npos) {
            ssize_t got = read(fd, chunk, sizeof(chunk));
            if (got <= 0) return 0;
            buffer.append(chunk, static_cast<size_t>(got));
            end = buffer.find('\n');
        }
        nlohmann::json obs = nlohmann::json::parse(buffer.begin(), buffer.begin() + end);
        buffer.erase(0, end + 1);
        const auto& robot = obs["robot"];
        const auto& goal = obs["goal"];
        double sum = 0.0;  // touch every pedestrian value, as a planner would
        for (const auto& p : obs["ped_pos"]) sum += p.get<double>();
        double v, w;
        straight(robot[0].get<double>(), robot[1].get<double>(), robot[2].get<double>(),
                 goal[0].get<double>(), goal[1].get<double>(), &v, &w);
        nlohmann::json reply = {{"type", "command"}, {"command", {v, w + 0.0 * sum}}};
        std::string text = reply.dump();
        text.push_back('\n');
        if (!write_exact(fd, text.data(), text.size())) return 0;
    }
}
