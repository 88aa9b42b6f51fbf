#pragma once
// Test servers for the live feed: a TCP server on 127.0.0.1 that one client connects to and
// that the test drives step by step (accept, send, close, listen again on the same port), and a
// UDP sender. No threads of their own: the test thread calls them, and every wait has a
// deadline. Plus the synthetic track that the servers play.

#include "formats/livefeed/Fix.h"

#include <chrono>
#include <cstdint>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

namespace orbis::livefeed::test {

class TcpFeedServer {
public:
    /// Binds 127.0.0.1:`port` (0: an ephemeral port) with SO_REUSEADDR, so that a restarted
    /// server gets the same port back. With `listenNow` false the socket is bound but not
    /// listening: connects are refused until listen(). Check ok().
    explicit TcpFeedServer(std::uint16_t port = 0, bool listenNow = true);
    ~TcpFeedServer();
    TcpFeedServer(const TcpFeedServer&) = delete;
    TcpFeedServer& operator=(const TcpFeedServer&) = delete;

    bool ok() const { return listenFd_ >= 0 && error_.empty(); }
    const std::string& error() const { return error_; }
    std::uint16_t port() const { return port_; }
    std::string url() const { return "tcp://127.0.0.1:" + std::to_string(port_); }

    bool listen();
    /// Accepts one client, waiting at most `timeout`. Replaces a previous client.
    bool acceptClient(std::chrono::milliseconds timeout = std::chrono::seconds(5));
    bool hasClient() const { return clientFd_ >= 0; }
    /// Sends all of `bytes` to the client (MSG_NOSIGNAL); false if there is none or it left.
    bool send(std::string_view bytes);
    /// Closes the client connection and the listening socket: the server is gone.
    void close();

private:
    int listenFd_ = -1;
    int clientFd_ = -1;
    std::uint16_t port_ = 0;
    std::string error_;
};

/// Sends datagrams to 127.0.0.1:port from an ephemeral port.
class UdpSender {
public:
    explicit UdpSender(std::uint16_t port);
    ~UdpSender();
    UdpSender(const UdpSender&) = delete;
    UdpSender& operator=(const UdpSender&) = delete;
    bool send(std::string_view datagram);

private:
    int fd_ = -1;
    std::uint16_t port_ = 0;
};

/// `count` fixes every `step` from `start` on a small loop near Bern: position, height above
/// the ellipsoid and MSL, speed, course, quality 1, 9 satellites, HDOP 0.8. Times are whole
/// milliseconds, so that NMEA carries them exactly.
std::vector<Fix> syntheticTrack(int count, TimeNs start, TimeNs step);

/// Polls `done` every 2 ms until it is true or `timeout` passes; returns its last value.
template <typename F>
bool waitUntil(F done, std::chrono::milliseconds timeout = std::chrono::seconds(5)) {
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (!done()) {
        if (std::chrono::steady_clock::now() > deadline) return done();
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return true;
}

}  // namespace orbis::livefeed::test
