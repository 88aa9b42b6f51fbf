#pragma once
// GDAL set up once for Orbis, by whatever reads through it first (a raster, a vector source, a
// volume): every driver registered, and these defaults unless the user set them (environment
// or CPLSetConfigOption): GDAL_HTTP_TIMEOUT=30 and GDAL_HTTP_CONNECTTIMEOUT=10 (s), so that a
// server that stalls (a WMS, a WFS, a file over /vsicurl/) ends the read instead of holding a
// worker for ever; GDAL_HTTP_MAX_RETRY=2 with GDAL_HTTP_RETRY_DELAY=1 (s, growing) for busy
// servers; GDAL_DEFAULT_WMS_CACHE_PATH in Orbis's tile cache (TileCacheFs.h); GDAL_CACHEMAX 64 MB;
// WFS GetFeature paged (OGR_WFS_PAGING_ALLOWED=ON, OGR_WFS_PAGE_SIZE=1000).
// A scene that reads nothing through GDAL never initialises it.

namespace orbis::globe {

void configureGdal();

}  // namespace orbis::globe
