// `orbis info cloud.las`: what a LAS file holds, as JSON.
#include "layers/points/PointCloud.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace orbis::points {

bool looksLikeLas(const std::string& path) {
    const std::string ext = std::filesystem::path(path).extension().string();
    if (ext == ".las" || ext == ".laz" || ext == ".LAS" || ext == ".LAZ") return true;
    if (path.rfind("http://", 0) == 0 || path.rfind("https://", 0) == 0) return false;   // named .las/.laz or not at all
    char magic[4] = {};
    std::ifstream in(path, std::ios::binary);
    return in.read(magic, 4) && std::equal(magic, magic + 4, "LASF");
}

Result<std::string> describeLasJson(const std::string& path) {
    auto opened = LasFile::open(path);
    if (!opened) return opened.error();
    const LasFile& f = **opened;
    const LasHeader& h = f.header();
    const auto vec = [](const glm::dvec3& v) { return nlohmann::json::array({v.x, v.y, v.z}); };
    nlohmann::json out;
    out["kind"] = "point cloud";
    out["file"] = path;
    out["version"] = std::to_string(h.versionMajor) + "." + std::to_string(h.versionMinor);
    out["pointFormat"] = h.pointFormat;
    out["recordLength"] = h.recordLength;
    out["extraBytes"] = h.extraBytes;
    out["points"] = h.pointCount;
    if (!h.compression.empty()) out["compression"] = h.compression;
    nlohmann::json byReturn = nlohmann::json::array();
    const size_t returns = h.versionMinor >= 4 ? 15 : 5;
    for (size_t i = 0; i < returns; ++i) byReturn.push_back(h.pointsByReturn[i]);
    out["pointsByReturn"] = byReturn;
    out["attributes"] = {{"gpsTime", h.hasGpsTime()}, {"rgb", h.hasRgb()}, {"nir", h.hasNir()}};
    out["scale"] = vec(h.scale);
    out["offset"] = vec(h.offset);
    out["bounds"] = {{"min", vec(h.min)}, {"max", vec(h.max)}};
    out["created"] = {{"year", h.creationYear}, {"dayOfYear", h.creationDay}};
    out["systemId"] = h.systemId;
    out["software"] = h.software;
    for (const LasVlr& v : h.vlrs)
        out["vlrs"].push_back({{"userId", v.userId}, {"recordId", v.recordId}, {"bytes", v.length},
                               {"description", v.description}, {"extended", v.extended}});
    nlohmann::json crs = {{"source", f.crs().source}};
    std::vector<LasPoint> first;
    if (auto r = f.read(0, 3, first); !r) return r.error();
    for (const LasPoint& p : first)
        out["firstPoints"].push_back({{"xyz", vec(p.position)}, {"intensity", p.intensity},
                                      {"classification", p.classification}, {"return", p.returnNumber},
                                      {"returns", p.numberOfReturns}, {"gpsTime", p.gpsTime},
                                      {"rgb", {p.red, p.green, p.blue}}});
    if (!f.crs().wkt.empty()) {
        auto g = LasGeoreference::create(f.crs().wkt, path);
        if (g) {
            crs["name"] = g->name();
            crs["linearUnitMetres"] = g->linearUnitMetres();
            crs["heightUnitMetres"] = g->verticalUnitMetres();
            // The header's corners on the globe (the box's 8 corners, lon/lat range and heights).
            std::vector<glm::dvec3> corners;
            for (int i = 0; i < 8; ++i)
                corners.push_back({(i & 1) ? h.max.x : h.min.x, (i & 2) ? h.max.y : h.min.y, (i & 4) ? h.max.z : h.min.z});
            g->toEcef(corners);
            double lon0 = 1e9, lon1 = -1e9, lat0 = 1e9, lat1 = -1e9, h0 = 1e30, h1 = -1e30;
            for (const glm::dvec3& c : corners) {
                if (!std::isfinite(c.x)) continue;
                const globe::Geodetic geo = globe::Ellipsoid::wgs84().toGeodetic(c);
                lon0 = std::min(lon0, geo.lonDeg), lon1 = std::max(lon1, geo.lonDeg);
                lat0 = std::min(lat0, geo.latDeg), lat1 = std::max(lat1, geo.latDeg);
                h0 = std::min(h0, geo.height), h1 = std::max(h1, geo.height);
            }
            if (lon0 <= lon1)
                out["geographicBounds"] = {{"lon", {lon0, lon1}}, {"lat", {lat0, lat1}}, {"heightAboveEllipsoid", {h0, h1}}};
        } else {
            crs["problem"] = g.message();
        }
    }
    out["crs"] = crs;
    return out.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);   // bytes from the file
}

}  // namespace orbis::points
