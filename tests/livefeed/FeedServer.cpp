#include "tests/livefeed/FeedServer.h"

#include "tests/support/Loopback.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>

namespace orbis::livefeed::test {

TcpFeedServer::TcpFeedServer(std::uint16_t port, bool listenNow) {
    int bound = 0;
    listenFd_ = orbis::test::bindLoopback(port, bound, error_);
    if (listenFd_ < 0) return;
    port_ = bound;
    if (listenNow) listen();
}

TcpFeedServer::~TcpFeedServer() { close(); }

bool TcpFeedServer::listen() {
    if (listenFd_ < 0) return false;
    if (::listen(listenFd_, 8) != 0) {
        error_ = std::string("listen: ") + std::strerror(errno);
        return false;
    }
    return true;
}

bool TcpFeedServer::acceptClient(std::chrono::milliseconds timeout) {
    if (listenFd_ < 0) return false;
    pollfd p{listenFd_, POLLIN, 0};
    if (::poll(&p, 1, int(timeout.count())) <= 0) return false;
    const int fd = ::accept4(listenFd_, nullptr, nullptr, SOCK_CLOEXEC);
    if (fd < 0) return false;
    if (clientFd_ >= 0) ::close(clientFd_);
    clientFd_ = fd;
    return true;
}

bool TcpFeedServer::send(std::string_view bytes) {
    if (clientFd_ < 0) return false;
    while (!bytes.empty()) {
        const ssize_t n = ::send(clientFd_, bytes.data(), bytes.size(), MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        bytes.remove_prefix(std::size_t(n));
    }
    return true;
}

void TcpFeedServer::close() {
    if (clientFd_ >= 0) ::close(clientFd_);
    if (listenFd_ >= 0) ::close(listenFd_);
    clientFd_ = listenFd_ = -1;
}

UdpSender::UdpSender(std::uint16_t port) : fd_(::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0)), port_(port) {}

UdpSender::~UdpSender() {
    if (fd_ >= 0) ::close(fd_);
}

bool UdpSender::send(std::string_view datagram) {
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    addr.sin_port = htons(port_);
    const ssize_t n = ::sendto(fd_, datagram.data(), datagram.size(), 0, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
    return n == ssize_t(datagram.size());
}

std::vector<Fix> syntheticTrack(int count, TimeNs start, TimeNs step) {
    std::vector<Fix> track;
    track.reserve(std::size_t(count));
    for (int i = 0; i < count; ++i) {
        const double a = 0.05 * i;
        Fix f;
        f.time = start + i * step;
        f.latDeg = 46.95 + 0.01 * std::sin(a);
        f.lonDeg = 7.45 + 0.015 * std::cos(a);
        f.heightEllipsoid = 600.0 + 0.25 * i;
        f.altitudeMsl = *f.heightEllipsoid - 49.576;
        f.speedMps = 12.5 + 0.01 * i;
        f.courseDeg = std::fmod(270.0 + 2.5 * i, 360.0);
        f.quality = 1;
        f.satellites = 9;
        f.hdop = 0.8;
        track.push_back(f);
    }
    return track;
}

}  // namespace orbis::livefeed::test
