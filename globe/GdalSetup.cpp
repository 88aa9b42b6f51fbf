#include "globe/GdalSetup.h"

#include "globe/RasterSource.h"
#include "globe/TileCacheFs.h"

#include <cpl_conv.h>
#include <gdal.h>

#include <cstdlib>
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
        // A server silent for 30 s ends the request whatever timeout a driver sets itself (GDAL's
        // WMTS and WMS-from-URL wait 300 s).
        setConfigDefault("GDAL_HTTP_LOW_SPEED_TIME", "30");
        setConfigDefault("GDAL_HTTP_LOW_SPEED_LIMIT", "1");
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

namespace {

std::optional<std::string> envValue(const std::string& name) {
    const char* v = name.empty() ? nullptr : std::getenv(name.c_str());
    if (!v) return std::nullopt;
    return std::string(v);
}

/// GDAL_HTTP_HEADERS splits on commas: a header with a comma or a quote goes in double quotes,
/// its quotes and backslashes escaped with a backslash.
std::string gdalHeaderList(const std::string& header) {
    if (header.find_first_of(",\"\\") == std::string::npos) return header;
    std::string q = "\"";
    for (char c : header) {
        if (c == '"' || c == '\\') q += '\\';
        q += c;
    }
    return q + "\"";
}

}  // namespace

Result<void> checkHttpAuth(const HttpAuth& auth) {
    if (!auth.basicEnv.empty()) {
        const auto v = envValue(auth.basicEnv);
        if (!v) return makeError("the environment variable " + auth.basicEnv + " (HTTP basic credentials) is not set");
        if (v->find(':') == std::string::npos || v->front() == ':')
            return makeError("the environment variable " + auth.basicEnv + " must hold \"user:password\"");
        if (v->find_first_of("\r\n") != std::string::npos)
            return makeError("the environment variable " + auth.basicEnv + " holds a line break");
    }
    if (!auth.headerEnv.empty()) {
        const auto v = envValue(auth.headerEnv);
        if (!v) return makeError("the environment variable " + auth.headerEnv + " (an HTTP header) is not set");
        const size_t colon = v->find(':');
        const bool nameOk = colon != std::string::npos && colon > 0 &&
                            v->find_first_of(" \t\"(),/;<=>?@[\\]{}") >= colon;
        if (!nameOk) return makeError("the environment variable " + auth.headerEnv + " must hold one header, \"Name: value\"");
        if (v->find_first_of("\r\n") != std::string::npos)
            return makeError("the environment variable " + auth.headerEnv + " holds a line break (one header only)");
    }
    return {};
}

ScopedThreadOption::ScopedThreadOption(const char* key, const char* value) : key_(key), set_(value != nullptr) {
    if (!set_) return;
    if (const char* old = CPLGetThreadLocalConfigOption(key, nullptr)) old_ = old, hadOld_ = true;
    CPLSetThreadLocalConfigOption(key, value);
}

ScopedThreadOption::~ScopedThreadOption() {
    if (set_) CPLSetThreadLocalConfigOption(key_, hadOld_ ? old_.c_str() : nullptr);
}

ScopedHttpAuth::ScopedHttpAuth(const HttpAuth& auth) {
    if (!auth.any()) return;
    configureGdal();
    if (const auto basic = envValue(auth.basicEnv)) {
        userPassword_.emplace("GDAL_HTTP_USERPWD", basic->c_str());
        method_.emplace("GDAL_HTTP_AUTH", "BASIC");
    }
    if (const auto header = envValue(auth.headerEnv)) headers_.emplace("GDAL_HTTP_HEADERS", gdalHeaderList(*header).c_str());
}

// Members are destroyed in reverse order: each option is put back as it was.
ScopedHttpAuth::~ScopedHttpAuth() = default;

}  // namespace orbis::globe
