// orbis convert IN OUT: point clouds between LAS and LAZ; orbis convert IN --decode: how fast a
// cloud decodes (points per second, the LAZ decoder's benchmark).
#include "tools/orbis/Args.h"
#include "tools/orbis/Commands.h"
#include "tools/orbis/Session.h"

#include "layers/points/CopcWriter.h"
#include "layers/points/LasReader.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>

namespace orbis::cli {
namespace {

const char* kHelp =
    "usage: orbis convert IN OUT [--chunk N] [--node-points N] [--batch-points N]\n"
    "       orbis convert IN --decode [--threads N] [--runs N] [--positions]\n"
    "IN: a LAS or LAZ point cloud (LAS 1.0-1.4, LAZ of every LASzip compressor, COPC). OUT: a .copc.laz\n"
    "(COPC 1.0: an octree of nodes of at most --node-points points, 100000 by default, each a LAZ chunk,\n"
    "for streaming from a web server; the input needs a CRS; built out of core: at most --batch-points\n"
    "points, 10000000 by default, in memory at once, larger clouds through temporary files next to OUT),\n"
    "a .laz (LAS 1.4, point format 6, 7 with colours or 8 with near-infrared, layered chunks of --chunk\n"
    "points, 50000 by default) or a .las (the same points uncompressed). Coordinates keep the input's\n"
    "scale and offset, and its CRS (as a WKT VLR). Progress goes to stderr.\n"
    "--decode reads every point of IN, RUNS times (3), and prints the median rate as JSON; --threads\n"
    "sets the LAZ decoding threads (default: every core); --positions reads positions only.\n";

using Clock = std::chrono::steady_clock;

int decode(const std::string& in, const Args& args) {
    auto file = points::LasFile::open(in);
    if (!file) {
        std::fprintf(stderr, "orbis: %s\n", file.message().c_str());
        return kBadInput;
    }
    const unsigned threads = unsigned(args.integer("--threads", 1, 256).value_or(0));
    if (threads > 0) (*file)->setDecodeThreads(threads);
    const int runs = int(args.integer("--runs", 1, 100).value_or(3));
    const bool positions = args.flag("--positions");
    const uint64_t n = (*file)->points(), per = 1u << 20;
    std::vector<double> seconds;
    std::vector<points::LasPoint> pts;
    std::vector<glm::dvec3> xyz;
    for (int r = 0; r < runs; ++r) {
        const auto t0 = Clock::now();
        for (uint64_t first = 0; first < n; first += per) {
            auto read = positions ? (*file)->readPositions(first, per, xyz) : (*file)->read(first, per, pts);
            if (!read) {
                std::fprintf(stderr, "orbis: %s\n", read.message().c_str());
                return kBadInput;
            }
        }
        seconds.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
    }
    std::sort(seconds.begin(), seconds.end());
    const double median = seconds[seconds.size() / 2];
    nlohmann::json out = {{"file", in},
                          {"compression", (*file)->header().compression.empty() ? "none" : (*file)->header().compression},
                          {"points", n},
                          {"threads", threads},
                          {"positionsOnly", positions},
                          {"seconds", {{"median", median}, {"min", seconds.front()}, {"max", seconds.back()}}},
                          {"millionPointsPerSecond", median > 0 ? double(n) / median * 1e-6 : 0.0}};
    std::printf("%s\n", out.dump(2).c_str());
    return kOk;
}

}  // namespace

int convertCommand(const std::vector<std::string>& argv) {
    const Args args(argv, {"--chunk", "--threads", "--runs", "--node-points", "--batch-points"}, {"--help", "--decode", "--positions"});
    if (args.flag("--help")) {
        std::printf("%s", kHelp);
        return kOk;
    }
    const auto& pos = args.positional();
    if (args.flag("--decode")) {
        if (pos.size() != 1) throw UsageError{"--decode takes one input file"};
        return decode(pos[0], args);
    }
    if (pos.size() != 2) throw UsageError{"expected an input and an output file"};
    const std::string in = pos[0], out = pos[1];
    std::string ext = std::filesystem::path(out).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (ext != ".laz" && ext != ".las") throw UsageError{"the output must be a .laz or a .las file"};
    auto file = points::LasFile::open(in);
    if (!file) {
        std::fprintf(stderr, "orbis: %s\n", file.message().c_str());
        return kBadInput;
    }
    std::string lower = out;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    if (lower.size() > 9 && lower.compare(lower.size() - 9, 9, ".copc.laz") == 0) {
        points::CopcWriteOptions o;
        o.maxNodePoints = uint32_t(args.integer("--node-points", 100, 10'000'000).value_or(100000));
        o.batchPoints = uint64_t(args.integer("--batch-points", 10'000, 4'000'000'000).value_or(10'000'000));
        int lastPercent = -1;
        o.progress = [&](double f) {
            if (int(100 * f) != lastPercent) std::fprintf(stderr, "\rwriting COPC %s: %d %%", out.c_str(), lastPercent = int(100 * f));
        };
        const auto t0 = Clock::now();
        auto stats = points::writeCopc(**file, out, o);
        if (!stats) {
            std::fprintf(stderr, "\norbis: %s\n", stats.message().c_str());
            return kBadInput;
        }
        std::fprintf(stderr, "\rwrote COPC %s: %llu points in %u nodes, depth %u, %u batches, %.1f MB in %.2f s\n", out.c_str(),
                     static_cast<unsigned long long>(stats->points), stats->nodes, stats->depth, stats->batches, double(stats->bytes) / 1e6,
                     std::chrono::duration<double>(Clock::now() - t0).count());
        return kOk;
    }
    const points::LasHeader& h = (*file)->header();
    points::LasWriteOptions o;
    o.versionMinor = 4;
    o.pointFormat = h.hasNir() ? 8 : h.hasRgb() ? 7 : 6;
    o.scale = h.scale;
    o.offset = h.offset;
    o.wkt = (*file)->crs().wkt;
    o.laz = ext == ".laz";
    o.lazChunkPoints = uint32_t(args.integer("--chunk", 1, 10'000'000).value_or(50000));
    auto writer = points::LasWriter::create(out, o);
    if (!writer) {
        std::fprintf(stderr, "orbis: %s\n", writer.message().c_str());
        return kBadInput;
    }
    const uint64_t n = (*file)->points(), per = 1u << 20;
    std::vector<points::LasPoint> pts;
    const auto t0 = Clock::now();
    int lastPercent = -1;
    for (uint64_t first = 0; first < n; first += per) {
        if (auto r = (*file)->read(first, per, pts); !r) {
            std::fprintf(stderr, "orbis: %s\n", r.message().c_str());
            return kBadInput;
        }
        (*writer)->write(pts);
        const int percent = int(100 * std::min(n, first + per) / std::max<uint64_t>(n, 1));
        if (percent != lastPercent) std::fprintf(stderr, "\rconverting %s: %d %%", in.c_str(), lastPercent = percent);
    }
    if (auto r = (*writer)->close(); !r) {
        std::fprintf(stderr, "\norbis: %s\n", r.message().c_str());
        return kBadInput;
    }
    const double s = std::chrono::duration<double>(Clock::now() - t0).count();
    std::error_code ec;
    const auto inBytes = std::filesystem::file_size(in, ec), outBytes = std::filesystem::file_size(out, ec);
    std::fprintf(stderr, "\rconverted %s: %llu points, %.1f MB -> %.1f MB (%s, format %u) in %.2f s\n", in.c_str(),
                 static_cast<unsigned long long>(n), double(inBytes) / 1e6, double(outBytes) / 1e6, o.laz ? "LAZ" : "LAS",
                 unsigned(o.pointFormat), s);
    return kOk;
}

}  // namespace orbis::cli
