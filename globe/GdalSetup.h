#pragma once
// GDAL set up once for Orbis, by whatever reads through it first (a raster, a vector source, a
// volume): every driver registered, and these defaults unless the user set them (environment
// or CPLSetConfigOption): GDAL_HTTP_TIMEOUT=30 and GDAL_HTTP_CONNECTTIMEOUT=10 (s), and
// GDAL_HTTP_LOW_SPEED_TIME=30 with GDAL_HTTP_LOW_SPEED_LIMIT=1 (for drivers that set their own
// timeout: a silent server ends the request after 30 s), so that a server that stalls (a WMS,
// a WMTS, a WFS, a file over /vsicurl/) ends the read instead of holding a worker for ever; GDAL_HTTP_MAX_RETRY=2 with GDAL_HTTP_RETRY_DELAY=1 (s, growing) for busy
// servers; GDAL_DEFAULT_WMS_CACHE_PATH in Orbis's tile cache (TileCacheFs.h); GDAL_CACHEMAX 64 MB;
// WFS GetFeature paged (OGR_WFS_PAGING_ALLOWED=ON, OGR_WFS_PAGE_SIZE=1000).
// A scene that reads nothing through GDAL never initialises it.
//
// HTTP credentials for one source (a WMS, a WFS, a file over /vsicurl/) come from environment
// variables that the source names, read at each request, so that a scene file, a log or an error
// message never holds them:
//
//   HttpAuth auth{.basicEnv = "ORBIS_WMS_USERPWD"};       // the variable holds "user:password"
//   if (auto ok = checkHttpAuth(auth); !ok) return ok.error();
//   ScopedHttpAuth scope(auth);                           // this thread's GDAL requests send them

#include "base/Result.h"

#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace orbis::globe {

void configureGdal();

/// Sets one GDAL configuration option for the calling thread for a scope (nothing with a null
/// value), and puts back what the thread had.
class ScopedThreadOption {
public:
    ScopedThreadOption(const char* key, const char* value);
    ~ScopedThreadOption();
    ScopedThreadOption(const ScopedThreadOption&) = delete;
    ScopedThreadOption& operator=(const ScopedThreadOption&) = delete;

private:
    const char* key_;
    bool set_, hadOld_ = false;
    std::string old_;
};

struct HttpAuth {
    std::string basicEnv;    ///< a variable holding "user:password" (HTTP basic authentication)
    std::string headerEnv;   ///< a variable holding one request header, "Name: value"
    bool any() const { return !basicEnv.empty() || !headerEnv.empty(); }
    bool operator==(const HttpAuth&) const = default;
};

/// Whether the variables are set and well formed. Errors name the variable and what is wrong,
/// never its value. Any thread.
Result<void> checkHttpAuth(const HttpAuth& auth);

/// For its life, the calling thread's GDAL HTTP requests send `auth`'s credentials (thread-local
/// GDAL_HTTP_USERPWD with GDAL_HTTP_AUTH=BASIC, and GDAL_HTTP_HEADERS); what the thread had
/// before is put back. Does nothing for an empty `auth`, or a variable that is not set.
class ScopedHttpAuth {
public:
    explicit ScopedHttpAuth(const HttpAuth& auth);
    ~ScopedHttpAuth();
    ScopedHttpAuth(const ScopedHttpAuth&) = delete;
    ScopedHttpAuth& operator=(const ScopedHttpAuth&) = delete;

private:
    std::optional<ScopedThreadOption> userPassword_, method_, headers_;
};

}  // namespace orbis::globe
