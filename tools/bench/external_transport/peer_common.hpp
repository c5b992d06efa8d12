// Shared by the transport benchmark's peers: connect to the address the benchmark
// listens on (unix:PATH or tcp:HOST:PORT) and read or write exactly n bytes.
#pragma once
#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

inline int connect_to(const std::string& address) {
    if (address.rfind("unix:", 0) == 0) {
        int fd = socket(AF_UNIX, SOCK_STREAM, 0);
        sockaddr_un sa{};
        sa.sun_family = AF_UNIX;
        std::strncpy(sa.sun_path, address.c_str() + 5, sizeof(sa.sun_path) - 1);
        if (connect(fd, reinterpret_cast<sockaddr*>(&sa), sizeof(sa)) != 0) std::exit(2);
        return fd;
    }
    std::string rest = address.substr(4);
    auto colon = rest.rfind(':');
    int fd = socket(AF_INET, SOCK_STREAM, 0);
    int one = 1;
    setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
    sockaddr_in sa{};
    sa.sin_family = AF_INET;
    sa.sin_port = htons(static_cast<uint16_t>(std::stoi(rest.substr(colon + 1))));
    inet_pton(AF_INET, rest.substr(0, colon).c_str(), &sa.sin_addr);
    if (connect(fd, reinterpret_cast<sockaddr*>(&sa), sizeof(sa)) != 0) std::exit(2);
    return fd;
}

inline bool read_exact(int fd, char* out, size_t n) {
    while (n > 0) {
        ssize_t got = read(fd, out, n);
        if (got <= 0) return false;
        out += got;
        n -= static_cast<size_t>(got);
    }
    return true;
}

inline bool write_exact(int fd, const char* data, size_t n) {
    while (n > 0) {
        ssize_t put = write(fd, data, n);
        if (put <= 0) return false;
        data += put;
        n -= static_cast<size_t>(put);
    }
    return true;
}

// The work every peer does with a decoded observation: a straight-to-goal command.
inline void straight(double x, double y, double theta, double gx, double gy, double* v,
                     double* w) {
    double error = std::remainder(std::atan2(gy - y, gx - x) - theta, 2.0 * M_PI);
    *v = 1.0 * std::fmax(std::cos(error), 0.0);
    *w = std::fmax(-1.0, std::fmin(1.0, 2.0 * error));
}
