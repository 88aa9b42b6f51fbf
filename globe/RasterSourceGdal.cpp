// RasterSource internals over GDAL: configuration, the pool of open handles, warping a tile,
// and inspecting a file when it is opened.
#include "globe/CplXml.h"
#include "globe/RasterSourceImpl.h"
#include "globe/TileCacheFs.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstring>
#include <sstream>
#include <string_view>
#include <thread>

namespace orbis::globe {
namespace raster_detail {

bool isRemotePath(const std::string& p) {
    static const char* kRemote[] = {"/vsicurl", "/vsis3", "/vsigs", "/vsiaz", "/vsiadls", "/vsioss",
                                    "/vsiswift", "/vsiwebhdfs", "/vsihdfs"};
    for (const char* r : kRemote)
        if (p.find(r) != std::string::npos) return true;
    return p.find("://") != std::string::npos || (!p.empty() && p.front() == '<');
}

std::string plainGdalMessage(const std::string& message) {
    std::string m = message;
    // "file, band 1: IReadBlock failed at X offset 0, Y offset 720: <why>" -> "<why>"
    if (const size_t at = m.find("IReadBlock failed at"); at != std::string::npos) {
        const size_t colon = m.find(": ", at);
        m = colon == std::string::npos ? m : m.substr(colon + 2);
    }
    const auto trim = [](std::string t) {
        const size_t a = t.find_first_not_of(" \t\r\n."), b = t.find_last_not_of(" \t\r\n.");
        return a == std::string::npos ? std::string() : t.substr(a, b - a + 1);
    };
    if (m.find("Unable to open downloaded block") != std::string::npos ||
        m.find("RasterIO failed on downloaded block") != std::string::npos || m.find("ReadBlockFromFile (") != std::string::npos)
        return {};
    if (m.rfind("/vsiorbiscache/", 0) == 0 && m.find("No such file or directory") != std::string::npos) return {};
    if (const size_t at = m.find("HTTP status code: "); at != std::string::npos) {
        const int code = std::atoi(m.c_str() + at + 18);
        const size_t e = m.find("error: ", at);
        std::string why = e == std::string::npos ? std::string() : trim(m.substr(e + 7));
        why = why.substr(0, why.find('\n'));
        if (code == 0) return "no answer from the server" + (why.empty() ? std::string() : " (" + why + ")");
        return "the server answered HTTP " + std::to_string(code) + (why.empty() ? std::string() : ": " + why);
    }
    if (m.find("libpng") != std::string::npos || m.find("JPEG") != std::string::npos || m.find("wmsresult.dat") != std::string::npos)
    {
        // "Error while reading row 720: libpng: Read Error" -> "libpng: Read Error"
        const size_t row = m.find("Error while reading row ");
        if (row != std::string::npos && m.find(": ", row) != std::string::npos) m = m.substr(m.find(": ", row) + 2);
        return "the server sent a damaged image (" + trim(m) + ")";
    }
    if (const size_t at = m.find("GDALWMS: "); at != std::string::npos) m = m.substr(at + 9);
    return trim(m.substr(0, m.find("\nAdd the HTTP status code")));
}

std::string GdalErrors::text(const char* fallback) const {
    std::vector<std::string> plain;
    for (const std::string& m : messages_) {
        std::string p = plainGdalMessage(m);
        if (!p.empty() && std::find(plain.begin(), plain.end(), p) == plain.end()) plain.push_back(std::move(p));
    }
    if (plain.empty()) return messages_.empty() ? fallback : messages_.front();
    std::string s;
    for (size_t i = 0; i < plain.size() && i < 3; ++i) s += (s.empty() ? "" : "; ") + plain[i];
    return s;
}

/// A GDAL WMS (TMS minidriver) description of an XYZ server: EPSG:3857, 256-pixel tiles, y down,
/// four bands (alpha 0 where the server has no tile: 404/204 are empty blocks, not errors).
std::string xyzToWmsXml(const std::string& xyzUrl, int maxZoom, const std::string& cacheDir) {
    // {z}/{x}/{y} become GDAL's ${z}/${x}/${y} (already-$ forms are kept).
    std::string url;
    url.reserve(xyzUrl.size() + 3);
    for (size_t i = 0; i < xyzUrl.size(); ++i) {
        const bool placeholder = i + 2 < xyzUrl.size() && xyzUrl[i] == '{' && xyzUrl[i + 2] == '}' &&
                                 std::string_view("zxy").find(xyzUrl[i + 1]) != std::string_view::npos;
        if (placeholder && (i == 0 || xyzUrl[i - 1] != '$')) url += '$';
        url += xyzUrl[i];
    }
    const char* timeout = CPLGetConfigOption("GDAL_HTTP_TIMEOUT", "30");
    std::ostringstream x;
    x << "<GDAL_WMS><Service name=\"TMS\"><ServerUrl>" << xml::escape(url) << "</ServerUrl></Service>"
      << "<DataWindow><UpperLeftX>-20037508.342789244</UpperLeftX>"
      << "<UpperLeftY>20037508.342789244</UpperLeftY>"
      << "<LowerRightX>20037508.342789244</LowerRightX>"
      << "<LowerRightY>-20037508.342789244</LowerRightY>"
      << "<TileLevel>" << std::clamp(maxZoom, 0, 24) << "</TileLevel>"
      << "<TileCountX>1</TileCountX><TileCountY>1</TileCountY><YOrigin>top</YOrigin></DataWindow>"
      << "<Projection>EPSG:3857</Projection><BlockSizeX>256</BlockSizeX><BlockSizeY>256</BlockSizeY>"
      << "<BandsCount>4</BandsCount><MaxConnections>4</MaxConnections>"
      << "<Timeout>" << xml::escape(timeout) << "</Timeout>"
      << "<ZeroBlockHttpCodes>204,404</ZeroBlockHttpCodes>"
      << "<ZeroBlockOnServerException>true</ZeroBlockOnServerException>"
      << "<Cache><Path>" << xml::escape(cacheDir) << "</Path></Cache></GDAL_WMS>";
    return x.str();
}

std::optional<std::string> wmsUrlToXml(GDALDatasetH ds, const std::string& cacheDir, bool heights) {
    GDALDriverH wms = GDALGetDatasetDriver(ds);
    if (!wms || std::strcmp(GDALGetDriverShortName(wms), "WMS") != 0) return std::nullopt;
    // GDAL writes a WMS dataset's description through its CreateCopy: into memory, then read.
    static std::atomic<uint64_t> serial{0};
    const std::string tmp = "/vsimem/orbis-wms-" + std::to_string(++serial) + ".xml";
    GdalErrors quiet;
    GDALDatasetH copy = GDALCreateCopy(wms, tmp.c_str(), ds, FALSE, nullptr, nullptr, nullptr);
    if (copy) GDALClose(copy);
    vsi_l_offset size = 0;
    GByte* bytes = VSIGetMemFileBuffer(tmp.c_str(), &size, FALSE);
    std::string xml = bytes ? std::string(reinterpret_cast<const char*>(bytes), size_t(size)) : std::string();
    VSIUnlink(tmp.c_str());
    const size_t end = xml.rfind("</GDAL_WMS>");
    if (end == std::string::npos) return std::nullopt;
    std::string add;
    if (xml.find("<Timeout>") == std::string::npos)
        add += "<Timeout>" + xml::escape(CPLGetConfigOption("GDAL_HTTP_TIMEOUT", "30")) + "</Timeout>";
    if (xml.find("<Cache") == std::string::npos) add += "<Cache><Path>" + xml::escape(tileCachePath(cacheDir)) + "</Path></Cache>";
    if (xml.find("<MaxConnections>") == std::string::npos) add += "<MaxConnections>4</MaxConnections>";
    if (heights) {
        if (const size_t b = xml.find("<BandsCount>"); b != std::string::npos) {
            const size_t e = xml.find("</BandsCount>", b);
            if (e != std::string::npos) xml.replace(b, e - b, "<BandsCount>1");
        }
        if (xml.find("<DataType>") == std::string::npos) add += "<DataType>Float32</DataType>";
    }
    xml.insert(xml.rfind("</GDAL_WMS>"), add);
    return xml;
}

GDALResampleAlg resampleAlg(const std::string& name, bool* ok) {
    static const std::pair<const char*, GDALResampleAlg> kAlgs[] = {
        {"near", GRA_NearestNeighbour}, {"nearest", GRA_NearestNeighbour}, {"bilinear", GRA_Bilinear},
        {"cubic", GRA_Cubic}, {"cubicspline", GRA_CubicSpline}, {"lanczos", GRA_Lanczos},
        {"average", GRA_Average}, {"mode", GRA_Mode}, {"min", GRA_Min}, {"max", GRA_Max},
        {"med", GRA_Med}, {"q1", GRA_Q1}, {"q3", GRA_Q3}};
    for (const auto& [n, alg] : kAlgs)
        if (EQUAL(n, name.c_str())) { *ok = true; return alg; }
    *ok = false;
    return GRA_Bilinear;
}

std::string fmtExtent(const GeoExtent& e) {
    std::ostringstream s;
    s.precision(10);
    s << "[" << e.west << ", " << e.south << " .. " << e.east << ", " << e.north << "]";
    return s.str();
}
int CPL_STDCALL warpProgress(double, const char*, void* arg) {
    const auto* handle = static_cast<const Handle*>(arg);
    return handle->cancel && handle->cancel->cancelled() ? FALSE : TRUE;
}

}  // namespace raster_detail

using namespace raster_detail;

// ---------------------------------------------------------------------------------------------
// Handles

Result<bool> RasterSource::Impl::makeTransformer(Level& level) const {
    CPLStringList opts;
    opts.SetNameValue("DST_SRS", "EPSG:4326");  // GenImgProj uses it in lon, lat order
    if (assumedLonLat) opts.SetNameValue("SRC_SRS", "EPSG:4326");
    GdalErrors errors;
    level.genImg = GDALCreateGenImgProjTransformer2(level.ds, nullptr, opts.List());
    if (!level.genImg) return error("cannot transform its coordinates to lon/lat: " + errors.text());
    // Replaced before every read; deliberately not a whole-pixel shift of the source, so that the
    // warp operation built on it never takes its copy-pixels shortcut.
    const double gt[6] = {-180.0, 0.0123456789, 0.0, 90.0, 0.0, -0.0123456789};
    GDALSetGenImgProjTransformerDstGeoTransform(level.genImg, gt);
    level.approx = GDALCreateApproxTransformer(GDALGenImgProjTransform, level.genImg, kApproxErrorPx);
    if (!level.approx) {
        GDALDestroyGenImgProjTransformer(level.genImg);
        level.genImg = nullptr;
        return error("cannot create an approximate transformer");
    }
    GDALApproxTransformerOwnsSubtransformer(level.approx, TRUE);
    return true;
}

std::string RasterSource::Impl::changedSinceOpened(GDALDatasetH ds) const {
    const int w = GDALGetRasterXSize(ds), h = GDALGetRasterYSize(ds), bands = GDALGetRasterCount(ds);
    std::array<double, 6> gt{};
    const bool hasGt = GDALGetGeoTransform(ds, gt.data()) == CE_None;
    if (w == width && h == height && bands == bandCount && hasGt == geoTransform.has_value() && (!hasGt || gt == *geoTransform))
        return "";
    std::ostringstream o;
    o << "changed on disk since it was opened (" << width << " x " << height << " pixels, " << bandCount << " bands then; "
      << w << " x " << h << ", " << bands << " now" << (w == width && h == height && bands == bandCount ? ", moved" : "")
      << "): open the scene again to read the new file";
    return o.str();
}

Result<std::unique_ptr<Handle>> RasterSource::Impl::openHandle(GDALDatasetH alreadyOpen) const {
    GDALDatasetH ds = alreadyOpen;
    if (!ds) {
        // Another handle for another thread: the file may have been replaced since it was opened
        // (tools write a new file and rename it over the old); its reads must match the first.
        GdalErrors errors;
        ds = GDALOpenEx(openPath.c_str(), GDAL_OF_RASTER | GDAL_OF_VERBOSE_ERROR, nullptr, nullptr, nullptr);
        if (!ds) return error("cannot open again: " + errors.text());
        if (const std::string why = changedSinceOpened(ds); !why.empty()) {
            GDALClose(ds);
            return error(why);
        }
    }
    auto h = std::make_unique<Handle>();
    h->levels.resize(1 + overviews.size());
    h->levels[0].ds = ds;
    if (auto ok = makeTransformer(h->levels[0]); !ok) return ok.error();
    return h;
}

Result<bool> RasterSource::Impl::ensureLevel(Handle& h, int level) const {
    Level& lv = h.levels[size_t(level)];
    if (lv.approx) return true;
    if (!lv.ds) {
        GdalErrors errors;
        const std::string ovr = "OVERVIEW_LEVEL=" + std::to_string(level - 1);
        const char* openOptions[] = {ovr.c_str(), nullptr};
        lv.ds = GDALOpenEx(openPath.c_str(), GDAL_OF_RASTER | GDAL_OF_VERBOSE_ERROR, nullptr, openOptions, nullptr);
        if (!lv.ds) return error("cannot open overview " + std::to_string(level) + ": " + errors.text());
        const auto [w, hgt] = overviews[size_t(level - 1)];
        if (GDALGetRasterXSize(lv.ds) != w || GDALGetRasterYSize(lv.ds) != hgt) {
            GDALClose(lv.ds);
            lv.ds = nullptr;
            return error("overview " + std::to_string(level) + " opened with another size: the file changed on disk since "
                         "it was opened; open the scene again to read the new file");
        }
    }
    return makeTransformer(lv);
}

Result<std::unique_ptr<Handle>> RasterSource::Impl::checkout(const jobs::CancelToken* cancel) const {
    std::unique_lock lock(poolMutex);
    for (;;) {
        if (!idle.empty()) {
            auto h = std::move(idle.back());
            idle.pop_back();
            return h;
        }
        if (opened < maxHandles) {
            ++opened;
            lock.unlock();
            auto h = openHandle();
            if (!h) {
                lock.lock();
                --opened;
                poolCv.notify_one();
            }
            return h;
        }
        // Wake now and then to notice a cancellation while every handle is busy.
        poolCv.wait_for(lock, std::chrono::milliseconds(20));
        if (isCancelled(cancel)) return error("cancelled");
    }
}

void RasterSource::Impl::giveBack(std::unique_ptr<Handle> h) const {
    h->cancel = nullptr;
    {
        std::lock_guard lock(poolMutex);
        idle.push_back(std::move(h));
    }
    poolCv.notify_one();
}

// ---------------------------------------------------------------------------------------------
// Reading

/// The coarsest overview (0 = none) whose pixels are no larger than the tile's, measured in
/// full-resolution source pixels per tile pixel.
int RasterSource::Impl::overviewFor(double srcPixelsPerTilePixel) const {
    int best = 0;
    double bestFactor = 1.0;
    for (size_t i = 0; i < overviews.size(); ++i) {
        const double f = std::min(double(width) / overviews[i].first, double(height) / overviews[i].second);
        if (f <= srcPixelsPerTilePixel * 1.001 && f > bestFactor) {
            best = int(i) + 1;
            bestFactor = f;
        }
    }
    return best;
}

/// Source pixels a tile of `level` near the data would read, for minLevel().
uint64_t RasterSource::Impl::sourcePixelsAt(uint32_t level, int tileSize) const {
    const double tileDeg = 180.0 / double(1u << level);
    const double wx = tileDeg * width / coverage.width(), wy = tileDeg * height / coverage.height();
    const int ovr = overviewFor(std::min(wx, wy) / tileSize);
    const double fx = ovr ? double(width) / overviews[size_t(ovr - 1)].first : 1.0;
    const double fy = ovr ? double(height) / overviews[size_t(ovr - 1)].second : 1.0;
    const double px = (std::min(wx, double(width)) / fx + 2.0) * (std::min(wy, double(height)) / fy + 2.0);
    return px > 1e18 ? uint64_t(1e18) : uint64_t(px);
}

Result<WarpOp*> RasterSource::Impl::warpOp(Handle& h, Level& level, int size) const {
    // A warp operation is NOT reused from tile to tile: Initialize() captures state derived from
    // the destination geotransform (special points, and the per-thread clones of the
    // transformer that the warp kernel uses), so reusing one after changing the geotransform
    // reads the previous tile's source area: results then depend on which tile a handle read
    // before (seen as nondeterministic imagery). The transformer itself is reused.
    level.ops.clear();
    GdalErrors errors;
    const int nb = int(bands.size());
    WarpOp w;
    w.size = size;
    GDALWarpOptions* wo = GDALCreateWarpOptions();
    wo->hSrcDS = level.ds;
    wo->eResampleAlg = resample;
    wo->eWorkingDataType = workType;
    wo->nBandCount = nb;
    wo->panSrcBands = static_cast<int*>(CPLMalloc(sizeof(int) * size_t(nb)));
    wo->panDstBands = static_cast<int*>(CPLMalloc(sizeof(int) * size_t(nb)));
    for (int i = 0; i < nb; ++i) {
        wo->panSrcBands[i] = bands[size_t(i)];
        wo->panDstBands[i] = i + 1;
    }
    if (!noData.empty()) {
        wo->padfSrcNoDataReal = static_cast<double*>(CPLMalloc(sizeof(double) * size_t(nb)));
        for (int i = 0; i < nb; ++i) wo->padfSrcNoDataReal[i] = noData[size_t(i)];
    }
    wo->nSrcAlphaBand = srcAlpha;
    if (role == RasterRole::Elevation) {
        wo->padfDstNoDataReal = static_cast<double*>(CPLMalloc(sizeof(double)));
        wo->padfDstNoDataReal[0] = std::numeric_limits<double>::quiet_NaN();
    } else {
        // The warper writes its destination density (coverage) only to a dataset's alpha band.
        w.alphaDst = GDALCreate(GDALGetDriverByName("MEM"), "", size, size, nb + 1, GDT_Byte, nullptr);
        wo->hDstDS = w.alphaDst;
        wo->nDstAlphaBand = nb + 1;
    }
    wo->pfnTransformer = GDALApproxTransform;
    wo->pTransformerArg = level.approx;
    wo->pfnProgress = warpProgress;
    wo->pProgressArg = &h;
    w.op = std::make_unique<GDALWarpOperation>();
    const CPLErr e = (role == RasterRole::Imagery && !w.alphaDst) ? CE_Failure : w.op->Initialize(wo);
    GDALDestroyWarpOptions(wo);
    if (e != CE_None) return error("cannot set up the warp: " + errors.text());
    if (level.ops.size() >= size_t(kMaxWarpOpsPerLevel)) level.ops.erase(level.ops.begin());
    level.ops.push_back(std::move(w));
    return &level.ops.back();
}

std::optional<raster_detail::PixelBox> RasterSource::Impl::tileInSource(Handle& h, const double gt[6], int size) const {
    GDALSetGenImgProjTransformerDstGeoTransform(h.levels[0].genImg, gt);
    constexpr int kGrid = 9;
    std::array<double, kGrid * kGrid> xs, ys, zs;
    std::array<int, kGrid * kGrid> ok;
    for (int j = 0; j < kGrid; ++j)
        for (int i = 0; i < kGrid; ++i) {
            xs[size_t(j * kGrid + i)] = double(size) * i / (kGrid - 1);
            ys[size_t(j * kGrid + i)] = double(size) * j / (kGrid - 1);
            zs[size_t(j * kGrid + i)] = 0.0;
        }
    {
        GdalErrors quiet;  // points outside the projection's domain fail: expected
        GDALGenImgProjTransform(h.levels[0].genImg, TRUE, kGrid * kGrid, xs.data(), ys.data(), zs.data(), ok.data());
    }
    raster_detail::PixelBox box{1e300, 1e300, -1e300, -1e300};
    for (size_t k = 0; k < xs.size(); ++k) {
        if (!ok[k] || !std::isfinite(xs[k]) || !std::isfinite(ys[k])) continue;
        box.x0 = std::min(box.x0, xs[k]), box.x1 = std::max(box.x1, xs[k]);
        box.y0 = std::min(box.y0, ys[k]), box.y1 = std::max(box.y1, ys[k]);
    }
    if (box.x0 > box.x1) return std::nullopt;
    return box;
}

bool RasterSource::Impl::overTileBudget(const raster_detail::PixelBox& clipped, int level, const GeoExtent& extent) const {
    const double fx = level ? double(width) / overviews[size_t(level - 1)].first : 1.0;
    const double fy = level ? double(height) / overviews[size_t(level - 1)].second : 1.0;
    const double pixels = ((clipped.x1 - clipped.x0) / fx + 2.0) * ((clipped.y1 - clipped.y0) / fy + 2.0);
    if (pixels <= double(RasterSource::kMaxSourcePixelsPerTile)) return false;
    log::trace(name, ": ", fmtExtent(extent), " would read ", uint64_t(pixels), " source pixels: left empty");
    return true;
}

Result<bool> RasterSource::Impl::warpLevel(Handle& h, int level, const double gt[6], int size, const GeoExtent& extent,
                                           const jobs::CancelToken* cancel, void* bandsOut, uint8_t* alphaOut) const {
    if (auto r = ensureLevel(h, level); !r) return r.error();
    Level& lv = h.levels[size_t(level)];
    GDALSetGenImgProjTransformerDstGeoTransform(lv.genImg, gt);
    auto op = warpOp(h, lv, size);
    if (!op) return op.error();
    const int nb = int(bands.size());
    GDALRasterBandH alphaBand = alphaOut ? GDALGetRasterBand((*op)->alphaDst, nb + 1) : nullptr;
    GdalErrors errors;
    if (alphaBand) {
        std::memset(alphaOut, 0, size_t(size) * size_t(size));
        if (GDALRasterIO(alphaBand, GF_Write, 0, 0, size, size, alphaOut, size, size, GDT_Byte, 0, 0) != CE_None)
            return error("cannot reset the alpha buffer: " + errors.text());
    }
    if (isCancelled(cancel)) return error("cancelled");
    const CPLErr e = (*op)->op->WarpRegionToBuffer(0, 0, size, size, bandsOut, workType);
    if (isCancelled(cancel)) return error("cancelled");
    if (e != CE_None) return error("reading " + fmtExtent(extent) + ": " + errors.text());
    if (alphaBand &&
        GDALRasterIO(alphaBand, GF_Read, 0, 0, size, size, alphaOut, size, size, GDT_Byte, 0, 0) != CE_None)
        return error("cannot read the alpha buffer: " + errors.text());
    return true;
}

/// Warps the source into planar `bandsOut` (bands.size() planes of workType, pre-filled by the
/// caller) and, for imagery, the coverage into `alphaOut`. False: nothing to read (outside the
/// coverage or over the per-tile budget), outputs untouched.
Result<bool> RasterSource::Impl::warp(const GeoExtent& extent, int size, bool cornerAligned,
                                      const jobs::CancelToken* cancel, void* bandsOut, uint8_t* alphaOut) const {
    if (isCancelled(cancel)) return error("cancelled");
    if (!coverage.intersects(extent)) return false;
    const ScopedHttpAuth auth(options.httpAuth);   // this source's credentials, on this thread only
    // Handles opened for this read (a WMTS builds its tile readers then) cache in `cacheDir`.
    const ScopedThreadOption cache("GDAL_DEFAULT_WMS_CACHE_PATH", cachePath.empty() ? nullptr : cachePath.c_str());
    GdalErrors unexpected;  // nothing GDAL says during a read reaches stderr
    auto leased = checkout(cancel);
    if (!leased) return leased.error();
    struct Lease {
        const Impl* impl;
        std::unique_ptr<Handle> h;
        ~Lease() { impl->giveBack(std::move(h)); }
    } lease{this, std::move(leased.value())};
    Handle& h = *lease.h;
    h.cancel = cancel;

    const int steps = cornerAligned ? size - 1 : size;
    const double dx = extent.width() / steps, dy = extent.height() / steps;
    const double half = cornerAligned ? 0.5 : 0.0;
    const double gt[6] = {extent.west - half * dx, dx, 0.0, extent.north + half * dy, 0.0, -dy};

    const auto box = tileInSource(h, gt, size);
    if (!box) return false;
    const raster_detail::PixelBox clipped{std::max(0.0, box->x0), std::max(0.0, box->y0), std::min(double(width), box->x1),
                                          std::min(double(height), box->y1)};
    if (clipped.x1 <= clipped.x0 || clipped.y1 <= clipped.y0) return false;
    const int level = overviewFor(std::min(box->x1 - box->x0, box->y1 - box->y0) / size);
    if (overTileBudget(clipped, level, extent)) return false;
    return warpLevel(h, level, gt, size, extent, cancel, bandsOut, alphaOut);
}

// ---------------------------------------------------------------------------------------------
// Opening: what the file is, and how it will be read

namespace {

/// A geotransform that can only be lon/lat degrees (used when a file has no CRS).
bool looksLonLat(const double gt[6], int w, int h) {
    const bool identity = gt[0] == 0.0 && gt[1] == 1.0 && gt[2] == 0.0 && gt[3] == 0.0 && gt[4] == 0.0 &&
                          std::fabs(gt[5]) == 1.0;
    if (identity) return false;
    for (const auto& [px, py] : {std::pair{0, 0}, {w, 0}, {0, h}, {w, h}}) {
        const double lon = gt[0] + px * gt[1] + py * gt[2], lat = gt[3] + px * gt[4] + py * gt[5];
        if (!(lon >= -180.5 && lon <= 360.5 && lat >= -90.5 && lat <= 90.5)) return false;
    }
    return true;
}

}  // namespace

Result<bool> RasterSource::Impl::inspect(GDALDatasetH ds) {
    driver = GDALGetDriverShortName(GDALGetDatasetDriver(ds));
    width = GDALGetRasterXSize(ds);
    height = GDALGetRasterYSize(ds);
    bandCount = GDALGetRasterCount(ds);
    if (width <= 0 || height <= 0)
        return error("has zero size (" + std::to_string(width) + " x " + std::to_string(height) + " pixels)");
    if (bandCount == 0) {
        CSLConstList sub = GDALGetMetadata(ds, "SUBDATASETS");
        if (const char* first = CSLFetchNameValue(sub, "SUBDATASET_1_NAME"))
            return error("has no raster bands of its own but " + std::to_string(CSLCount(sub) / 2) +
                         " subdatasets; open one of them, e.g. " + first);
        return error("has no raster bands");
    }
    for (int b = 1; b <= bandCount; ++b) {
        GDALRasterBandH band = GDALGetRasterBand(ds, b);
        BandInfo info;
        info.type = typeName(GDALGetRasterDataType(band));
        info.interp = GDALGetColorInterpretationName(GDALGetRasterColorInterpretation(band));
        int has = 0;
        const double nd = GDALGetRasterNoDataValue(band, &has);
        if (has) info.noData = nd;
        info.scale = GDALGetRasterScale(band, nullptr);
        info.offset = GDALGetRasterOffset(band, nullptr);
        bandInfo.push_back(info);
    }

    OGRSpatialReferenceH srs = GDALGetSpatialRef(ds);
    const bool gcps = GDALGetGCPCount(ds) > 0;
    if (!srs && gcps) srs = GDALGetGCPSpatialRef(ds);
    double gt[6];
    const bool hasGt = GDALGetGeoTransform(ds, gt) == CE_None;
    if (hasGt) geoTransform.emplace(std::to_array(gt));
    if (!srs) {
        if (!hasGt || !looksLonLat(gt, width, height))
            return error("has no coordinate reference system; assign one (gdal_edit.py -a_srs EPSG:<code> " + name +
                         ", or a .prj/.aux.xml next to it)");
        assumedLonLat = true;
        crsName = "WGS 84 (assumed: the file has no CRS)";
        crsEpsg = "4326";
        log::warn(name, ": has no coordinate reference system; its geotransform looks like lon/lat degrees, so it "
                  "is read as EPSG:4326 (WGS 84). If that is wrong, assign its CRS with gdal_edit.py -a_srs.");
    } else {
        crsName = OSRGetName(srs) ? OSRGetName(srs) : "unnamed";
        const char* auth = OSRGetAuthorityName(srs, nullptr);
        const char* code = OSRGetAuthorityCode(srs, nullptr);
        if (auth && code && EQUAL(auth, "EPSG")) crsEpsg = code;
    }
    if (!hasGt && !gcps) return error("has no georeferencing (no geotransform and no ground control points)");
    return true;
}

namespace {

GDALColorInterp interpretationOf(GDALDatasetH ds, int band) {
    return GDALGetRasterColorInterpretation(GDALGetRasterBand(ds, band));
}

}  // namespace

Result<bool> RasterSource::Impl::chooseBands(GDALDatasetH ds) {
    for (int b : options.bands)
        if (b < 1 || b > bandCount)
            return error("band " + std::to_string(b) + " out of range: the file has " + std::to_string(bandCount) +
                         (bandCount == 1 ? " band" : " bands"));
    if (role == RasterRole::Elevation) {
        if (options.bands.size() > 1) return error("an elevation source reads exactly one band");
        bands = {options.bands.empty() ? 1 : options.bands[0]};
        return true;
    }
    if (options.bands.empty()) {
        bands = bandCount >= 3 ? std::vector<int>{1, 2, 3} : std::vector<int>{1};
    } else {
        const size_t n = options.bands.size();
        if (n != 1 && n != 2 && n != 3 && n != 4)
            return error("imagery reads 1 (grey), 2 (grey, alpha), 3 (RGB) or 4 (RGBA) bands, not " +
                         std::to_string(n));
        bands.assign(options.bands.begin(), options.bands.begin() + (n == 2 || n == 4 ? long(n) - 1 : long(n)));
        if (n == 2 || n == 4) srcAlpha = options.bands.back();
    }
    // Without an alpha band named, the file's own (one it does not read as colour).
    for (int b = 1; b <= bandCount && !srcAlpha; ++b)
        if (interpretationOf(ds, b) == GCI_AlphaBand && std::find(bands.begin(), bands.end(), b) == bands.end()) srcAlpha = b;
    return true;
}

Result<bool> RasterSource::Impl::chooseWorkType(GDALDatasetH ds) {
    workType = role == RasterRole::Elevation ? GDT_Float32 : GDT_Byte;
    for (int b : bands) {
        GDALRasterBandH band = GDALGetRasterBand(ds, b);
        const GDALDataType t = GDALGetRasterDataType(band);
        if (GDALDataTypeIsComplex(t))
            return error("band " + std::to_string(b) + " has complex values (" + typeName(t) + "): not supported");
        if (t != GDT_Byte) workType = GDT_Float32;
    }
    return true;
}

void RasterSource::Impl::readPalette(GDALDatasetH ds) {
    GDALRasterBandH first = GDALGetRasterBand(ds, bands[0]);
    if (role == RasterRole::Imagery && bands.size() == 1 && interpretationOf(ds, bands[0]) == GCI_PaletteIndex &&
        GDALGetRasterColorTable(first) && workType == GDT_Byte) {
        palette = true;
        GDALColorTableH table = GDALGetRasterColorTable(first);
        const int n = std::min(256, GDALGetColorEntryCount(table));
        for (int i = 0; i < n; ++i) {
            GDALColorEntry c;
            if (!GDALGetColorEntryAsRGB(table, i, &c)) continue;
            paletteRgba[size_t(i)] = {uint8_t(c.c1), uint8_t(c.c2), uint8_t(c.c3), uint8_t(c.c4)};
        }
    }
}

Result<bool> RasterSource::Impl::chooseResampling() {
    std::string alg = options.resampling;
    if (alg.empty()) alg = role == RasterRole::Elevation ? "bilinear" : "cubic";
    if (palette) alg = "near";  // interpolated colour indices are meaningless
    bool known = false;
    resample = resampleAlg(alg, &known);
    if (!known) return error("unknown resampling \"" + alg + "\" (near, bilinear, cubic, lanczos, average, ...)");
    return true;
}

void RasterSource::Impl::readNoData(GDALDatasetH ds) {
    bool anyNoData = options.noData.has_value();
    for (int b : bands) {
        int has = 0;
        const double v = GDALGetRasterNoDataValue(GDALGetRasterBand(ds, b), &has);
        noData.push_back(options.noData ? *options.noData : has ? v : std::numeric_limits<double>::quiet_NaN());
        anyNoData = anyNoData || has;
    }
    if (!anyNoData) noData.clear();
}

Result<bool> RasterSource::Impl::readValueScaling(GDALDatasetH ds) {
    if (role == RasterRole::Elevation) {
        GDALRasterBandH first = GDALGetRasterBand(ds, bands[0]);
        int hasScale = 0, hasOffset = 0;
        const double scale = GDALGetRasterScale(first, &hasScale), offset = GDALGetRasterOffset(first, &hasOffset);
        if (hasScale && scale != 0.0) valueScale = scale;
        if (hasOffset) valueOffset = offset;
        return true;
    }
    if (workType == GDT_Byte) return true;
    for (int b : bands) {
        std::pair<double, double> range;
        if (options.scaleRange) {
            range = *options.scaleRange;
        } else {
            GDALRasterBandH band = GDALGetRasterBand(ds, b);
            int hasMin = 0, hasMax = 0;
            range = {GDALGetRasterMinimum(band, &hasMin), GDALGetRasterMaximum(band, &hasMax)};
            if (!hasMin || !hasMax) {
                double mm[2] = {0.0, 255.0};
                GdalErrors errors;
                if (GDALComputeRasterMinMax(band, TRUE, mm) != CE_None)
                    return error("cannot compute the value range of band " + std::to_string(b) + ": " +
                                 errors.text() + " (give scaleRange)");
                range = {mm[0], mm[1]};
            }
        }
        valueRange.push_back(range);
    }
    return true;
}

Result<bool> RasterSource::Impl::planBands(GDALDatasetH ds) {
    if (auto r = chooseBands(ds); !r) return r;
    if (auto r = chooseWorkType(ds); !r) return r;
    readPalette(ds);
    if (auto r = chooseResampling(); !r) return r;
    readNoData(ds);
    if (auto r = readValueScaling(ds); !r) return r;
    GDALRasterBandH first = GDALGetRasterBand(ds, bands[0]);
    for (int i = 0, n = GDALGetOverviewCount(first); i < n; ++i) {
        GDALRasterBandH o = GDALGetOverview(first, i);
        if (o) overviews.emplace_back(GDALGetRasterBandXSize(o), GDALGetRasterBandYSize(o));
    }
    return true;
}

Result<bool> RasterSource::Impl::computeCoverage(Level& full) {
    double w = 0, s = 0, e = 0, n = 0;
    bool done = false;
    double gt[6];
    if (GDALGetGCPCount(full.ds) == 0 && GDALGetGeoTransform(full.ds, gt) == CE_None) {
        double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
        for (const auto& [px, py] : {std::pair{0, 0}, {width, 0}, {0, height}, {width, height}}) {
            const double x = gt[0] + px * gt[1] + py * gt[2], y = gt[3] + px * gt[4] + py * gt[5];
            x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
        }
        OGRSpatialReferenceH wgs84 = OSRNewSpatialReference(nullptr);
        OSRImportFromEPSG(wgs84, 4326);
        OSRSetAxisMappingStrategy(wgs84, OAMS_TRADITIONAL_GIS_ORDER);
        OGRSpatialReferenceH src = assumedLonLat ? OSRClone(wgs84) : OSRClone(GDALGetSpatialRef(full.ds));
        OSRSetAxisMappingStrategy(src, OAMS_TRADITIONAL_GIS_ORDER);
        GdalErrors quiet;
        if (OGRCoordinateTransformationH ct = OCTNewCoordinateTransformation(src, wgs84)) {
            done = OCTTransformBounds(ct, x0, y0, x1, y1, &w, &s, &e, &n, 21) != 0;
            OCTDestroyCoordinateTransformation(ct);
        }
        OSRRelease(src);
        OSRRelease(wgs84);
    }
    // The transformer's own view of pixels -> lon/lat: GCPs, and a fallback for the rest.
    const double identity[6] = {0, 1, 0, 0, 0, 1};
    GDALSetGenImgProjTransformerDstGeoTransform(full.genImg, identity);
    if (!done) {
        constexpr int kN = 21;
        std::vector<double> xs, ys, zs(kN * kN, 0.0);
        std::vector<int> ok(kN * kN);
        for (int j = 0; j < kN; ++j)
            for (int i = 0; i < kN; ++i) xs.push_back(double(width) * i / (kN - 1)), ys.push_back(double(height) * j / (kN - 1));
        GdalErrors quiet;
        GDALGenImgProjTransform(full.genImg, FALSE, kN * kN, xs.data(), ys.data(), zs.data(), ok.data());
        w = s = 1e300, e = n = -1e300;
        for (size_t k = 0; k < xs.size(); ++k) {
            if (!ok[k] || !std::isfinite(xs[k]) || !std::isfinite(ys[k])) continue;
            w = std::min(w, xs[k]), e = std::max(e, xs[k]), s = std::min(s, ys[k]), n = std::max(n, ys[k]);
            done = true;
        }
    }
    if (!done || !std::isfinite(w) || !std::isfinite(e) || !std::isfinite(s) || !std::isfinite(n))
        return error("its extent cannot be converted to lon/lat");
    if (w > e) w = -180.0, e = 180.0;  // crosses the antimeridian
    if (e > 180.0 + 1e-9 && w >= -1e-9 && (assumedLonLat || crsEpsg == "4326"))
        log::warn(name, ": longitudes run from ", w, " to ", e, "; only the part west of 180 is shown");
    coverage = GeoExtent{std::max(-180.0, w), std::max(-90.0, s), std::min(180.0, e), std::min(90.0, n)};
    if (!coverage.valid()) return error("lies outside the globe (lon/lat extent " + fmtExtent({w, s, e, n}) + ")");

    // Native resolution at the centre: one pixel step along x and along y, in degrees.
    double xs[3] = {width / 2.0, width / 2.0 + 1.0, width / 2.0}, ys[3] = {height / 2.0, height / 2.0, height / 2.0 + 1.0};
    double zs[3] = {0, 0, 0};
    int ok[3] = {0, 0, 0};
    GdalErrors quiet;
    GDALGenImgProjTransform(full.genImg, FALSE, 3, xs, ys, zs, ok);
    const double resLon = std::hypot(xs[1] - xs[0], xs[2] - xs[0]), resLat = std::hypot(ys[1] - ys[0], ys[2] - ys[0]);
    resolutionDeg = std::min(resLon, resLat);
    if (!ok[0] || !ok[1] || !ok[2] || !std::isfinite(resolutionDeg) || resolutionDeg <= 0.0 || resLon > 180.0)
        resolutionDeg = std::min(coverage.width() / width, coverage.height() / height);
    return true;
}

void RasterSource::Impl::computeLevels() {
    const int tileSize = role == RasterRole::Elevation ? 65 : 256;
    minLevel = TileKey::kMaxLevel;
    for (uint32_t level = 0; level <= TileKey::kMaxLevel; ++level)
        if (sourcePixelsAt(level, tileSize) <= RasterSource::kMaxSourcePixelsPerTile) {
            minLevel = level;
            break;
        }
    if (minLevel > 0)
        log::warn(name, ": ", width, " x ", height, " pixels", overviews.empty() ? " and no overviews" : " and too few overviews",
                  ": a tile coarser than level ", minLevel, " would read more than ",
                  RasterSource::kMaxSourcePixelsPerTile >> 20, " Mi source pixels, so it is shown from level ", minLevel,
                  " on. Add overviews (gdaladdo -r average ", name, ") to see it from level 0.");
}

/// Reads a pixel in the middle and the last pixel: a truncated or corrupt file fails here, at
/// open, rather than tile by tile.
Result<bool> RasterSource::Impl::probe(GDALDatasetH ds) const {
    std::vector<int> map = bands;
    std::vector<double> buf(map.size());
    for (const auto& [x, y] : {std::pair{width / 2, height / 2}, {width - 1, height - 1}}) {
        GdalErrors errors;
        if (GDALDatasetRasterIO(ds, GF_Read, x, y, 1, 1, buf.data(), 1, 1, GDT_Float64, int(map.size()), map.data(), 0,
                                0, 0) != CE_None)
            return error("cannot be read (truncated or corrupt?): " + errors.text());
    }
    return true;
}

}  // namespace orbis::globe
