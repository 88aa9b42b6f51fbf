#pragma once
// GDAL's tile cache for remote imagery and elevation (XYZ, WMS) made safe on a full, read-only or
// damaged disk. GDAL's WMS driver copies each downloaded tile straight to its final name and
// trusts whatever file it later finds there, so a disk that fills mid-copy leaves a cut tile that
// decodes to wrong pixels for as long as the cache lives. Orbis gives GDAL the cache folder
// through its own file system (a GDAL virtual file system handler, "/vsiorbiscache/"):
//  - a tile is written under a temporary name with a CRC-32 trailer and renamed over its final
//    name only when every byte went out; a failed write leaves nothing, says so once per folder
//    (the tiles are then fetched without a cache), and the read goes on from the download;
//  - a tile is read whole and its CRC checked on open: a cut, damaged or foreign file (an older
//    Orbis's cache) counts as absent and is removed, so GDAL fetches the tile again.

#include <cstdint>
#include <string>

namespace orbis::globe {

/// The bytes after a tile's own: CRC-32 of the tile (little-endian), then "OTC1".
inline constexpr uint64_t kTileCacheTrailerBytes = 8;

/// The path to give GDAL (a WMS <Cache><Path>, GDAL_DEFAULT_WMS_CACHE_PATH) for the cache folder
/// `dir`: "/vsiorbiscache" followed by its absolute path. Installs the handler on first use.
std::string tileCachePath(const std::string& dir);

/// Failed tile writes since the start (a full or read-only disk): for tests and status.
uint64_t tileCacheWriteFailures();

}  // namespace orbis::globe
