#include "globe/GdalSetup.h"

#include "globe/RasterSource.h"
#include "globe/TileCacheFs.h"

#include <cpl_conv.h>
#include <gdal.h>

#include <mutex>
#include <string>

namespace orbis::globe {

namespace {

// GDAL's block cache (decoded source blocks), unless GDAL_CACHEMAX says otherwise. Finished
// tiles live in the pager's own LRU cache, so this only serves neighbouring tiles that read the
// same blocks: 64 MB reads as fast as 256 MB (bench --tiles) and keeps the process's memory
// close to the layer budgets.
constexpr GIntBig kGdalBlockCacheBytes = GIntBig(64) << 20;

void setConfigDefault(const char* key, const std::string& value) {
    if (CPLGetConfigOption(key, nullptr) == nullptr) CPLSetConfigOption(key, value.c_str());
}

}  // namespace

void configureGdal() {
    static std::once_flag once;
    std::call_once(once, [] {
        const bool userCache = CPLGetConfigOption("GDAL_CACHEMAX", nullptr) != nullptr;
        setConfigDefault("GDAL_HTTP_TIMEOUT", "30");
        setConfigDefault("GDAL_HTTP_CONNECTTIMEOUT", "10");
        // A busy server (429, 502, 503, 504) is asked again twice, after 1 s then about 2 s.
        setConfigDefault("GDAL_HTTP_MAX_RETRY", "2");
        setConfigDefault("GDAL_HTTP_RETRY_DELAY", "1");
        // A WMS description with an empty <Cache/> caches here, through Orbis's safe tile cache.
        setConfigDefault("GDAL_DEFAULT_WMS_CACHE_PATH", tileCachePath(defaultRasterCacheDir()));
        // WFS: GetFeature in pages (STARTINDEX/COUNT) of 1000 features, so that a server that
        // caps its answers still gives every feature, and none is asked for all at once.
        setConfigDefault("OGR_WFS_PAGING_ALLOWED", "ON");
        setConfigDefault("OGR_WFS_PAGE_SIZE", "1000");
        GDALAllRegister();
        if (!userCache) GDALSetCacheMax64(kGdalBlockCacheBytes);
    });
}

}  // namespace orbis::globe
