// orbis measure: geodesic measures, terrain profiles and lines of sight from the command line
// (globe/Geodesic.h, globe/TerrainAnalysis.h, globe/ElevationSampler.h). No GPU.
//
//   orbis measure --path "LON,LAT LON,LAT ..."                 length along geodesics
//   orbis measure --path "..." --polygon                        area and perimeter too
//   orbis measure --path "..." --dem DEM [--step M] [--csv OUT] the ground along it
//   orbis measure --sight "LON,LAT,H LON,LAT,H" --dem DEM       line of sight (H above the ground)
#include "globe/ElevationSampler.h"
#include "globe/Geodesic.h"
#include "globe/GdalSetup.h"
#include "globe/RasterSource.h"
#include "globe/TerrainAnalysis.h"
#include "tools/orbis/Args.h"
#include "tools/orbis/Commands.h"
#include "tools/orbis/Session.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace orbis::cli {
namespace {

const char* kHelp =
    "usage: orbis measure --path \"LON,LAT LON,LAT ...\" [--polygon] [--dem DEM [--step M] [--csv OUT.csv]]\n"
    "       orbis measure --sight \"LON,LAT,H LON,LAT,H\" --dem DEM [--step M] [--refraction K]\n"
    "Geodesic measures on WGS84 (GeographicLib): a path's length, with --polygon the area and\n"
    "perimeter of the ring it closes; with --dem, the ground along the path from the DEM at its own\n"
    "resolution (every --step metres, default 10; --csv writes distance,lon,lat,height). --sight:\n"
    "whether the second point is seen from the first, each H metres above the ground, the straight\n"
    "line raised by refraction K (default 1/7, as gdal_viewshed; 0: geometric).\n"
    "Points are separated by spaces or ';'. Exit codes: 0 ok (also when the sight is blocked),\n"
    "1 bad input, 2 usage.\n";

/// "LON,LAT[,H] ..." into points of `arity` numbers; UsageError naming the option.
std::vector<std::vector<double>> points(const std::string& option, const std::string& text, size_t arity) {
    std::vector<std::vector<double>> out;
    std::string spaced = text;
    for (char& c : spaced)
        if (c == ';') c = ' ';
    std::istringstream in(spaced);
    std::string token;
    while (in >> token) {
        std::vector<double> p;
        std::istringstream parts(token);
        std::string part;
        while (std::getline(parts, part, ',')) {
            size_t used = 0;
            double v = 0.0;
            try {
                v = std::stod(part, &used);
            } catch (const std::exception&) {
                used = 0;
            }
            if (used != part.size() || part.empty() || !std::isfinite(v))
                throw UsageError{option + ": \"" + token + "\" is not " + (arity == 2 ? "LON,LAT" : "LON,LAT,H") + " numbers"};
            p.push_back(v);
        }
        if (p.size() != arity) throw UsageError{option + ": \"" + token + "\" has " + std::to_string(p.size()) + " numbers, expected " + std::to_string(arity)};
        if (p[1] < -90.0 || p[1] > 90.0) throw UsageError{option + ": the latitude in \"" + token + "\" is outside -90..90"};
        if (p[0] < -540.0 || p[0] > 540.0) throw UsageError{option + ": longitude in \"" + token + "\" is outside -540..540"};
        if (out.size() >= 100000) throw UsageError{option + ": more than 100000 points"};
        out.push_back(std::move(p));
    }
    return out;
}

std::string metres(double m) {
    char s[64];
    if (std::abs(m) >= 10000.0) std::snprintf(s, sizeof s, "%.3f km", m / 1000.0);
    else std::snprintf(s, sizeof s, "%.3f m", m);
    return s;
}

}  // namespace

int measureCommand(const std::vector<std::string>& argv) {
    const Args args(argv, {"--path", "--sight", "--dem", "--step", "--csv", "--refraction"}, {"--polygon", "--help"}, {{"-h", "--help"}});
    if (args.flag("--help")) {
        std::printf("%s", kHelp);
        return kOk;
    }
    if (!args.positional().empty()) throw UsageError{"unexpected argument " + args.positional().front()};
    const auto path = args.value("--path"), sight = args.value("--sight"), demPath = args.value("--dem");
    if (!!path == !!sight) throw UsageError{"give --path or --sight (one of them)"};
    if (sight && !demPath) throw UsageError{"--sight needs --dem (the ground)"};
    if (args.flag("--polygon") && !path) throw UsageError{"--polygon measures a --path"};
    if (args.value("--csv") && !demPath) throw UsageError{"--csv writes the ground along the path: give --dem"};
    const double step = args.number("--step", 0.01, 1e7).value_or(10.0);
    const double refraction = args.number("--refraction", -1.0, 1.0).value_or(1.0 / 7.0);

    std::shared_ptr<const globe::ElevationSampler> sampler;
    if (demPath) {
        globe::configureGdal();
        auto dem = globe::RasterSource::open({.path = *demPath, .role = globe::RasterRole::Elevation});
        if (!dem) return badInput(dem.message());
        sampler = std::make_shared<const globe::ElevationSampler>(*dem);
    }
    if (sight) {
        const auto p = points("--sight", *sight, 3);
        if (p.size() != 2) throw UsageError{"--sight takes two points, the observer and the target"};
        const auto groundAt = [&](const std::vector<double>& q) { return sampler->heightAt(q[0], q[1]); };
        const auto g0 = groundAt(p[0]), g1 = groundAt(p[1]);
        if (!g0 || !g1)
            return badInput(*demPath + ": no ground under the " + std::string(!g0 ? "observer" : "target") + " (outside the DEM or no data)" +
                            (sampler->error().empty() ? "" : ": " + sampler->error()));
        const globe::Geodetic observer{p[0][0], p[0][1], *g0 + p[0][2]}, target{p[1][0], p[1][1], *g1 + p[1][2]};
        const globe::LineOfSight s =
            globe::lineOfSight(observer, target, globe::ElevationSampler::function(sampler), {.stepM = step, .refraction = refraction});
        std::printf("observer    %.7f, %.7f at %.2f m (%.2f m above the ground)\n", observer.lonDeg, observer.latDeg, observer.height, p[0][2]);
        std::printf("target      %.7f, %.7f at %.2f m (%.2f m above the ground)\n", target.lonDeg, target.latDeg, target.height, p[1][2]);
        std::printf("distance    %s (straight), %zu samples, %zu without ground\n", metres(s.distanceM).c_str(), s.samples, s.unknown);
        if (s.visible) std::printf("visible     yes, %.2f m clear at the closest\n", s.clearanceM);
        else
            std::printf("visible     no: blocked %s from the observer at %.7f, %.7f, ground %.2f m, %.2f m above the line\n",
                        metres(s.blockedAtM).c_str(), s.blockedAt.x, s.blockedAt.y, s.blockingHeight, s.aboveLineM);
        return kOk;
    }
    std::vector<globe::LonLat> ring;
    for (const auto& q : points("--path", *path, 2)) ring.push_back({q[0], q[1]});
    if (ring.size() < 2) throw UsageError{"--path needs two points at least"};
    const globe::PathLength length = globe::geodesicLength(ring);
    std::printf("length      %s over %zu points\n", metres(length.metres).c_str(), ring.size());
    if (args.flag("--polygon")) {
        const globe::PolygonMeasure m = globe::geodesicPolygon(ring);
        if (m.vertices < 3) throw UsageError{"--polygon needs three distinct points at least"};
        std::printf("area        %.6g m^2 (%.6g km^2)\n", m.areaM2, m.areaM2 / 1e6);
        std::printf("perimeter   %s\n", metres(m.perimeterM).c_str());
    }
    if (!sampler) return kOk;
    const globe::TerrainProfile profile = globe::terrainProfile(ring, globe::ElevationSampler::function(sampler), step);
    if (!sampler->error().empty()) return badInput(sampler->error());
    std::printf("ground      %zu samples every %s at most, %zu without data\n", profile.samples.size(), metres(step).c_str(), profile.unknown);
    if (profile.minHeight)
        std::printf("heights     %.2f to %.2f m; ascent %.2f m, descent %.2f m\n", *profile.minHeight, *profile.maxHeight, profile.ascentM,
                    profile.descentM);
    if (const auto csv = args.value("--csv")) {
        std::ofstream out(*csv);
        out << "distance_m,lon,lat,height_m\n";
        char line[160];
        for (const globe::ProfileSample& s : profile.samples) {
            if (s.height) std::snprintf(line, sizeof line, "%.3f,%.8f,%.8f,%.3f\n", s.distanceM, s.at.x, s.at.y, *s.height);
            else std::snprintf(line, sizeof line, "%.3f,%.8f,%.8f,\n", s.distanceM, s.at.x, s.at.y);
            out << line;
        }
        out.close();
        if (!out) return badInput(*csv + ": cannot write");
        std::printf("wrote       %s\n", csv->c_str());
    }
    return kOk;
}

}  // namespace orbis::cli
