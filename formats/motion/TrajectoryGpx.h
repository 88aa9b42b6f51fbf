#pragma once
// GPX 1.0 / 1.1 (www.topografix.com/GPX): tracks (<trk>, its <trkseg>s and <trkpt>s), routes
// (<rte>, <rtept>) and waypoints (<wpt>), read by a small XML scanner of our own (no GDAL: it
// names the line of every problem). CPU only.
//
// What is read: a point's lat and lon attributes, its <ele> (metres; GPX says "elevation", above
// mean sea level, i.e. the geoid) and <time> (ISO 8601, UTC); a track's or route's <name>; the
// file's <bounds>. Everything else (extensions, links, names of points) is skipped, whatever its
// namespace. Element names are matched without their namespace prefix (<gpx:trkpt> is <trkpt>).
//
// As trajectory samples (gpxSamples): one per point, the segments of a track concatenated in
// file order; altitude MeanSeaLevel from <ele>, or Ground at 0 where a point has no <ele> ("on
// the ground"); no attitude, so the Trajectory derives heading from the course over ground and
// pitch from the climb angle, roll 0. A point without <time> is an error naming its line: a
// trajectory needs a time at every sample. Times out of order or repeated are Trajectory::create's
// errors, naming the lines.
//
// Errors (each names the file and, where there is one, the line): XML that is not well formed
// (a tag closed by another, the file ending inside an element, an unknown entity, ...), a root
// element other than <gpx>, a point without lat/lon or with a value that is not a number or out
// of range, an <ele> that is not a number, a <time> that is not an ISO 8601 time, a file over
// kMaxGpxBytes or that cannot be read.

#include "base/Result.h"
#include "formats/motion/TrajectorySample.h"

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace orbis::motion {

/// Largest GPX file read (it is read whole; a point takes ~60 bytes in memory, its XML ~100).
inline constexpr uint64_t kMaxGpxBytes = uint64_t(256) << 20;

struct GpxPoint {
    double lonDeg = 0.0, latDeg = 0.0;
    std::optional<double> ele;     ///< metres above mean sea level
    std::optional<TimeNs> time;
    std::size_t line = 0;          ///< of the point's start tag
};

struct GpxTrack {
    std::string name;
    bool route = false;            ///< a <rte>, not a <trk>
    std::size_t segments = 0;      ///< <trkseg>s (1 for a route)
    std::vector<GpxPoint> points;  ///< the segments' points in file order
    std::size_t line = 0;
};

struct GpxBounds {
    double minLatDeg = 0.0, minLonDeg = 0.0, maxLatDeg = 0.0, maxLonDeg = 0.0;
};

struct Gpx {
    std::string version;               ///< the <gpx version> attribute
    std::vector<GpxTrack> tracks;      ///< tracks and routes in file order
    std::vector<GpxPoint> waypoints;
    std::optional<GpxBounds> bounds;   ///< as the file states it (metadata/bounds)
};

/// Parses GPX text; `name` (the file) starts every message. Any thread.
Result<Gpx> parseGpx(std::string_view text, const std::string& name);

/// Reads and parses `path` (errors name it; files over kMaxGpxBytes are refused).
Result<Gpx> readGpx(const std::string& path);

/// The samples of one track or route (see above). Errors: a point without <time>, no points.
Result<std::vector<TrajectorySample>> gpxSamples(const GpxTrack& track, const std::string& name);

/// The samples of the track or route `track` names (its <name>, or its 1-based position among
/// the file's tracks and routes: "2"); with `track` empty, the first one whose every point has
/// a time. Errors name the tracks there are and why none fits.
Result<std::vector<TrajectorySample>> gpxTrajectorySamples(const Gpx& gpx, const std::string& name,
                                                           const std::string& track = "");

}  // namespace orbis::motion
