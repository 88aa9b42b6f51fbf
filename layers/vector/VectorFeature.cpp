#include "layers/vector/VectorFeature.h"

#include "layers/vector/LonLatGeometry.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>

namespace orbis::vector::detail {
namespace {

// ---------------------------------------------------------------------------------------------
// Flattening: every simple geometry of a (multi, collection, curved) geometry into parts

/// The parts of one feature, by kind, while they are gathered.
struct Gathered {
    Feature points, lines, polygons;
    uint64_t vertices = 0, maxVertices = 0;
    bool overLimit = false;
    bool hasZ = false;

    /// Counts `n` more vertices; false (and overLimit) past the limit, before anything is copied.
    bool reserve(uint64_t n) {
        vertices += n;
        overLimit = overLimit || vertices > maxVertices;
        return !overLimit;
    }
};

void appendCurve(Feature& f, const OGRSimpleCurve& curve) {
    f.parts.push_back(uint32_t(f.coords.size()));
    const int n = curve.getNumPoints();
    for (int i = 0; i < n; ++i) f.coords.emplace_back(curve.getX(i), curve.getY(i), curve.getZ(i));
}

void addLine(Gathered& g, const OGRSimpleCurve& line) {
    if (line.getNumPoints() < 2 || !g.reserve(uint64_t(line.getNumPoints()))) return;
    appendCurve(g.lines, line);
}

void addPolygon(Gathered& g, const OGRPolygon& polygon) {
    const OGRLinearRing* outer = polygon.getExteriorRing();
    if (!outer || outer->getNumPoints() < 3) return;
    g.polygons.polygons.push_back(uint32_t(g.polygons.parts.size()));
    for (int r = -1; r < polygon.getNumInteriorRings(); ++r) {
        const OGRLinearRing* ring = r < 0 ? outer : polygon.getInteriorRing(r);
        if (!ring || ring->getNumPoints() < 3 || !g.reserve(uint64_t(ring->getNumPoints()))) continue;
        appendCurve(g.polygons, *ring);
    }
}

void addGeometry(Gathered& g, const OGRGeometry& geometry) {
    if (g.overLimit || geometry.IsEmpty()) return;
    g.hasZ = g.hasZ || geometry.Is3D();
    if (geometry.hasCurveGeometry()) {
        // Circular strings, compound curves, curve polygons: GDAL's default step (4 degrees of arc).
        const std::unique_ptr<OGRGeometry> linear(geometry.getLinearGeometry());
        if (linear && !linear->hasCurveGeometry()) addGeometry(g, *linear);
        return;
    }
    switch (wkbFlatten(geometry.getGeometryType())) {
        case wkbPoint:
            if (g.reserve(1)) {
                const OGRPoint& p = *geometry.toPoint();
                g.points.parts.push_back(uint32_t(g.points.coords.size()));
                g.points.coords.emplace_back(p.getX(), p.getY(), p.getZ());
            }
            return;
        case wkbLineString:
        case wkbLinearRing: addLine(g, *geometry.toSimpleCurve()); return;
        case wkbPolygon:
        case wkbTriangle: addPolygon(g, *static_cast<const OGRPolygon*>(&geometry)); return;
        case wkbPolyhedralSurface:
        case wkbTIN:
            for (const OGRPolygon* p : *geometry.toPolyhedralSurface()) addGeometry(g, *p);
            return;
        case wkbMultiPoint:
        case wkbMultiLineString:
        case wkbMultiPolygon:
        case wkbGeometryCollection:
            for (const OGRGeometry* part : *geometry.toGeometryCollection())
                if (part) addGeometry(g, *part);
            return;
        default: return;
    }
}

// ---------------------------------------------------------------------------------------------
// Coordinates: finite, to WGS84, unwrapped; pole rings; bounds

bool allFinite(const std::vector<glm::dvec3>& coords) {
    return std::all_of(coords.begin(), coords.end(), [](const glm::dvec3& v) {
        return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
    });
}

/// Transforms x, y in place (heights stay as stored); false when any vertex fails.
bool toLonLat(std::vector<glm::dvec3>& coords, OGRCoordinateTransformation* transform) {
    if (!transform) return true;
    constexpr size_t kBatch = 1 << 16;
    std::vector<double> x, y;
    std::vector<int> ok;
    for (size_t start = 0; start < coords.size(); start += kBatch) {
        const size_t n = std::min(kBatch, coords.size() - start);
        x.resize(n);
        y.resize(n);
        ok.assign(n, 0);
        for (size_t i = 0; i < n; ++i) x[i] = coords[start + i].x, y[i] = coords[start + i].y;
        transform->Transform(int(n), x.data(), y.data(), nullptr, nullptr, ok.data());
        for (size_t i = 0; i < n; ++i) {
            if (!ok[i] || !std::isfinite(x[i]) || !std::isfinite(y[i])) return false;
            coords[start + i].x = x[i];
            coords[start + i].y = y[i];
        }
    }
    return true;
}

/// Latitudes a hair past a pole (rounding in a transform) are put on it; a coordinate beyond
/// that, or a longitude past +-540 degrees (0..360 data unwraps fine), is a wrong CRS or a
/// corrupt file: the first such vertex, or none.
std::optional<glm::dvec3> outsideLonLat(std::vector<glm::dvec3>& coords) {
    constexpr double kPoleSlack = 1e-9, kMaxLon = 540.0;
    for (glm::dvec3& v : coords) {
        if (std::abs(v.y) > 90.0 && std::abs(v.y) <= 90.0 + kPoleSlack) v.y = std::copysign(90.0, v.y);
        if (!(std::abs(v.y) <= 90.0) || !(std::abs(v.x) <= kMaxLon)) return v;
    }
    return std::nullopt;
}

/// Unwraps lines and rings (holes next to their outer ring), flags pole rings and computes the
/// bounds.
void finish(Feature& f) {
    std::vector<LonLatBounds> boxes;
    boxes.reserve(f.parts.size());
    const bool polygons = f.kind == GeometryKind::Polygons;
    if (polygons) f.containsPole.assign(f.parts.size(), 0);
    size_t nextPolygon = 0;
    double outerMidLon = 0.0;
    for (size_t p = 0; p < f.parts.size(); ++p) {
        const std::span<glm::dvec3> part(f.coords.data() + f.parts[p], f.partEnd(p) - f.parts[p]);
        if (f.kind == GeometryKind::Points) {
            part[0].x = normalizeLonDeg(part[0].x);
            boxes.push_back(partBounds(part));
            continue;
        }
        unwrapLongitudes(part);
        int8_t pole = 0;
        if (polygons) {
            const bool outer = nextPolygon < f.polygons.size() && f.polygons[nextPolygon] == p;
            nextPolygon += outer;
            if (outer) outerMidLon = lonMidpoint(part);
            else moveNextTo(part, outerMidLon);
            pole = f.containsPole[p] = ringPoleWinding(part);
        }
        boxes.push_back(pole ? poleCapBounds(part, pole) : partBounds(part));
    }
    f.bounds = coverBounds(boxes);
}

std::string fidText(const OGRFeature& feature) { return "feature " + std::to_string(feature.GetFID()); }

// ---------------------------------------------------------------------------------------------
// Attributes

std::string isoDateTime(const OGRFeature& feature, int i, OGRFieldType type) {
    int year = 0, month = 0, day = 0, hour = 0, minute = 0, tz = 0;
    float second = 0.0f;
    if (!feature.GetFieldAsDateTime(i, &year, &month, &day, &hour, &minute, &second, &tz)) return {};
    char date[32] = "", time[48] = "", zone[16] = "";
    std::snprintf(date, sizeof date, "%04d-%02d-%02d", year, month, day);
    // Whole seconds unless the value has a fraction (OGR keeps milliseconds).
    const float whole = std::floor(second);
    if (second - whole > 0.0005f) std::snprintf(time, sizeof time, "%02d:%02d:%06.3f", hour, minute, double(second));
    else std::snprintf(time, sizeof time, "%02d:%02d:%02d", hour, minute, int(whole));
    // OGR's TZFlag: 0 unknown, 1 local time, 100 UTC, 100 + n: UTC + n quarter hours.
    if (tz == 100) std::snprintf(zone, sizeof zone, "Z");
    else if (tz > 1) {
        const int minutes = (tz - 100) * 15, a = std::abs(minutes);
        std::snprintf(zone, sizeof zone, "%c%02d:%02d", minutes < 0 ? '-' : '+', a / 60, a % 60);
    }
    if (type == OFTDate) return date;
    if (type == OFTTime) return std::string(time) + zone;
    return std::string(date) + "T" + time + zone;
}

AttributeValue attribute(const OGRFeature& feature, int i, const OGRFieldDefn& field) {
    if (!feature.IsFieldSetAndNotNull(i)) return std::monostate{};
    switch (field.GetType()) {
        case OFTInteger:
        case OFTInteger64: return int64_t(feature.GetFieldAsInteger64(i));
        case OFTReal: return feature.GetFieldAsDouble(i);
        case OFTDate:
        case OFTTime:
        case OFTDateTime: return isoDateTime(feature, i, field.GetType());
        default: return std::string(feature.GetFieldAsString(i));
    }
}

}  // namespace

ConvertedFeature convertFeature(const OGRFeature& feature, OGRCoordinateTransformation* transform,
                                uint64_t maxVertices) {
    ConvertedFeature out;
    const OGRGeometry* geometry = feature.GetGeometryRef();
    if (!geometry || geometry->IsEmpty()) {
        out.skipped = fidText(feature) + ": no geometry";
        return out;
    }
    Gathered g;
    g.maxVertices = std::min<uint64_t>(maxVertices, UINT32_MAX);   // Feature indexes with uint32_t
    g.points.kind = GeometryKind::Points;
    g.lines.kind = GeometryKind::Lines;
    g.polygons.kind = GeometryKind::Polygons;
    addGeometry(g, *geometry);
    if (g.overLimit) {
        out.skipped = fidText(feature) + ": more than " + std::to_string(maxVertices) + " vertices (the limit per feature)";
        return out;
    }
    for (Feature* f : {&g.points, &g.lines, &g.polygons}) {
        if (f->parts.empty()) continue;
        if (!allFinite(f->coords)) {
            out.skipped = fidText(feature) + ": a coordinate is NaN or infinite";
            out.features.clear();
            return out;
        }
        if (!toLonLat(f->coords, transform)) {
            out.skipped = fidText(feature) + ": a coordinate cannot be transformed to WGS84";
            out.features.clear();
            return out;
        }
        if (const auto v = outsideLonLat(f->coords)) {
            char where[96];
            std::snprintf(where, sizeof where, "(%.6g, %.6g)", v->x, v->y);
            out.skipped = fidText(feature) + ": the coordinate " + where +
                          " is not a WGS84 longitude, latitude (is the layer's CRS right?)";
            out.features.clear();
            return out;
        }
        f->fid = feature.GetFID() == OGRNullFID ? -1 : int64_t(feature.GetFID());
        f->hasZ = g.hasZ;
        finish(*f);
        out.features.push_back(std::move(*f));
    }
    if (out.features.empty()) {
        out.skipped = fidText(feature) + ": no usable geometry (empty or degenerate parts)";
        return out;
    }
    std::vector<AttributeValue> attributes = readAttributes(feature);
    for (size_t k = 0; k + 1 < out.features.size(); ++k) out.features[k].attributes = attributes;
    out.features.back().attributes = std::move(attributes);
    return out;
}

std::vector<FieldInfo> readFields(const OGRFeatureDefn& definition) {
    std::vector<FieldInfo> fields;
    for (int i = 0; i < definition.GetFieldCount(); ++i) {
        const OGRFieldDefn* f = definition.GetFieldDefn(i);
        fields.push_back({f->GetNameRef(), OGRFieldDefn::GetFieldTypeName(f->GetType())});
    }
    return fields;
}

std::vector<AttributeValue> readAttributes(const OGRFeature& feature) {
    std::vector<AttributeValue> values;
    const OGRFeatureDefn& definition = *feature.GetDefnRef();
    values.reserve(size_t(definition.GetFieldCount()));
    for (int i = 0; i < definition.GetFieldCount(); ++i) values.push_back(attribute(feature, i, *definition.GetFieldDefn(i)));
    return values;
}

}  // namespace orbis::vector::detail
