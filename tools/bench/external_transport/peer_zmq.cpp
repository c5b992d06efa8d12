// MessagePack over ZeroMQ: a REP socket bound to the address given (ipc:// or tcp://).
#include <msgpack.hpp>
#include <zmq.hpp>

#include <map>
#include <vector>

#include "peer_common.hpp"

int main(int argc, char** argv) {
    if (argc != 2) return 2;
    zmq::context_t context(1);
    zmq::socket_t socket(context, zmq::socket_type::rep);
    socket.bind(argv[1]);
    for (;;) {
        zmq::message_t request;
        if (!socket.recv(request)) return 0;
        if (request.size() == 0) return 0;  // the benchmark's "stop"
        msgpack::object_handle handle =
            msgpack::unpack(static_cast<const char*>(request.data()), request.size());
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
        socket.send(zmq::buffer(out.data(), out.size()), zmq::send_flags::none);
    }
}
