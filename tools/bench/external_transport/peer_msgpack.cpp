// MessagePack (msgpack-cxx) over a stream socket, each message after its length as a
// 4-byte big-endian integer.
#include <msgpack.hpp>

#include <map>
#include <vector>

#include "peer_common.hpp"

int main(int argc, char** argv) {
    if (argc != 2) return 2;
    int fd = connect_to(argv[1]);
    std::vector<char> body;
    for (;;) {
        unsigned char head[4];
        if (!read_exact(fd, reinterpret_cast<char*>(head), 4)) return 0;
        size_t n = (size_t(head[0]) << 24) | (size_t(head[1]) << 16) | (size_t(head[2]) << 8) |
                   size_t(head[3]);
        body.resize(n);
        if (!read_exact(fd, body.data(), n)) return 0;
        msgpack::object_handle handle = msgpack::unpack(body.data(), n);
        auto obs = handle.get().as<std::map<std::string, msgpack::object>>();
        auto robot = obs.at("robot").as<std::vector<double>>();
        auto goal = obs.at("goal").as<std::vector<double>>();
        auto pos = obs.at("ped_pos").as<std::vector<double>>();
        double sum = 0.0;
        for (double p : pos) sum += p;
        double v, w;
        straight(robot[0], robot[1], robot[2], goal[0], goal[1], &v, &w);
        msgpack::sbuffer out;
        msgpack::packer<msgpack::sbuffer> pk(out);
        pk.pack_map(2);
        pk.pack(std::string("type"));
        pk.pack(std::string("command"));
        pk.pack(std::string("command"));
        pk.pack_array(2);
        pk.pack_double(v);
        pk.pack_double(w + 0.0 * sum);
        uint32_t size = static_cast<uint32_t>(out.size());
        unsigned char len[4] = {static_cast<unsigned char>(size >> 24),
                                static_cast<unsigned char>(size >> 16),
                                static_cast<unsigned char>(size >> 8),
                                static_cast<unsigned char>(size)};
        if (!write_exact(fd, reinterpret_cast<char*>(len), 4)) return 0;
        if (!write_exact(fd, out.data(), out.size())) return 0;
    }
}
