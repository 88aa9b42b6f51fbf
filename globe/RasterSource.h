#pragma once
// RasterSource: the TileSource over GDAL. Reads any raster GDAL opens (GeoTIFF, DTED, VRT, JP2,
// netCDF, WMS/TMS XML, /vsicurl/...) or an XYZ tile URL, and warps it with GDAL's warper to the
// lon/lat extent of one geodetic tile (EPSG:4326, longitude first). No Vulkan, and no GDAL
// headers here: users of this file do not include gdal.h.
//
//   auto dem = RasterSource::open({.path = "dem.tif", .role = RasterRole::Elevation});
//   if (!dem) return dem.error();
//   Result<ElevationTile> t = (*dem)->readElevation(key.extent(), 65, &cancel);   // any thread
//
// GDAL is configured on the first open() (GdalSetup.h: HTTP timeouts and retries, the tile
// cache, the block cache): a scene without rasters never initialises it. A tile that still
// fails is tried again by the pager later (TerrainTiles: kTileRetries, with back-off).
//
// Cost bound: one tile never reads more than kMaxSourcePixelsPerTile source pixels (counting the
// overview GDAL reads from). Tiles that would need more (a huge file without overviews seen from
// far away) come back empty at once (anyValid = false): see minLevel().

#include "base/Result.h"
#include "globe/GdalSetup.h"
#include "globe/TileImageSource.h"
#include "globe/TileKey.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace orbis::jobs {
class CancelToken;
}

namespace orbis::globe {

enum class RasterRole { Elevation, Imagery };

struct RasterSourceOptions {
    /// Anything GDALOpenEx accepts: a file, a VRT, /vsicurl/..., a WMS/TMS XML file or string.
    std::string path;
    /// Alternative to `path`: an XYZ tile URL ("http://host/{z}/{x}/{y}.png", web mercator, y
    /// down), read through GDAL's WMS driver (TMS minidriver) and its disk cache. Imagery only.
    std::string xyzUrl;
    /// Deepest zoom level the XYZ server has (GDAL requests no finer tiles).
    int xyzMaxZoom = 18;
    RasterRole role = RasterRole::Imagery;
    /// 1-based band numbers. Imagery: {} = 1,2,3 (or 1 for a single-band file, shown grey or
    /// through its colour table); a 4th entry, or a band whose colour interpretation is alpha,
    /// is used as alpha. Elevation: {} = 1; exactly one band.
    std::vector<int> bands;
    /// Imagery: source values mapped linearly to 0..255. Default: Byte data as is; other types
    /// from each band's minimum/maximum (file metadata, else approximate statistics).
    std::optional<std::pair<double, double>> scaleRange;
    /// Overrides the nodata value of every read band.
    std::optional<double> noData;
    /// GDAL resampling name. Default: "bilinear" for elevation (no overshoot at cliffs),
    /// "cubic" for imagery (sharp when magnified; GDAL picks overviews when minified);
    /// colour-table images always use "near".
    std::string resampling;
    /// When >= 0, maxLevel() returns this instead of the level derived from the resolution.
    int maxLevelOverride = -1;
    /// Disk cache for WMS/XYZ tiles. Empty: defaultRasterCacheDir().
    std::string cacheDir;
    /// HTTP credentials for a remote source, from the environment variables it names (sent by
    /// every request of this source only; never in a message).
    HttpAuth httpAuth;
    /// Georeferences a picture that has none (a plate carrée image such as NASA's Blue Marble
    /// as a JPEG): its outer corners in WGS 84 lon/lat degrees. The file's own georeferencing,
    /// if any, is then ignored. Not for XYZ sources.
    std::optional<GeoExtent> bounds;
};

/// Heights on a CORNER-ALIGNED grid: sample (i, j) lies at lon = west + i * width / (size - 1),
/// lat = north - j * height / (size - 1); row 0 is north. Metres (band scale/offset applied);
/// NaN where there is no data (nodata, outside the coverage).
struct ElevationTile {
    int size = 0;
    std::vector<float> heights;  ///< size * size
    float minHeight = 0.0f;      ///< over valid samples; 0 when none
    float maxHeight = 0.0f;
    bool anyValid = false;
};

/// Imagery sources are the terrain's tile images (readTile is readImagery); elevation sources
/// are read with readElevation.
class RasterSource : public TileImageSource {
public:
    /// Most source pixels (width x height of the window read, at the overview used) one tile may
    /// read: 16 Mi. Bounds the memory (<= 4 bytes x bands per pixel) and time of a read.
    static constexpr uint64_t kMaxSourcePixelsPerTile = uint64_t(16) << 20;

    /// Opens and validates the raster (CRS, bands, a probe read of local files). Errors name
    /// the file and what is wrong. Logs one warning when the file is too big to be shown from
    /// level 0 (see minLevel()). Any thread.
    static Result<std::shared_ptr<RasterSource>> open(const RasterSourceOptions& options);

    ~RasterSource() override;
    RasterSource(const RasterSource&) = delete;
    RasterSource& operator=(const RasterSource&) = delete;

    // Properties: fixed at open, any thread.
    const std::string& name() const override;  ///< the path or URL, for messages
    RasterRole role() const;
    /// Geodetic bounds of the data (lon/lat degrees), clamped to the globe; the full longitude
    /// range for data that crosses the antimeridian.
    GeoExtent coverage() const;
    /// Native pixel size in degrees at the data's centre (the finer of its lon and lat sizes).
    double resolutionDeg() const;
    /// Finest level whose tiles of `tileSize` samples still add detail: the first level whose
    /// tile pixels are no larger than the native pixels (or options.maxLevelOverride).
    uint32_t maxLevel(int tileSize) const override;
    /// Coarsest level whose tiles (of 65 samples for elevation, 256 for imagery) stay within
    /// kMaxSourcePixelsPerTile, given the overviews present; 0 normally.
    uint32_t minLevel() const override;
    bool covers(const GeoExtent& extent) const override;

    /// Thread-safe: calls from several threads run in parallel on a bounded pool of GDAL
    /// handles (one per concurrent call, at most maxHandles()); a call waits for a free handle.
    /// `cancel` is checked between steps and during the warp: a cancelled call returns the
    /// Error "<name>: cancelled". Empty tiles (anyValid = false) for extents outside the
    /// coverage or over the per-tile budget. `size` must be 2..4096.
    Result<ElevationTile> readElevation(const GeoExtent& extent, int size,
                                        const jobs::CancelToken* cancel = nullptr) const;
    /// As readElevation; `size` must be 1..4096. Imagery sources only.
    Result<ImageryTile> readImagery(const GeoExtent& extent, int size,
                                    const jobs::CancelToken* cancel = nullptr) const;
    Result<ImageryTile> readTile(const TileImageRequest& request, const jobs::CancelToken* cancel) const override {
        return readImagery(request.extent, request.size, cancel);
    }

    /// Multi-line human description: driver, size, bands and types, CRS name and EPSG code,
    /// nodata, coverage, resolution, overviews, levels. Any thread.
    std::string describe() const;

    /// Most GDAL handles this source keeps open at once.
    int maxHandles() const;
    /// GDAL handles opened so far (<= maxHandles()). Any thread.
    int openHandles() const;

private:
    struct Impl;
    explicit RasterSource(std::unique_ptr<Impl> impl);
    std::unique_ptr<Impl> impl_;
};

/// A JSON object (as text) describing any raster GDAL opens, for `orbis info FILE`:
/// {"file", "driver", "width", "height", "bands": [{"band", "type", "colorInterp", "noData"?,
/// "scale", "offset", "overviews": [[w, h], ...]}], "crs": {"name", "epsg"?} or null,
/// "geoTransform"?, "coverage"? {"west","south","east","north"}, "resolutionDeg"?,
/// "maxLevel65"?, "maxLevel256"?, "minLevel"?, "warning"?}. The level fields are present when
/// the file opens as a RasterSource; otherwise "warning" says why. Errors (missing file, not a
/// raster) name the file. Any thread.
Result<std::string> describeRasterJson(const std::string& path);

/// Whether the source is read from a server (WMS, WMTS, XYZ, http, /vsicurl/ and the other
/// network file systems): its tiles go through the disk cache. Any thread.
bool isRemoteSource(const RasterSourceOptions& options);

/// Where WMS/XYZ tiles are cached by default: $ORBIS_CACHE_DIR/gdal, else
/// $XDG_CACHE_HOME/orbis/gdal, else $HOME/.cache/orbis/gdal, else <temp>/orbis-gdal-cache.
std::string defaultRasterCacheDir();

}  // namespace orbis::globe
