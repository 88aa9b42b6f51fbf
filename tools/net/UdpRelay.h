#pragma once
// A lossy UDP relay on loopback (tests and benchmarks of live video): every datagram that
// arrives on 127.0.0.1:port() goes on to 127.0.0.1:`toPort`, except a share `drop` of them
// (dropped) and a share `corrupt` (one payload byte flipped on the way: not an MPEG-TS sync
// byte, so the damage is in the data, as on a noisy link). Decisions come from a seeded
// generator: a run is repeatable. One thread; stops (joined) on destruction.

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>

namespace orbis::net {

struct RelayCounts {
    uint64_t received = 0, dropped = 0, corrupted = 0, sent = 0;
};

class UdpRelay {
public:
    /// Binds 127.0.0.1:`listenPort` (0: a free port); `error()` says why not (then port() is 0).
    UdpRelay(int toPort, double drop, double corrupt, uint32_t seed = 1, int listenPort = 0);
    ~UdpRelay();
    UdpRelay(const UdpRelay&) = delete;
    UdpRelay& operator=(const UdpRelay&) = delete;

    int port() const { return port_; }
    const std::string& error() const { return error_; }
    RelayCounts counts() const;
    /// Changes the shares while it runs.
    void setLoss(double drop, double corrupt);

private:
    void run();

    int in_ = -1, out_ = -1, port_ = 0, toPort_;
    std::atomic<double> drop_, corrupt_;
    uint32_t seed_;
    std::atomic<bool> stop_{false};
    std::atomic<uint64_t> received_{0}, dropped_{0}, corrupted_{0}, sent_{0};
    std::string error_;
    std::thread thread_;
};

/// A UDP port on 127.0.0.1 free now (bound and released), for a receiver to bind; 0 on failure.
int freeUdpPort();

}  // namespace orbis::net
