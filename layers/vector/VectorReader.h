#pragma once
// Vector data (points, lines, polygons) from anything GDAL/OGR opens: Shapefile, GeoPackage,
// GeoJSON, CSV with WKT, KML, FlatGeobuf, or a connection string ("WFS:http://..."). CPU only,
// no Vulkan; safe to call from any thread (each call opens its own dataset).
//
//   VectorReadOptions o;
//   o.source = "countries.shp";
//   o.where = "continent = 'Africa'";        // or o.sql = "SELECT * FROM countries WHERE ..."
//   auto data = readVector(o);                // Result<VectorData>
//   if (!data) log::error(data.message());    // names the source, the layer and the problem
//
// Every coordinate reference system is transformed to WGS84 longitude/latitude in degrees
// (longitude first) through PROJ, datum shifts and foot units included. Heights are the
// geometry's Z as stored (0 without Z). A layer without a CRS is taken as WGS84 lon/lat, with a
// warning, when its extent fits [-180, 360] x [-90, 90]; otherwise it is an error.
//
// The antimeridian: each line and ring is unwrapped, so consecutive longitudes never jump by
// more than 180 degrees (a line from 179 to -179 becomes 179 to 181). Bounds are the shortest
// longitude interval covering the parts, so Fiji, cut at 180 into parts on both sides, is a
// few degrees wide, not 360. A ring whose longitude turns once around the globe (Antarctica)
// encloses a pole: it is flagged, and its bounds span every longitude down to the pole.
//
// Bad data never crashes the reader: a feature with NaN or infinite coordinates, one that
// cannot be transformed, or one over the vertex limit is skipped with a warning naming its fid.

#include "base/Result.h"
#include "globe/GdalSetup.h"
#include "layers/vector/SourceStyle.h"

#include <glm/glm.hpp>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

namespace orbis::vector {

/// A longitude/latitude box on the sphere. `west` is in [-180, 180); `east` is in
/// [west, west + 360], so a box across the antimeridian has east > 180 (Fiji: 177 .. 180.2).
/// A box spanning every longitude is west = -180, east = 180.
struct LonLatBounds {
    double west = 0.0, south = 0.0, east = 0.0, north = 0.0;
    bool empty = true;

    double widthDeg() const { return empty ? 0.0 : east - west; }
    bool spansAllLongitudes() const { return !empty && east - west >= 360.0; }
    /// True when `lonDeg` (any turn) lies in the longitude interval and lat in [south, north].
    bool contains(double lonDeg, double latDeg) const;
};

enum class GeometryKind : uint8_t {
    Points,     ///< every part is one point
    Lines,      ///< every part is one line string (two or more vertices)
    Polygons,   ///< every part is one ring; `polygons` groups rings into polygons
};

/// A typed attribute: null, integer (OGR Integer, Integer64, booleans as 0/1), real, or text
/// (strings; dates and times as ISO 8601 text; lists and binaries as OGR writes them).
using AttributeValue = std::variant<std::monostate, int64_t, double, std::string>;

/// One feature's geometry, flattened. Multi-geometries, collections and curves (linearised)
/// become parts of one kind; a collection that mixes kinds becomes one Feature per kind, with
/// the same fid and attributes.
///
/// `coords` holds (lon, lat, height) in degrees and metres. Part p runs from parts[p] to
/// parts[p + 1] (or coords.size() for the last). For polygons, polygon k's rings are the parts
/// from polygons[k] to polygons[k + 1] (or parts.size()): the first is the outer ring, the rest
/// its holes. Rings are closed as stored (the first vertex repeated last, when the source did).
/// Longitudes within a part are continuous (unwrapped across the antimeridian), so they may lie
/// outside [-180, 180]. Each line, point and outer ring starts in [-180, 180]; a hole is moved by
/// whole turns next to its outer ring.
struct Feature {
    int64_t fid = -1;   ///< OGR's feature id (-1 when the source has none)
    GeometryKind kind = GeometryKind::Points;
    std::vector<glm::dvec3> coords;
    std::vector<uint32_t> parts;
    std::vector<uint32_t> polygons;
    /// Polygons only, one per part: +1 when the ring winds once around the North Pole (its
    /// longitude changes by 360 degrees over the ring, and it lies north of the equator on
    /// average), -1 for the South Pole, 0 otherwise.
    std::vector<int8_t> containsPole;
    std::vector<AttributeValue> attributes;   ///< one per field of the layer, in field order
    LonLatBounds bounds;
    bool hasZ = false;
    int32_t style = -1;   ///< its own style in VectorLayer::styles (KML), -1: none

    uint32_t partEnd(size_t p) const { return p + 1 < parts.size() ? parts[p + 1] : uint32_t(coords.size()); }
    /// Part p's coordinates; empty when its indices are out of order or out of range.
    std::span<const glm::dvec3> part(size_t p) const {
        const size_t begin = std::min<size_t>(parts[p], coords.size());
        const size_t end = std::min<size_t>(std::max<size_t>(partEnd(p), begin), coords.size());
        return {coords.data() + begin, end - begin};
    }
    uint32_t polygonEnd(size_t k) const { return k + 1 < polygons.size() ? polygons[k + 1] : uint32_t(parts.size()); }
};

struct FieldInfo {
    std::string name;
    std::string type;   ///< OGR's type name: "Integer", "Integer64", "Real", "String", "Date", ...
};

/// The index of the field called `name`, if the layer has one.
std::optional<size_t> findField(std::span<const FieldInfo> fields, const std::string& name);
/// The fields' names for messages: "name, pop, height", or "none".
std::string fieldNames(std::span<const FieldInfo> fields);

struct VectorLayer {
    std::string name;
    std::string geometryType;   ///< OGR's name of the declared type: "Polygon", "Multi Point", ...
    std::string crs;            ///< "EPSG:4267" when an authority code is known, else the CRS's name
    std::string crsName;        ///< the CRS's own name ("NAD27"), empty without a CRS
    std::vector<FieldInfo> fields;
    std::vector<Feature> features;
    LonLatBounds bounds;        ///< of every feature read
    uint64_t featuresRead = 0;      ///< features OGR returned (kept or skipped)
    uint64_t featuresSkipped = 0;
    uint64_t vertexCount = 0;       ///< in `features`
    std::vector<std::string> warnings;   ///< at most VectorLimits::maxWarnings, then a summary
    std::vector<SourceStyle> styles;     ///< the features' own styles, each distinct one once
};

struct VectorLimits {
    uint64_t maxVerticesPerFeature = 1'000'000;   ///< a larger feature is skipped with a warning
    uint64_t maxTotalVertices = 50'000'000;       ///< reading stops there, with a warning
    uint64_t maxFeatures = 10'000'000;            ///< per read; reading stops there, with a warning
    size_t maxWarnings = 100;                     ///< per layer; the rest are counted
};

struct VectorReadOptions {
    std::string source;                 ///< a path, or any string OGR opens ("WFS:http://...")
    std::vector<std::string> layers;    ///< empty: every layer of the source
    std::string where;                  ///< an OGR attribute filter for each layer
    std::string sql;                    ///< a full OGR SQL statement instead of layers and where
    /// Only the features whose box meets this lon/lat box (west < east, within [-180, 180]):
    /// a feature tile's read. OGR's spatial filter in the layer's CRS (the box transformed with
    /// its edges densified), so sources with a spatial index (GeoPackage, FlatGeobuf,
    /// Shapefile with .qix, PostGIS) read only what is near. Features are not clipped.
    std::optional<LonLatBounds> within;
    /// Called on each feature as it is read, before it is kept: it may change the feature (a
    /// feature tile clips and simplifies it, so that a read holds only what it keeps) and
    /// returns false to drop it; one that moves vertices sets the feature's bounds again. The
    /// limits count what is kept.
    std::function<bool(Feature&)> shape;
    /// Keep the source open on this thread for its next read (a pager's many small reads; the
    /// filters are set again on each). Off: opened and closed by the read.
    bool reuseDataset = false;
    VectorLimits limits;
    /// HTTP credentials for a WFS or a remote file, from the environment variables named here.
    globe::HttpAuth httpAuth;
};

struct VectorData {
    std::string source;
    std::vector<VectorLayer> layers;
};

/// Reads the chosen layers of a source. Errors name the source and, where relevant, the layer
/// and the expression: a missing file, a source OGR cannot open, an unknown layer, a bad
/// `where` or `sql` (with OGR's message), a CRS that cannot be transformed to WGS84, a layer
/// without a CRS whose coordinates are not lon/lat. An empty layer is not an error.
Result<VectorData> readVector(const VectorReadOptions& options);

/// What a read with these options covers, from OGR's metadata (no feature is converted): for
/// each layer it would read, its fields, its feature count (after `where`; -1 when OGR
/// cannot tell) and its extent on the globe (none when unknown; some drivers give the whole
/// layer's even with `where`, a box that still covers every feature). Whether to page a source.
struct LayerSummary {
    std::string name;
    std::vector<FieldInfo> fields;
    int64_t featureCount = -1;
    std::optional<LonLatBounds> bounds;
};
Result<std::vector<LayerSummary>> summarizeVector(const VectorReadOptions& options);

/// What a source holds, as JSON, without reading its features: per layer the geometry type,
/// the feature count, the CRS (name and EPSG code), the fields and the extent in WGS84
/// lon/lat. For `orbis info`.
Result<std::string> describeVectorJson(const std::string& source);

/// True when GDAL opens `path` as vector data with at least one layer that has a geometry.
bool looksLikeVectorFile(const std::string& path);

}  // namespace orbis::vector
