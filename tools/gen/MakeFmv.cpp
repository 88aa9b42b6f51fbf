// orbis-make-fmv: the FMV fixture: a synthetic DEM and an MPEG-TS with H.264 frames and a
// synchronous MISB ST 0601 KLV stream from a scripted flight over it (layers/fmv/SyntheticFlight.h),
// so that tests and benchmarks know where every corner of every frame must land.
//
//   orbis-make-fmv OUTDIR [--frames 100] [--fps 10] [--size 640x480] [--async] [--no-klv] [--csv]
//                  [--flight-start S]   (seconds into the 240 s lap of frame 0)
//
// Writes OUTDIR/flight-dem.tif (EPSG:4979 heights over lon 9.00..9.06, lat 46.00..46.04, 1/7200
// degree cells: about 11 x 15 m), OUTDIR/flight.ts, and with --csv OUTDIR/flight.csv (the same
// poses as a CSV sidecar). Frames: a checkerboard of 8 x 6 squares (the image's corners are
// coloured: upper left red, upper right green, lower right blue, lower left yellow), the frame
// number in digits and as 12 bits in blocks along the bottom. One KLV packet per frame, at the
// frame's time. Deterministic.
//
//   orbis-make-fmv --stream URL [--frames N] [--fps F] [--size WxH] [--async] [--wall-clock]
//                  [--flight-start S] [--listen]
//
// Sends the same flight live, in real time, to URL (udp://127.0.0.1:5600, a multicast group
// udp://239.255.0.1:5600?ttl=1, rtp://127.0.0.1:5600, srt://127.0.0.1:5600?mode=caller):
// the source of the live FMV scene (assets/scenes/fmv-live.json). --listen waits for one
// receiver to connect instead (tcp://, srt://, or http://127.0.0.1:8080/feed.ts served by
// FFmpeg's HTTP server). --frames 0 sends until stopped (Ctrl+C). --wall-clock stamps each
// packet with the time it is sent (for latency).
#include "tools/gen/FmvFixture.h"

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

int usage() {
    std::fprintf(stderr, "usage: orbis-make-fmv OUTDIR [--frames N] [--fps F] [--size WxH] [--async] [--no-klv] [--csv] [--flight-start S]\n"
                         "       orbis-make-fmv --stream URL [--frames N (0: until stopped)] [--fps F] [--size WxH] [--async] [--wall-clock] [--listen]\n"
                         "                      [--flight-start S]\n");
    return 2;
}

std::atomic<bool> stopped{false};

/// The options both modes take (--frames, --fps, --size, --flight-start, --async), from argv[i]
/// on; false on one it does not know or a value missing.
template <class Options>
bool commonOption(Options& o, int argc, char** argv, int& i) {
    const std::string a = argv[i];
    if (a == "--async") return o.async = true;
    if (i + 1 >= argc) return false;
    if (a == "--frames") o.frames = std::atoi(argv[++i]);
    else if (a == "--fps") o.fps = std::atoi(argv[++i]);
    else if (a == "--flight-start") o.flightStart = std::atof(argv[++i]);
    else if (a == "--size") return std::sscanf(argv[++i], "%dx%d", &o.width, &o.height) == 2;
    else return false;
    return true;
}

int stream(int argc, char** argv) {
    orbis::fmv::FmvStreamOptions o;
    const std::string url = argv[2];
    for (int i = 3; i < argc; ++i) {
        if (std::string(argv[i]) == "--wall-clock") o.stampWallClock = true;
        else if (std::string(argv[i]) == "--listen") o.listen = true;
        else if (!commonOption(o, argc, argv, i)) return usage();
    }
    if (o.frames < 0 || o.fps < 1 || o.fps > 240 || o.width < 16 || o.height < 16 || o.width > 4096 || o.height > 4096 ||
        o.width % 2 || o.height % 2) {
        std::fprintf(stderr, "orbis-make-fmv: frames >= 0, fps 1..240, an even size from 16x16 to 4096x4096\n");
        return 2;
    }
    if (o.frames == 0) o.frames = 1 << 30;
    std::signal(SIGINT, [](int) { stopped = true; });
    std::signal(SIGTERM, [](int) { stopped = true; });
    std::printf("orbis-make-fmv: sending the flight to %s (%dx%d, %d fps, %s KLV)\n", url.c_str(), o.width, o.height, o.fps,
                o.async ? "asynchronous" : "synchronous");
    std::fflush(stdout);
    auto sent = orbis::fmv::streamFmvFixture(url, o, stopped);
    if (!sent) {
        std::fprintf(stderr, "orbis-make-fmv: %s\n", sent.message().c_str());
        return 1;
    }
    std::printf("orbis-make-fmv: %d frames sent\n", *sent);
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc >= 3 && std::string(argv[1]) == "--stream") return stream(argc, argv);
    if (argc < 2 || argv[1][0] == '-') return usage();
    orbis::fmv::FmvFixtureOptions o;
    for (int i = 2; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--csv") o.csv = true;
        else if (a == "--no-klv") o.klv = false;
        else if (!commonOption(o, argc, argv, i)) return usage();
    }
    if (o.frames < 1 || o.frames > 100000 || o.fps < 1 || o.fps > 240 || o.width < 16 || o.height < 16 || o.width > 4096 ||
        o.height > 4096 || o.width % 2 || o.height % 2) {
        std::fprintf(stderr, "orbis-make-fmv: frames 1..100000, fps 1..240, an even size from 16x16 to 4096x4096\n");
        return 2;
    }
    if (auto r = orbis::fmv::writeFmvFixture(argv[1], o); !r) {
        std::fprintf(stderr, "orbis-make-fmv: %s\n", r.message().c_str());
        return 1;
    }
    std::printf("orbis-make-fmv: %s: flight.ts (%d frames, %dx%d, %d fps, %s), flight-dem.tif%s\n", argv[1], o.frames, o.width,
                o.height, o.fps, !o.klv ? "no KLV" : o.async ? "asynchronous KLV" : "synchronous KLV", o.csv ? ", flight.csv" : "");
    return 0;
}
