#pragma once
// The few POSIX socket pieces the live feed needs: an owning fd, a wake-up fd that interrupts
// poll() (so that stop() never waits for a timeout), name resolution, a non-blocking TCP connect
// that can be interrupted, and a UDP bind. Linux (eventfd, MSG_NOSIGNAL semantics).
//
// Errors name the feed and the address: "live feed 'tcp://h:1': connect to 127.0.0.1:1:
// Connection refused".

#include "base/Result.h"
#include "formats/livefeed/FeedAddress.h"

#include <sys/socket.h>

#include <chrono>
#include <string>
#include <vector>

namespace orbis::livefeed {

/// Owns one file descriptor; move-only; closes it on destruction.
class Fd {
public:
    Fd() = default;
    explicit Fd(int fd) : fd_(fd) {}
    Fd(Fd&& o) noexcept : fd_(o.release()) {}
    Fd& operator=(Fd&& o) noexcept;
    Fd(const Fd&) = delete;
    Fd& operator=(const Fd&) = delete;
    ~Fd() { reset(); }

    int get() const { return fd_; }
    bool valid() const { return fd_ >= 0; }
    int release() {
        const int fd = fd_;
        fd_ = -1;
        return fd;
    }
    void reset();

private:
    int fd_ = -1;
};

/// An eventfd that another thread signals to wake a poll() on it. Thread-safe.
class WakeFd {
public:
    WakeFd();
    bool valid() const { return fd_.valid(); }
    int fd() const { return fd_.get(); }
    /// Makes fd() readable (and keeps it so: a stop is not consumed). Any thread.
    void signal();

private:
    Fd fd_;
};

struct ResolvedAddress {
    sockaddr_storage storage{};
    socklen_t length = 0;
    int family = 0;
    std::string text;   ///< numeric "host:port" for messages
};

/// getaddrinfo for the feed's host and port (AF_UNSPEC: IPv4 and IPv6 as the resolver orders
/// them). Blocking: a slow DNS server delays the caller (numeric hosts never ask one).
Result<std::vector<ResolvedAddress>> resolve(const FeedAddress& address);

/// What waiting on a socket and the wake fd gave.
enum class WaitResult { Ready, Woken, TimedOut, Failed };

/// poll() on `fd` for `events` and on `wakeFd` for readability, at most `timeout` (-1 ms: no limit).
WaitResult waitFor(int fd, short events, int wakeFd, std::chrono::milliseconds timeout);

/// Non-blocking TCP connect to `to`, waiting at most `timeout`; returns early with an error
/// "stopped" when `wakeFd` is signalled. The socket is left non-blocking.
Result<Fd> connectTcp(const FeedAddress& feed, const ResolvedAddress& to, std::chrono::milliseconds timeout, int wakeFd);

/// A non-blocking UDP socket bound to `at` (SO_REUSEADDR, so a restarted viewer binds again at once).
Result<Fd> bindUdp(const FeedAddress& feed, const ResolvedAddress& at);

/// The local port a socket is bound to, 0 on error.
std::uint16_t localPort(int fd);

}  // namespace orbis::livefeed
