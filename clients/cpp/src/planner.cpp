// The C++ client of srfm's external planner protocol: framing, messages, the loop.
// Every message is a MessagePack map after its length as a 4-byte big-endian integer.
#include "srfm/planner.hpp"

#include <arpa/inet.h>
#include <msgpack.hpp>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace srfm {
namespace {

constexpr std::uint32_t kMaxMessageBytes = 64u << 20;

// A message srfm sent that this client cannot use.
struct ProtocolError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

bool read_exact(int fd, char* out, std::size_t n) {
    while (n > 0) {
        ssize_t got = ::read(fd, out, n);
        if (got < 0 && errno == EINTR) continue;
        if (got <= 0) return false;
        out += got;
        n -= static_cast<std::size_t>(got);
    }
    return true;
}

bool write_exact(int fd, const char* data, std::size_t n) {
    while (n > 0) {
        ssize_t put = ::send(fd, data, n, MSG_NOSIGNAL);
        if (put < 0 && errno == EINTR) continue;
        if (put <= 0) return false;
        data += put;
        n -= static_cast<std::size_t>(put);
    }
    return true;
}

// One framed message in a reusable buffer: the 4 length bytes, then the body.
class Writer {
public:
    Writer() : packer_(buffer_) {}
    msgpack::packer<msgpack::sbuffer>& start() {
        buffer_.clear();
        const char zeros[4] = {0, 0, 0, 0};
        buffer_.write(zeros, 4);
        return packer_;
    }
    bool send(int fd) {
        std::uint32_t n = htonl(static_cast<std::uint32_t>(buffer_.size() - 4));
        std::memcpy(buffer_.data(), &n, 4);
        return write_exact(fd, buffer_.data(), buffer_.size());
    }

private:
    msgpack::sbuffer buffer_;
    msgpack::packer<msgpack::sbuffer> packer_;
};

void pack_key(msgpack::packer<msgpack::sbuffer>& pk, const char* key) {
    std::size_t n = std::strlen(key);
    pk.pack_str(static_cast<std::uint32_t>(n));
    pk.pack_str_body(key, static_cast<std::uint32_t>(n));
}

bool send_error(int fd, Writer& out, const std::string& message) {
    auto& pk = out.start();
    pk.pack_map(2);
    pack_key(pk, "type");
    pk.pack(std::string("error"));
    pack_key(pk, "message");
    pk.pack(message);
    return out.send(fd);
}

// The fields of a message map by name (views into the unpacked object).
using Fields = std::unordered_map<std::string, const msgpack::object*>;

Fields fields_of(const msgpack::object& obj) {
    if (obj.type != msgpack::type::MAP) throw ProtocolError("a message that is not a map");
    Fields fields;
    for (std::uint32_t i = 0; i < obj.via.map.size; ++i) {
        const auto& kv = obj.via.map.ptr[i];
        if (kv.key.type != msgpack::type::STR) throw ProtocolError("a key that is not a string");
        fields.emplace(kv.key.as<std::string>(), &kv.val);
    }
    return fields;
}

const msgpack::object& field(const Fields& fields, const char* name) {
    auto it = fields.find(name);
    if (it == fields.end()) throw ProtocolError(std::string("a message without '") + name + "'");
    return *it->second;
}

double number(const Fields& fields, const char* name) { return field(fields, name).as<double>(); }

std::int64_t integer(const Fields& fields, const char* name) {
    return field(fields, name).as<std::int64_t>();
}

std::string text(const Fields& fields, const char* name) {
    return field(fields, name).as<std::string>();
}

const msgpack::object_array& array(const Fields& fields, const char* name, std::size_t multiple) {
    const auto& value = field(fields, name);
    if (value.type != msgpack::type::ARRAY) {
        throw ProtocolError(std::string("'") + name + "' is not a list");
    }
    if (value.via.array.size % multiple != 0) {
        throw ProtocolError(std::string("'") + name + "' has a length that is not a multiple of " +
                            std::to_string(multiple));
    }
    return value.via.array;
}

template <std::size_t N>
std::array<double, N> fixed(const Fields& fields, const char* name) {
    const auto& a = array(fields, name, N);
    if (a.size != N) throw ProtocolError(std::string("'") + name + "' has the wrong length");
    std::array<double, N> out{};
    for (std::size_t i = 0; i < N; ++i) out[i] = a.ptr[i].as<double>();
    return out;
}

Episode read_episode(const Fields& f) {
    Episode e;
    e.scenario = text(f, "scenario");
    e.seed = integer(f, "seed");
    e.dt_s = number(f, "dt_s");
    e.horizon_steps = integer(f, "horizon_steps");
    e.kinematics = text(f, "kinematics");
    e.radius_m = number(f, "radius_m");
    e.max_speed_mps = number(f, "max_speed_mps");
    e.max_angular_speed_radps = number(f, "max_angular_speed_radps");
    e.max_accel_mps2 = number(f, "max_accel_mps2");
    e.max_angular_accel_radps2 = number(f, "max_angular_accel_radps2");
    e.goal_radius_m = number(f, "goal_radius_m");
    e.goal = fixed<2>(f, "goal");
    e.world = fixed<4>(f, "world");
    const auto& walls = array(f, "walls", 4);
    for (std::uint32_t i = 0; i < walls.size; i += 4) {
        e.walls.push_back({walls.ptr[i].as<double>(), walls.ptr[i + 1].as<double>(),
                           walls.ptr[i + 2].as<double>(), walls.ptr[i + 3].as<double>()});
    }
    const auto& pillars = array(f, "pillars", 3);
    for (std::uint32_t i = 0; i < pillars.size; i += 3) {
        e.pillars.push_back({pillars.ptr[i].as<double>(), pillars.ptr[i + 1].as<double>(),
                             pillars.ptr[i + 2].as<double>()});
    }
    return e;
}

void read_step(const Fields& f, Step& s) {
    s.step = integer(f, "step");
    s.time_s = number(f, "time_s");
    auto robot = fixed<7>(f, "robot");
    s.x = robot[0];
    s.y = robot[1];
    s.theta = robot[2];
    s.vx = robot[3];
    s.vy = robot[4];
    s.v = robot[5];
    s.omega = robot[6];
    s.goal = fixed<2>(f, "goal");
    const auto& ids = array(f, "ped_ids", 1);
    const auto& pos = array(f, "ped_pos", 2);
    const auto& vel = array(f, "ped_vel", 2);
    const auto& radius = array(f, "ped_radius", 1);
    std::uint32_t k = ids.size;
    if (pos.size != 2 * k || vel.size != 2 * k || radius.size != k) {
        throw ProtocolError("pedestrian lists of different lengths");
    }
    s.pedestrians.resize(k);
    for (std::uint32_t i = 0; i < k; ++i) {
        Pedestrian& p = s.pedestrians[i];
        p.id = ids.ptr[i].as<std::int64_t>();
        p.x = pos.ptr[2 * i].as<double>();
        p.y = pos.ptr[2 * i + 1].as<double>();
        p.vx = vel.ptr[2 * i].as<double>();
        p.vy = vel.ptr[2 * i + 1].as<double>();
        p.radius = radius.ptr[i].as<double>();
    }
}

// The next message into `body`; false at end of file.
bool receive(int fd, std::vector<char>& body, msgpack::object_handle& handle) {
    unsigned char head[4];
    if (!read_exact(fd, reinterpret_cast<char*>(head), 4)) return false;
    std::uint32_t n = (std::uint32_t(head[0]) << 24) | (std::uint32_t(head[1]) << 16) |
                      (std::uint32_t(head[2]) << 8) | std::uint32_t(head[3]);
    if (n > kMaxMessageBytes) throw ProtocolError("an impossible message length");
    body.resize(n);
    if (!read_exact(fd, body.data(), n)) return false;
    handle = msgpack::unpack(body.data(), n);
    return true;
}

int connect_to(const std::string& address, bool listen_there) {
    if (address.rfind("unix:", 0) == 0) {
        std::string path = address.substr(5);
        sockaddr_un sa{};
        sa.sun_family = AF_UNIX;
        if (path.empty() || path.size() >= sizeof(sa.sun_path)) return -1;
        std::memcpy(sa.sun_path, path.c_str(), path.size() + 1);
        int fd = ::socket(AF_UNIX, SOCK_STREAM, 0);
        if (fd < 0) return -1;
        auto* p = reinterpret_cast<sockaddr*>(&sa);
        int rc = listen_there ? (::unlink(path.c_str()), ::bind(fd, p, sizeof(sa)))
                              : ::connect(fd, p, sizeof(sa));
        if (rc != 0 || (listen_there && ::listen(fd, 64) != 0)) {
            ::close(fd);
            return -1;
        }
        return fd;
    }
    if (address.rfind("tcp:", 0) == 0) {
        std::string rest = address.substr(4);
        auto colon = rest.rfind(':');
        if (colon == std::string::npos) return -1;
        addrinfo hints{};
        hints.ai_family = AF_INET;
        hints.ai_socktype = SOCK_STREAM;
        addrinfo* found = nullptr;
        if (::getaddrinfo(rest.substr(0, colon).c_str(), rest.substr(colon + 1).c_str(), &hints,
                          &found) != 0) {
            return -1;
        }
        int fd = ::socket(AF_INET, SOCK_STREAM, 0);
        int one = 1;
        ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
        ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
        int rc = listen_there ? ::bind(fd, found->ai_addr, found->ai_addrlen)
                              : ::connect(fd, found->ai_addr, found->ai_addrlen);
        ::freeaddrinfo(found);
        if (rc != 0 || (listen_there && ::listen(fd, 64) != 0)) {
            ::close(fd);
            return -1;
        }
        return fd;
    }
    return -1;
}

}  // namespace

int serve_connection(int fd, Planner& planner) {
    int one = 1;
    ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));  // fails on Unix sockets
    std::vector<char> body;
    msgpack::object_handle handle;
    Writer out;
    Episode episode;
    bool have_episode = false;
    Step step;
    try {
        if (!receive(fd, body, handle)) return 0;
        Fields hello = fields_of(handle.get());
        std::int64_t version = integer(hello, "protocol");
        if (text(hello, "type") != "hello" || version != kProtocolVersion) {
            send_error(fd, out,
                       "this planner speaks protocol version " + std::to_string(kProtocolVersion) +
                           ", srfm sent version " + std::to_string(version));
            return 1;
        }
        auto& pk = out.start();
        pk.pack_map(3);
        pack_key(pk, "type");
        pk.pack(std::string("hello"));
        pack_key(pk, "protocol");
        pk.pack(kProtocolVersion);
        pack_key(pk, "detection_range_m");
        auto range = planner.detection_range_m();
        if (range) {
            pk.pack_double(*range);
        } else {
            pk.pack_nil();
        }
        if (!out.send(fd)) return 0;
        while (receive(fd, body, handle)) {
            Fields message = fields_of(handle.get());
            std::string type = text(message, "type");
            if (type == "observe") {
                if (!have_episode) throw ProtocolError("observe before reset");
                read_step(message, step);
                Command command = planner.act(step, episode);
                auto& p = out.start();
                p.pack_map(2);
                pack_key(p, "type");
                p.pack(std::string("command"));
                pack_key(p, "command");
                p.pack_array(2);
                p.pack_double(command[0]);
                p.pack_double(command[1]);
                if (!out.send(fd)) return 0;
            } else if (type == "reset") {
                episode = read_episode(message);
                have_episode = true;
                planner.reset(episode);
                auto& p = out.start();
                p.pack_map(1);
                pack_key(p, "type");
                p.pack(std::string("ready"));
                if (!out.send(fd)) return 0;
            } else if (type == "bye") {
                return 0;
            } else {
                throw ProtocolError("unknown message type '" + type + "'");
            }
        }
        return 0;
    } catch (const std::exception& exc) {  // ProtocolError, msgpack's type errors
        send_error(fd, out, std::string("cannot use srfm's message: ") + exc.what());
        return 1;
    }
}

int run(const PlannerFactory& factory, int argc, char** argv) {
    std::string listen_address;
    for (int i = 1; i < argc; ++i) {
        if (std::string(argv[i]) == "--listen" && i + 1 < argc) listen_address = argv[++i];
    }
    if (listen_address.empty()) {
        const char* address = std::getenv("SRFM_PLANNER_ADDRESS");
        if (address == nullptr) {
            std::fprintf(stderr,
                         "%s: SRFM_PLANNER_ADDRESS is not set: srfm sets it when it starts this "
                         "program (--external NAME=PROGRAM); or give --listen unix:PATH or "
                         "--listen tcp:HOST:PORT\n",
                         argv[0]);
            return 2;
        }
        int fd = connect_to(address, false);
        if (fd < 0) {
            std::fprintf(stderr, "%s: cannot connect to %s: %s\n", argv[0], address,
                         std::strerror(errno));
            return 2;
        }
        auto planner = factory();
        int status = serve_connection(fd, *planner);
        ::close(fd);
        return status;
    }
    int server = connect_to(listen_address, true);
    if (server < 0) {
        std::fprintf(stderr, "%s: cannot listen on %s: %s\n", argv[0], listen_address.c_str(),
                     std::strerror(errno));
        return 2;
    }
    ::signal(SIGCHLD, SIG_IGN);  // children are reaped by the kernel
    std::fprintf(stderr, "srfm planner listening on %s\n", listen_address.c_str());
    for (;;) {
        int fd = ::accept(server, nullptr, nullptr);
        if (fd < 0) {
            if (errno == EINTR) continue;
            return 1;
        }
        pid_t child = ::fork();
        if (child == 0) {
            ::close(server);
            auto planner = factory();
            int status = serve_connection(fd, *planner);
            ::close(fd);
            std::_Exit(status);
        }
        ::close(fd);
    }
}

}  // namespace srfm
