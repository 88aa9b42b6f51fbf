// orbis-udp-relay: a lossy UDP relay on loopback (tools/net/UdpRelay.h) for the live video
// benchmarks: datagrams to 127.0.0.1:LISTEN go on to 127.0.0.1:TO, less a share dropped and a
// share with one byte flipped. Prints its counts every 5 s and when stopped (Ctrl+C, SIGTERM).
//   orbis-udp-relay --listen PORT --to PORT [--drop 0.05] [--corrupt 0] [--seed 1]
#include "tools/net/UdpRelay.h"

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

namespace {

std::atomic<bool> stopped{false};

int usage() {
    std::fprintf(stderr, "usage: orbis-udp-relay --listen PORT --to PORT [--drop SHARE] [--corrupt SHARE] [--seed N]\n");
    return 2;
}

void print(const orbis::net::UdpRelay& relay) {
    const orbis::net::RelayCounts c = relay.counts();
    std::printf("orbis-udp-relay: %llu datagrams in, %llu dropped, %llu corrupted, %llu sent\n", (unsigned long long)c.received,
                (unsigned long long)c.dropped, (unsigned long long)c.corrupted, (unsigned long long)c.sent);
    std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
    int listen = 0, to = 0;
    double drop = 0.0, corrupt = 0.0;
    unsigned seed = 1;
    for (int i = 1; i + 1 < argc; i += 2) {
        const std::string a = argv[i];
        if (a == "--listen") listen = std::atoi(argv[i + 1]);
        else if (a == "--to") to = std::atoi(argv[i + 1]);
        else if (a == "--drop") drop = std::atof(argv[i + 1]);
        else if (a == "--corrupt") corrupt = std::atof(argv[i + 1]);
        else if (a == "--seed") seed = unsigned(std::atoi(argv[i + 1]));
        else return usage();
    }
    if (argc % 2 == 0 || listen <= 0 || listen > 65535 || to <= 0 || to > 65535 || !(drop >= 0.0 && drop <= 1.0) ||
        !(corrupt >= 0.0 && corrupt <= 1.0))
        return usage();
    orbis::net::UdpRelay relay(to, drop, corrupt, seed, listen);
    if (relay.port() == 0) {
        std::fprintf(stderr, "orbis-udp-relay: %s\n", relay.error().c_str());
        return 1;
    }
    std::signal(SIGINT, [](int) { stopped = true; });
    std::signal(SIGTERM, [](int) { stopped = true; });
    std::printf("orbis-udp-relay: 127.0.0.1:%d -> 127.0.0.1:%d, dropping %.1f %%, corrupting %.1f %%\n", listen, to, drop * 100.0,
                corrupt * 100.0);
    std::fflush(stdout);
    for (int tick = 1; !stopped; ++tick) {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        if (tick % 50 == 0) print(relay);
    }
    print(relay);
    return 0;
}
