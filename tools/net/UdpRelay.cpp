#include "tools/net/UdpRelay.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <random>
#include <vector>

namespace orbis::net {
namespace {

sockaddr_in loopback(int port) {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    a.sin_port = htons(uint16_t(port));
    return a;
}

/// A UDP socket bound to 127.0.0.1:port (0: any); its port in `bound`.
int bindUdp(int port, int& bound, std::string& error) {
    const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd < 0) {
        error = std::string("socket: ") + std::strerror(errno);
        return -1;
    }
    sockaddr_in a = loopback(port);
    socklen_t len = sizeof a;
    if (::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 || ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) != 0) {
        error = "bind 127.0.0.1:" + std::to_string(port) + ": " + std::strerror(errno);
        ::close(fd);
        return -1;
    }
    bound = ntohs(a.sin_port);
    return fd;
}

}  // namespace

int freeUdpPort() {
    int port = 0;
    std::string error;
    const int fd = bindUdp(0, port, error);
    if (fd < 0) return 0;
    ::close(fd);
    return port;
}

UdpRelay::UdpRelay(int toPort, double drop, double corrupt, uint32_t seed, int listenPort)
    : toPort_(toPort), drop_(drop), corrupt_(corrupt), seed_(seed) {
    in_ = bindUdp(listenPort, port_, error_);
    if (in_ < 0) {
        port_ = 0;
        return;
    }
    const int big = 4 << 20;
    ::setsockopt(in_, SOL_SOCKET, SO_RCVBUF, &big, sizeof big);
    out_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (out_ < 0) {
        error_ = std::string("socket: ") + std::strerror(errno);
        port_ = 0;
        return;
    }
    thread_ = std::thread([this] { run(); });
}

UdpRelay::~UdpRelay() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    if (in_ >= 0) ::close(in_);
    if (out_ >= 0) ::close(out_);
}

RelayCounts UdpRelay::counts() const { return {received_.load(), dropped_.load(), corrupted_.load(), sent_.load()}; }

void UdpRelay::setLoss(double drop, double corrupt) {
    drop_ = drop;
    corrupt_ = corrupt;
}

void UdpRelay::run() {
    std::mt19937 random(seed_);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<uint8_t> buffer(65536);
    const sockaddr_in to = loopback(toPort_);
    while (!stop_) {
        pollfd p{in_, POLLIN, 0};
        if (::poll(&p, 1, 50) <= 0) continue;
        const ssize_t n = ::recv(in_, buffer.data(), buffer.size(), 0);
        if (n <= 0) continue;
        ++received_;
        if (unit(random) < drop_.load()) {
            ++dropped_;
            continue;
        }
        if (unit(random) < corrupt_.load()) {
            // A byte that is not a TS packet's sync byte (offsets 0, 188, ...).
            size_t at = size_t(unit(random) * double(n));
            if (at % 188 == 0) at = (at + 1) % size_t(n);
            buffer[at] ^= uint8_t(1u + (random() % 255u));
            ++corrupted_;
        }
        if (::sendto(out_, buffer.data(), size_t(n), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to) == n) ++sent_;
    }
}

}  // namespace orbis::net
