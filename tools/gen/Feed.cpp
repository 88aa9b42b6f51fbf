// orbis-feed: plays a live position feed, a vehicle flying circles, as NMEA 0183 (GGA, RMC,
// VTG) in UDP datagrams, one epoch per datagram, on the wall clock: what a GPS receiver on a
// network sends. For the live model layers (`"live": {"url": "udp://127.0.0.1:PORT"}`) of the
// soak scene and for trying the live feed without a receiver.
//
//   orbis-feed --udp 127.0.0.1:47100 [--centre 9.03,46.02] [--radius 800] [--height 900]
//              [--speed 40] [--rate 5] [--seconds S]
//
// Sends to loopback or any address given; runs until --seconds pass or it is stopped.

#include "formats/livefeed/NmeaWriter.h"
#include "globe/Ellipsoid.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>

namespace {

[[noreturn]] void usage(const char* problem) {
    if (problem) std::fprintf(stderr, "orbis-feed: %s\n", problem);
    std::fprintf(stderr,
                 "usage: orbis-feed --udp HOST:PORT [--centre LON,LAT] [--radius M] [--height M] [--speed M/S] [--rate HZ]"
                 " [--seconds S]\n");
    std::exit(2);
}

double number(const char* option, const char* text, double lo, double hi) {
    char* end = nullptr;
    const double v = std::strtod(text, &end);
    if (end == text || *end || !(v >= lo && v <= hi)) {
        std::fprintf(stderr, "orbis-feed: %s %s: expected a number in %g .. %g\n", option, text, lo, hi);
        std::exit(2);
    }
    return v;
}

}  // namespace

int main(int argc, char** argv) {
    std::string udp;
    double lon = 9.03, lat = 46.02, radius = 800.0, height = 900.0, speed = 40.0, rate = 5.0, seconds = 1e9;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (i + 1 >= argc) usage(("missing the value of " + a).c_str());
        const char* v = argv[++i];
        if (a == "--udp") udp = v;
        else if (a == "--centre") {
            if (std::sscanf(v, "%lf,%lf", &lon, &lat) != 2 || std::abs(lon) > 180 || std::abs(lat) > 89)
                usage("--centre expects LON,LAT in degrees");
        } else if (a == "--radius") radius = number("--radius", v, 1.0, 1e6);
        else if (a == "--height") height = number("--height", v, -500.0, 1e5);
        else if (a == "--speed") speed = number("--speed", v, 0.1, 1000.0);
        else if (a == "--rate") rate = number("--rate", v, 0.1, 100.0);
        else if (a == "--seconds") seconds = number("--seconds", v, 0.0, 1e9);
        else usage(("unknown option " + a).c_str());
    }
    const size_t colon = udp.rfind(':');
    if (colon == std::string::npos) usage("--udp expects HOST:PORT (e.g. 127.0.0.1:47100)");
    sockaddr_in to{};
    to.sin_family = AF_INET;
    const long port = std::strtol(udp.c_str() + colon + 1, nullptr, 10);
    if (port < 1 || port > 65535 || ::inet_pton(AF_INET, udp.substr(0, colon).c_str(), &to.sin_addr) != 1)
        usage("--udp expects an IPv4 address and a port 1..65535");
    to.sin_port = htons(uint16_t(port));
    const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd < 0) {
        std::perror("orbis-feed: socket");
        return 1;
    }

    // The circle lies in the plane tangent to the ellipsoid at the centre, raised to --height.
    const auto& earth = orbis::globe::Ellipsoid::wgs84();
    const glm::dvec3 centre = earth.toEcef(lon, lat, height);
    const glm::dmat3 enu = earth.enuFrame(lon, lat);
    const orbis::livefeed::NmeaWriter writer;
    const auto start = std::chrono::steady_clock::now();
    const auto period = std::chrono::duration<double>(1.0 / rate);
    for (long k = 0;; ++k) {
        const auto due = start + std::chrono::duration_cast<std::chrono::steady_clock::duration>(period * double(k));
        std::this_thread::sleep_until(due);
        const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        if (t > seconds) break;
        const double angle = speed * t / radius;   // counter-clockwise seen from above
        orbis::livefeed::Fix fix;
        fix.time = std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch()).count();
        const orbis::globe::Geodetic g = earth.toGeodetic(centre + enu * glm::dvec3(radius * std::cos(angle), radius * std::sin(angle), 0.0));
        fix.lonDeg = g.lonDeg;
        fix.latDeg = g.latDeg;
        fix.heightEllipsoid = g.height;
        fix.speedMps = speed;
        // The velocity (-sin, cos) in (east, north): course = atan2(east, north).
        fix.courseDeg = std::fmod(std::atan2(-std::sin(angle), std::cos(angle)) * 180.0 / M_PI + 360.0, 360.0);
        fix.quality = 1;
        fix.satellites = 10;
        fix.hdop = 0.9;
        const std::string datagram = writer.epoch(fix);
        if (::sendto(fd, datagram.data(), datagram.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to) < 0 &&
            errno != ECONNREFUSED)
            std::perror("orbis-feed: sendto");
    }
    ::close(fd);
    return 0;
}
