#include "formats/livefeed/Socket.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace orbis::livefeed {
namespace {

std::string errnoText(int err) { return std::strerror(err); }

std::string numericText(const sockaddr* sa, socklen_t len) {
    char host[NI_MAXHOST];
    char port[NI_MAXSERV];
    if (::getnameinfo(sa, len, host, sizeof host, port, sizeof port, NI_NUMERICHOST | NI_NUMERICSERV) != 0) return "?";
    std::string text = sa->sa_family == AF_INET6 ? std::string("[").append(host).append("]") : std::string(host);
    return text.append(":").append(port);
}

}  // namespace

Fd& Fd::operator=(Fd&& o) noexcept {
    if (this != &o) {
        reset();
        fd_ = o.release();
    }
    return *this;
}

void Fd::reset() {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
}

WakeFd::WakeFd() : fd_(::eventfd(0, EFD_CLOEXEC | EFD_NONBLOCK)) {}

void WakeFd::signal() {
    const std::uint64_t one = 1;
    // Cannot block (EFD_NONBLOCK); fails only when the counter is saturated, i.e. already readable.
    [[maybe_unused]] const ssize_t n = ::write(fd_.get(), &one, sizeof one);
}

Result<std::vector<ResolvedAddress>> resolve(const FeedAddress& address) {
    addrinfo hints{};
    hints.ai_family = AF_UNSPEC;
    hints.ai_socktype = address.transport == Transport::Tcp ? SOCK_STREAM : SOCK_DGRAM;
    hints.ai_flags = AI_NUMERICSERV | (address.transport == Transport::Udp ? AI_PASSIVE : 0);
    addrinfo* list = nullptr;
    const std::string port = std::to_string(address.port);
    const int rc = ::getaddrinfo(address.host.c_str(), port.c_str(), &hints, &list);
    if (rc != 0)
        return makeError("live feed '" + address.text + "': cannot resolve '" + address.host + "': " +
                         (rc == EAI_SYSTEM ? errnoText(errno) : std::string(::gai_strerror(rc))));
    std::vector<ResolvedAddress> out;
    for (const addrinfo* ai = list; ai; ai = ai->ai_next) {
        if (ai->ai_addrlen > sizeof(sockaddr_storage)) continue;
        ResolvedAddress r;
        std::memcpy(&r.storage, ai->ai_addr, ai->ai_addrlen);
        r.length = ai->ai_addrlen;
        r.family = ai->ai_family;
        r.text = numericText(ai->ai_addr, ai->ai_addrlen);
        out.push_back(r);
    }
    ::freeaddrinfo(list);
    if (out.empty()) return makeError("live feed '" + address.text + "': '" + address.host + "' has no address");
    return out;
}

WaitResult waitFor(int fd, short events, int wakeFd, std::chrono::milliseconds timeout) {
    pollfd p[2];
    nfds_t count = 0;
    if (fd >= 0) p[count++] = {fd, events, 0};   // fd < 0: wait on the wake fd alone (a backoff)
    const nfds_t wake = count;
    p[count++] = {wakeFd, POLLIN, 0};
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    for (;;) {
        int ms = -1;
        if (timeout.count() >= 0) {
            const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
            ms = int(std::max<std::int64_t>(0, left.count()));
        }
        const int n = ::poll(p, count, ms);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return WaitResult::Failed;
        if (n == 0) return WaitResult::TimedOut;
        if (p[wake].revents & POLLIN) return WaitResult::Woken;
        return WaitResult::Ready;
    }
}

Result<Fd> connectTcp(const FeedAddress& feed, const ResolvedAddress& to, std::chrono::milliseconds timeout, int wakeFd) {
    const std::string what = "live feed '" + feed.text + "': connect to " + to.text;
    Fd fd(::socket(to.family, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
    if (!fd.valid()) return makeError(what + ": socket: " + errnoText(errno));
    // Small position messages: do not let Nagle's algorithm on our side delay anything we send
    // (we send nothing today, but a future handshake would suffer from it).
    const int one = 1;
    ::setsockopt(fd.get(), IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
    if (::connect(fd.get(), reinterpret_cast<const sockaddr*>(&to.storage), to.length) == 0) return fd;
    if (errno != EINPROGRESS) return makeError(what + ": " + errnoText(errno));
    switch (waitFor(fd.get(), POLLOUT, wakeFd, timeout)) {
        case WaitResult::Woken: return makeError(what + ": stopped");
        case WaitResult::TimedOut: return makeError(what + ": no answer within " + std::to_string(timeout.count()) + " ms");
        case WaitResult::Failed: return makeError(what + ": poll: " + errnoText(errno));
        case WaitResult::Ready: break;
    }
    int err = 0;
    socklen_t len = sizeof err;
    if (::getsockopt(fd.get(), SOL_SOCKET, SO_ERROR, &err, &len) != 0) err = errno;
    if (err != 0) return makeError(what + ": " + errnoText(err));
    return fd;
}

Result<Fd> bindUdp(const FeedAddress& feed, const ResolvedAddress& at) {
    const std::string what = "live feed '" + feed.text + "': bind " + at.text;
    Fd fd(::socket(at.family, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
    if (!fd.valid()) return makeError(what + ": socket: " + errnoText(errno));
    const int one = 1;
    ::setsockopt(fd.get(), SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    if (::bind(fd.get(), reinterpret_cast<const sockaddr*>(&at.storage), at.length) != 0) return makeError(what + ": " + errnoText(errno));
    return fd;
}

std::uint16_t localPort(int fd) {
    sockaddr_storage ss{};
    socklen_t len = sizeof ss;
    if (::getsockname(fd, reinterpret_cast<sockaddr*>(&ss), &len) != 0) return 0;
    if (ss.ss_family == AF_INET) return ntohs(reinterpret_cast<const sockaddr_in*>(&ss)->sin_port);
    if (ss.ss_family == AF_INET6) return ntohs(reinterpret_cast<const sockaddr_in6*>(&ss)->sin6_port);
    return 0;
}

}  // namespace orbis::livefeed
