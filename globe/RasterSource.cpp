// RasterSource: opening a source, reading tiles, describing a file. The GDAL side (configuration,
// handle pool, warping, inspecting) is in RasterSourceGdal.cpp; shared internals in RasterSourceImpl.h.
#include "globe/CplXml.h"
#include "globe/RasterSourceImpl.h"
#include "globe/TileCacheFs.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <thread>

namespace orbis::globe {

using namespace raster_detail;

std::string defaultRasterCacheDir() {
    namespace fs = std::filesystem;
    if (const char* d = std::getenv("ORBIS_CACHE_DIR"); d && *d) return (fs::path(d) / "gdal").string();
    if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d) return (fs::path(d) / "orbis" / "gdal").string();
    if (const char* d = std::getenv("HOME"); d && *d) return (fs::path(d) / ".cache" / "orbis" / "gdal").string();
    std::error_code ec;
    return (fs::temp_directory_path(ec) / "orbis-gdal-cache").string();
}

// ---------------------------------------------------------------------------------------------
// RasterSource

RasterSource::RasterSource(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
RasterSource::~RasterSource() = default;

namespace {
/// A VRT (as XML text) that shows `ds`, read from `path`, as a WGS 84 lon/lat image covering
/// `b` (outer pixel corners), every band as it is.
Result<std::string> georeferencedVrt(GDALDatasetH ds, const std::string& path, const GeoExtent& b) {
    if (!(b.west < b.east && b.south < b.north) || b.west < -540.0 || b.east > 540.0 || b.south < -90.0 || b.north > 90.0)
        return makeError("\"bounds\" must be [west, south, east, north] in degrees with west < east, south < north, "
                         "latitudes within -90..90");
    const int w = GDALGetRasterXSize(ds), h = GDALGetRasterYSize(ds);
    std::ostringstream x;
    x.precision(17);
    x << "<VRTDataset rasterXSize=\"" << w << "\" rasterYSize=\"" << h << "\"><SRS>EPSG:4326</SRS><GeoTransform>" << b.west
      << "," << (b.east - b.west) / w << ",0," << b.north << ",0," << -(b.north - b.south) / h << "</GeoTransform>";
    for (int i = 1; i <= GDALGetRasterCount(ds); ++i) {
        GDALRasterBandH band = GDALGetRasterBand(ds, i);
        x << "<VRTRasterBand dataType=\"" << GDALGetDataTypeName(GDALGetRasterDataType(band)) << "\" band=\"" << i
          << "\"><ColorInterp>" << GDALGetColorInterpretationName(GDALGetRasterColorInterpretation(band))
          << "</ColorInterp><SimpleSource><SourceFilename relativeToVRT=\"0\">" << xml::escape(path)
          << "</SourceFilename><SourceBand>" << i << "</SourceBand>"
          // Without the source's size and the rectangles, GDAL's implicit overviews of the VRT
          // read zeros (GDAL 3.6: measured).
          << "<SourceProperties RasterXSize=\"" << w << "\" RasterYSize=\"" << h << "\" DataType=\""
          << GDALGetDataTypeName(GDALGetRasterDataType(band)) << "\"/><SrcRect xOff=\"0\" yOff=\"0\" xSize=\"" << w
          << "\" ySize=\"" << h << "\"/><DstRect xOff=\"0\" yOff=\"0\" xSize=\"" << w << "\" ySize=\"" << h
          << "\"/></SimpleSource></VRTRasterBand>";
    }
    x << "</VRTDataset>";
    return x.str();
}

}  // namespace

Result<std::shared_ptr<RasterSource>> RasterSource::open(const RasterSourceOptions& options) {
    auto impl = std::make_unique<Impl>();
    Impl& s = *impl;
    s.options = options;
    s.role = options.role;
    configureGdal();   // GDAL and the tile cache's file system first: the XYZ description names it
    if (options.path.empty() == options.xyzUrl.empty())
        return makeError("raster source: give exactly one of a path and an XYZ URL (got \"" + options.path + "\" and \"" +
                         options.xyzUrl + "\")");
    if (!options.xyzUrl.empty()) {
        s.name = redactSecrets(options.xyzUrl);
        if (s.role == RasterRole::Elevation) return s.error("XYZ tile URLs are read as imagery only");
        if (options.xyzUrl.find("{z}") == std::string::npos && options.xyzUrl.find("${z}") == std::string::npos)
            return s.error("an XYZ URL needs {z}, {x} and {y} placeholders");
        s.openPath = xyzToWmsXml(options.xyzUrl, options.xyzMaxZoom,
                                 tileCachePath(options.cacheDir.empty() ? defaultRasterCacheDir() : options.cacheDir));
    } else {
        s.openPath = options.path;
        s.name = redactSecrets(options.path);   // for messages and logs only
    }
    if (options.bounds && !options.xyzUrl.empty()) return s.error("\"bounds\" georeferences a file, not an XYZ source");

    configureGdal();
    if (!options.cacheDir.empty()) s.cachePath = tileCachePath(options.cacheDir);
    if (auto ok = checkHttpAuth(options.httpAuth); !ok) return s.error(ok.message());
    const ScopedHttpAuth auth(options.httpAuth);
    GdalErrors unexpected;  // nothing GDAL says while opening reaches stderr
    const bool remote = isRemotePath(s.openPath);
    if (!remote) {
        VSIStatBufL st;
        if (VSIStatExL(s.openPath.c_str(), &st, VSI_STAT_EXISTS_FLAG) != 0) return s.error("no such file");
    }
    GDALDatasetH ds = nullptr;
    {
        // A WMTS builds its tile readers as it opens: they cache in `cacheDir` when one is given.
        const ScopedThreadOption cache("GDAL_DEFAULT_WMS_CACHE_PATH", s.cachePath.empty() ? nullptr : s.cachePath.c_str());
        GdalErrors errors;
        ds = GDALOpenEx(s.openPath.c_str(), GDAL_OF_RASTER | GDAL_OF_VERBOSE_ERROR, nullptr, nullptr, nullptr);
        if (!ds) {
            const std::string why = errors.text();
            GdalErrors quiet;
            if (GDALDatasetH vector = GDALOpenEx(s.openPath.c_str(), GDAL_OF_VECTOR, nullptr, nullptr, nullptr)) {
                GDALClose(vector);
                return s.error("is vector data, not a raster");
            }
            return s.error("not a raster GDAL can read (" + why + ")");
        }
    }
    if (options.bounds) {
        // A picture without georeferencing: read through a VRT that places it on the given
        // lon/lat box (an XML string GDAL opens like a file, for every handle and overview).
        auto vrt = georeferencedVrt(ds, s.openPath, *options.bounds);
        GDALClose(ds);
        if (!vrt) return s.error(vrt.message());
        s.openPath = *vrt;
        GdalErrors errors;
        ds = GDALOpenEx(s.openPath.c_str(), GDAL_OF_RASTER | GDAL_OF_VERBOSE_ERROR, nullptr, nullptr, nullptr);
        if (!ds) return s.error("cannot georeference it with \"bounds\" (" + errors.text() + ")");
    }
    if (!options.path.empty() && EQUALN(options.path.c_str(), "WMS:", 4)) {
        // A WMS URL: read through a description with a timeout and the tile cache (GDAL's own
        // from a URL has neither).
        if (auto xml = wmsUrlToXml(ds, options.cacheDir.empty() ? defaultRasterCacheDir() : options.cacheDir,
                                   options.role == RasterRole::Elevation)) {
            GDALClose(ds);
            s.openPath = *xml;
            GdalErrors errors;
            ds = GDALOpenEx(s.openPath.c_str(), GDAL_OF_RASTER | GDAL_OF_VERBOSE_ERROR, nullptr, nullptr, nullptr);
            if (!ds) return s.error("cannot open its service description (" + errors.text() + ")");
        }
    }
    DatasetGuard guard{ds};
    if (auto r = s.inspect(ds); !r) return r.error();
    if (auto r = s.planBands(ds); !r) return r.error();
    const bool local = !remote && s.driver != "WMS" && s.driver != "WMTS";
    if (local)
        if (auto r = s.probe(ds); !r) return r.error();
    guard.ds = nullptr;  // the first handle owns it now
    auto first = s.openHandle(ds);
    if (!first) return first.error();
    if (auto r = s.computeCoverage((*first)->levels[0]); !r) return r.error();
    s.computeLevels();
    s.maxHandles = int(std::clamp(std::thread::hardware_concurrency(), 2u, 8u));
    s.opened = 1;
    s.idle.push_back(std::move(first.value()));
    log::debug(s.name, ": opened (", s.driver, ", ", s.width, " x ", s.height, ", ", s.crsName, ")");
    return std::shared_ptr<RasterSource>(new RasterSource(std::move(impl)));
}

bool isRemoteSource(const RasterSourceOptions& options) { return !options.xyzUrl.empty() || isRemotePath(options.path); }

const std::string& RasterSource::name() const { return impl_->name; }
RasterRole RasterSource::role() const { return impl_->role; }
GeoExtent RasterSource::coverage() const { return impl_->coverage; }
double RasterSource::resolutionDeg() const { return impl_->resolutionDeg; }
uint32_t RasterSource::minLevel() const { return impl_->minLevel; }
bool RasterSource::covers(const GeoExtent& extent) const { return impl_->coverage.intersects(extent); }
int RasterSource::maxHandles() const { return impl_->maxHandles; }
int RasterSource::openHandles() const {
    std::lock_guard lock(impl_->poolMutex);
    return impl_->opened;
}

uint32_t RasterSource::maxLevel(int tileSize) const {
    if (impl_->options.maxLevelOverride >= 0)
        return std::min<uint32_t>(uint32_t(impl_->options.maxLevelOverride), TileKey::kMaxLevel);
    const double res = impl_->resolutionDeg;
    uint32_t level = 0;
    while (level < TileKey::kMaxLevel && 180.0 / double(1u << level) / std::max(1, tileSize) > res * 1.0001) ++level;
    return std::max(level, impl_->minLevel);
}

namespace {

Result<bool> checkRequest(const std::string& name, const GeoExtent& e, int size, int minSize) {
    if (size < minSize || size > kMaxTileSize)
        return makeError(name + ": tile size " + std::to_string(size) + " outside " + std::to_string(minSize) + ".." +
                         std::to_string(kMaxTileSize));
    if (!std::isfinite(e.west) || !std::isfinite(e.east) || !std::isfinite(e.south) || !std::isfinite(e.north) ||
        !e.valid())
        return makeError(name + ": invalid extent " + fmtExtent(e));
    return true;
}
}  // namespace

Result<ElevationTile> RasterSource::readElevation(const GeoExtent& extent, int size,
                                                  const jobs::CancelToken* cancel) const {
    const Impl& s = *impl_;
    if (s.role != RasterRole::Elevation) return s.error("is an imagery source, not elevation");
    if (auto r = checkRequest(s.name, extent, size, 2); !r) return r.error();
    ElevationTile tile;
    tile.size = size;
    tile.heights.assign(size_t(size) * size_t(size), kNaN);
    auto read = s.warp(extent, size, true, cancel, tile.heights.data(), nullptr);
    if (!read) return read.error();
    if (!*read) return tile;
    float lo = std::numeric_limits<float>::max(), hi = std::numeric_limits<float>::lowest();
    const bool scaled = s.valueScale != 1.0 || s.valueOffset != 0.0;
    for (float& h : tile.heights) {
        if (std::isnan(h)) continue;
        if (scaled) h = float(h * s.valueScale + s.valueOffset);
        lo = std::min(lo, h), hi = std::max(hi, h);
        tile.anyValid = true;
    }
    if (tile.anyValid) tile.minHeight = lo, tile.maxHeight = hi;
    return tile;
}

Result<ImageryTile> RasterSource::readImagery(const GeoExtent& extent, int size, const jobs::CancelToken* cancel) const {
    const Impl& s = *impl_;
    if (s.role != RasterRole::Imagery) return s.error("is an elevation source, not imagery");
    if (auto r = checkRequest(s.name, extent, size, 1); !r) return r.error();
    const size_t n = size_t(size) * size_t(size), nb = s.bands.size();
    ImageryTile tile;
    tile.size = size;
    tile.rgba.assign(n * 4, 0);
    std::vector<uint8_t> alpha(n, 0);
    std::vector<uint8_t> bytes;
    std::vector<float> floats;
    void* planes = nullptr;
    if (s.workType == GDT_Byte)
        bytes.assign(n * nb, 0), planes = bytes.data();
    else
        floats.assign(n * nb, 0.0f), planes = floats.data();
    auto read = s.warp(extent, size, false, cancel, planes, alpha.data());
    if (!read) return read.error();
    if (!*read) return tile;

    // Planar work type -> interleaved RGBA8; alpha 0 (and black) where nothing was warped.
    const uint8_t* r = bytes.data();
    const uint8_t* g = nb == 3 ? r + n : r;
    const uint8_t* b = nb == 3 ? r + 2 * n : r;
    if (s.workType != GDT_Byte) {
        bytes.resize(n * nb);
        for (size_t k = 0; k < nb; ++k) {
            const auto [lo, hi] = s.valueRange[k];
            const double scale = 255.0 / (hi > lo ? hi - lo : 1.0);
            for (size_t p = 0; p < n; ++p) {
                const double v = (double(floats[k * n + p]) - lo) * scale;
                bytes[k * n + p] = uint8_t(std::isfinite(v) ? std::clamp(v + 0.5, 0.0, 255.0) : 0.0);
            }
        }
        r = bytes.data(), g = nb == 3 ? r + n : r, b = nb == 3 ? r + 2 * n : r;
    }
    uint8_t any = 0;
    uint8_t* out = tile.rgba.data();
    if (s.palette) {
        for (size_t p = 0; p < n; ++p, out += 4) {
            if (!alpha[p]) continue;
            const auto& c = s.paletteRgba[r[p]];
            out[0] = c[0], out[1] = c[1], out[2] = c[2];
            out[3] = uint8_t((unsigned(alpha[p]) * c[3] + 127) / 255);
            any |= out[3];
        }
    } else {
        for (size_t p = 0; p < n; ++p, out += 4) {
            if (!alpha[p]) continue;
            out[0] = r[p], out[1] = g[p], out[2] = b[p], out[3] = alpha[p];
            any = 1;
        }
    }
    tile.anyValid = any != 0;
    return tile;
}

std::string RasterSource::describe() const {
    const Impl& s = *impl_;
    std::ostringstream o;
    o.precision(8);
    o << s.name << "\n  driver " << s.driver << ", " << s.width << " x " << s.height << " pixels, " << s.bandCount
      << (s.bandCount == 1 ? " band\n" : " bands\n");
    for (size_t b = 0; b < s.bandInfo.size(); ++b) {
        const auto& i = s.bandInfo[b];
        o << "  band " << b + 1 << ": " << i.type << ", " << i.interp;
        if (i.noData) o << ", nodata " << *i.noData;
        if (i.scale != 1.0 || i.offset != 0.0) o << ", scale " << i.scale << " offset " << i.offset;
        o << "\n";
    }
    o << "  CRS: " << s.crsName << (s.crsEpsg.empty() ? " (no EPSG code)" : " (EPSG:" + s.crsEpsg + ")") << "\n";
    o << "  coverage: lon " << s.coverage.west << " .. " << s.coverage.east << ", lat " << s.coverage.south << " .. "
      << s.coverage.north << "\n";
    o << "  resolution: " << s.resolutionDeg << " deg (~" << std::lround(s.resolutionDeg * 111320.0) << " m)\n";
    o << "  overviews:";
    if (s.overviews.empty()) o << " none";
    for (const auto& [w, h] : s.overviews) o << " " << w << "x" << h;
    o << "\n  read as " << (s.role == RasterRole::Elevation ? "elevation" : s.palette ? "imagery (colour table)" : "imagery")
      << ", bands";
    for (int b : s.bands) o << " " << b;
    if (s.srcAlpha) o << ", alpha band " << s.srcAlpha;
    o << "; levels " << s.minLevel << " .. " << maxLevel(s.role == RasterRole::Elevation ? 65 : 256) << "\n";
    return o.str();
}

Result<std::string> describeRasterJson(const std::string& path) {
    using nlohmann::json;
    configureGdal();
    if (!isRemotePath(path)) {
        VSIStatBufL st;
        if (VSIStatExL(path.c_str(), &st, VSI_STAT_EXISTS_FLAG) != 0) return makeError(path + ": no such file");
    }
    json j;
    bool elevationLike = false;
    {
        GdalErrors errors;
        GDALDatasetH ds = GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_VERBOSE_ERROR, nullptr, nullptr, nullptr);
        if (!ds) return makeError(path + ": not a raster GDAL can read (" + errors.text() + ")");
        DatasetGuard guard{ds};
        j["file"] = path;
        j["driver"] = GDALGetDriverShortName(GDALGetDatasetDriver(ds));
        j["width"] = GDALGetRasterXSize(ds);
        j["height"] = GDALGetRasterYSize(ds);
        j["bands"] = json::array();
        for (int b = 1; b <= GDALGetRasterCount(ds); ++b) {
            GDALRasterBandH band = GDALGetRasterBand(ds, b);
            json jb = {{"band", b},
                       {"type", typeName(GDALGetRasterDataType(band))},
                       {"colorInterp", GDALGetColorInterpretationName(GDALGetRasterColorInterpretation(band))},
                       {"scale", GDALGetRasterScale(band, nullptr)},
                       {"offset", GDALGetRasterOffset(band, nullptr)}};
            int has = 0;
            const double nd = GDALGetRasterNoDataValue(band, &has);
            if (has) jb["noData"] = std::isfinite(nd) ? json(nd) : json(std::to_string(nd));
            jb["overviews"] = json::array();
            for (int i = 0; i < GDALGetOverviewCount(band); ++i)
                if (GDALRasterBandH ov = GDALGetOverview(band, i))
                    jb["overviews"].push_back({GDALGetRasterBandXSize(ov), GDALGetRasterBandYSize(ov)});
            j["bands"].push_back(jb);
        }
        elevationLike = GDALGetRasterCount(ds) == 1 && GDALGetRasterDataType(GDALGetRasterBand(ds, 1)) != GDT_Byte;
        OGRSpatialReferenceH srs = GDALGetSpatialRef(ds);
        if (!srs && GDALGetGCPCount(ds) > 0) srs = GDALGetGCPSpatialRef(ds);
        if (srs) {
            json crs = {{"name", OSRGetName(srs) ? OSRGetName(srs) : "unnamed"}};
            const char* auth = OSRGetAuthorityName(srs, nullptr);
            const char* code = OSRGetAuthorityCode(srs, nullptr);
            if (auth && code && EQUAL(auth, "EPSG")) crs["epsg"] = std::atoi(code);
            j["crs"] = crs;
        } else {
            j["crs"] = nullptr;
        }
        double gt[6];
        if (GDALGetGeoTransform(ds, gt) == CE_None) j["geoTransform"] = {gt[0], gt[1], gt[2], gt[3], gt[4], gt[5]};
    }
    if (j["width"].get<int>() > 0 && !j["bands"].empty()) {
        RasterSourceOptions o;
        o.path = path;
        o.role = elevationLike ? RasterRole::Elevation : RasterRole::Imagery;
        auto src = RasterSource::open(o);
        if (src) {
            const GeoExtent c = (*src)->coverage();
            j["readAs"] = elevationLike ? "elevation" : "imagery";
            j["coverage"] = {{"west", c.west}, {"south", c.south}, {"east", c.east}, {"north", c.north}};
            j["resolutionDeg"] = (*src)->resolutionDeg();
            j["maxLevel65"] = (*src)->maxLevel(65);
            j["maxLevel256"] = (*src)->maxLevel(256);
            j["minLevel"] = (*src)->minLevel();
        } else {
            j["warning"] = src.message();
        }
    } else {
        j["warning"] = path + ": has no raster bands";
    }
    return j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);   // metadata from the file
}

}  // namespace orbis::globe
