#include "layers/vector/FeatureMesh.h"

#include "base/ThreadPool.h"
#include "globe/Ellipsoid.h"
#include "globe/TileKey.h"
#include "layers/vector/LonLatGeometry.h"
#include "layers/vector/Triangulate.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace orbis::vector {
namespace {

/// A polygon's vertices in a plane around its first vertex: x east, y north, in degrees of
/// latitude (longitudes scaled by the cosine of the first latitude). Invertible exactly.
struct LocalPlane {
    double lon0 = 0.0, lat0 = 0.0, k = 1.0;
    LocalPlane(double lon, double lat) : lon0(lon), lat0(lat), k(std::max(std::cos(glm::radians(lat)), 1e-6)) {}
    glm::dvec2 to(const glm::dvec3& c) const { return {(c.x - lon0) * k, c.y - lat0}; }
    glm::dvec2 lonLat(const glm::dvec2& p) const { return {lon0 + p.x / k, lat0 + p.y}; }
};

uint32_t packColor(const glm::dvec3& srgb, double opacity = 1.0) {
    const auto byte = [](double v) { return uint32_t(std::lround(std::clamp(v, 0.0, 1.0) * 255.0)); };
    return byte(srgb.r) | (byte(srgb.g) << 8) | (byte(srgb.b) << 16) | (byte(opacity) << 24);
}

uint32_t packNormal(const glm::dvec3& n) {
    const auto snorm = [](double v) { return uint32_t(uint8_t(int8_t(std::lround(std::clamp(v, -1.0, 1.0) * 127.0)))); };
    return snorm(n.x) | (snorm(n.y) << 8) | (snorm(n.z) << 16);
}

glm::dvec3 upAt(double lonDeg, double latDeg) { return globe::Ellipsoid::wgs84().surfaceNormal(lonDeg, latDeg); }

/// Appends vertices to one chunk, remembering their bounds.
struct ChunkWriter {
    MeshChunk& chunk;
    glm::dvec3& lo;
    glm::dvec3& hi;

    glm::vec3 relative(const glm::dvec3& ecef) {
        const glm::dvec3 rel = ecef - chunk.origin;
        lo = glm::min(lo, rel);
        hi = glm::max(hi, rel);
        return glm::vec3(rel);
    }
    uint32_t vertex(const glm::dvec3& ecef, const glm::dvec3& normal, uint32_t color, uint32_t id) {
        chunk.vertices.push_back({relative(ecef), packNormal(normal), color, id});
        return uint32_t(chunk.vertices.size() - 1);
    }
    enum class Faces { Front, Both, Blended };
    /// A triangle facing `normal` (its winding made so), or both faces, or one to blend (drawn
    /// from both sides without culling).
    void triangle(uint32_t a, uint32_t b, uint32_t c, const glm::dvec3& facing, Faces faces) {
        const glm::dvec3 pa(chunk.vertices[a].position), pb(chunk.vertices[b].position), pc(chunk.vertices[c].position);
        if (glm::dot(glm::cross(pb - pa, pc - pa), facing) < 0.0) std::swap(b, c);
        auto& out = faces == Faces::Blended ? chunk.translucent : chunk.indices;
        out.insert(out.end(), {a, b, c});
        if (faces == Faces::Both) chunk.indices.insert(chunk.indices.end(), {a, c, b});
    }
};

struct PolygonInput {
    std::vector<glm::dvec2> plane;       ///< every ring's points in the local plane
    std::vector<double> surface, ground;  ///< s(v), g(v) per point
    std::vector<uint32_t> starts;        ///< ring starts
};

/// The surface of a polygon at altitude: each triangle cut into n x n by a grid of barycentric
/// points (n the same for the whole polygon, so that neighbours share their edges' points), at
/// the heights interpolated.
void emitSurface(ChunkWriter& w, const PolygonInput& in, const LocalPlane& plane, std::span<const uint32_t> tris,
                 uint32_t color, uint32_t id) {
    const auto faces = (color >> 24) < 255u ? ChunkWriter::Faces::Blended : ChunkWriter::Faces::Both;
    const auto& ell = globe::Ellipsoid::wgs84();
    double longest = 0.0;
    for (size_t t = 0; t < tris.size(); t += 3)
        for (int e = 0; e < 3; ++e)
            longest = std::max(longest, glm::length(in.plane[tris[t + e]] - in.plane[tris[t + (e + 1) % 3]]));
    // At most ~64k triangles for one polygon's surface: beyond that the chords sag more.
    const double budget = std::max(1.0, std::sqrt(65536.0 / double(std::max<size_t>(tris.size() / 3, 1))));
    const int n = int(std::clamp(std::ceil(longest / kMaxEdgeDeg), 1.0, std::min(budget, 64.0)));
    std::vector<uint32_t> grid;
    for (size_t t = 0; t < tris.size(); t += 3) {
        const uint32_t v[3] = {tris[t], tris[t + 1], tris[t + 2]};
        grid.clear();
        // Point (i, j) = corner 0 + i/n towards corner 1 + j/n towards corner 2 (i + j <= n). On an
        // edge, the point is found from the edge's lower-numbered vertex, so both triangles that
        // share the edge compute the same numbers.
        const auto point = [&](int i, int j) {
            const int k = n - i - j;
            double wt[3] = {double(k) / n, double(i) / n, double(j) / n};
            if (k == 0 || i == 0 || j == 0) {
                int a = 0, b = 1;
                if (k == 0) a = 1, b = 2;
                else if (i == 0) a = 0, b = 2;
                if (v[a] > v[b]) std::swap(a, b);
                const double tb = wt[b];
                wt[0] = wt[1] = wt[2] = 0.0;
                wt[a] = 1.0 - tb;
                wt[b] = tb;
            }
            glm::dvec2 p(0.0);
            double h = 0.0;
            for (int c = 0; c < 3; ++c) {
                p += wt[c] * in.plane[v[c]];
                h += wt[c] * in.surface[v[c]];
            }
            const glm::dvec2 ll = plane.lonLat(p);
            return w.vertex(ell.toEcef(ll.x, ll.y, h), upAt(ll.x, ll.y), color, id);
        };
        for (int j = 0; j <= n; ++j)
            for (int i = 0; i + j <= n; ++i) grid.push_back(point(i, j));
        const auto at = [&](int i, int j) { return grid[size_t(j * (n + 1) - j * (j - 1) / 2 + i)]; };
        const glm::dvec2 mid = (in.plane[v[0]] + in.plane[v[1]] + in.plane[v[2]]) / 3.0;
        const glm::dvec2 ll = plane.lonLat(mid);
        const glm::dvec3 up = upAt(ll.x, ll.y);
        for (int j = 0; j < n; ++j)
            for (int i = 0; i + j < n; ++i) {
                w.triangle(at(i, j), at(i + 1, j), at(i, j + 1), up, faces);
                if (i + j + 1 < n) w.triangle(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1), up, faces);
            }
    }
}

/// An extruded polygon: a flat roof at `roof` and walls from `bottom` up to it.
void emitSolid(ChunkWriter& w, const PolygonInput& in, const LocalPlane& plane, std::span<const uint32_t> tris,
               double roof, double bottom, uint32_t color, uint32_t id) {
    const auto& ell = globe::Ellipsoid::wgs84();
    const uint32_t base = uint32_t(w.chunk.vertices.size());
    for (const glm::dvec2& p : in.plane) {
        const glm::dvec2 ll = plane.lonLat(p);
        w.vertex(ell.toEcef(ll.x, ll.y, roof), upAt(ll.x, ll.y), color, id);
    }
    for (size_t t = 0; t < tris.size(); t += 3) {
        const glm::dvec2 ll = plane.lonLat(in.plane[tris[t]]);
        w.triangle(base + tris[t], base + tris[t + 1], base + tris[t + 2], upAt(ll.x, ll.y), ChunkWriter::Faces::Front);
    }
    for (size_t r = 0; r < in.starts.size(); ++r) {
        const uint32_t begin = in.starts[r], end = r + 1 < in.starts.size() ? in.starts[r + 1] : uint32_t(in.plane.size());
        const std::span<const glm::dvec2> ring(in.plane.data() + begin, end - begin);
        // The solid lies left of each edge when an outer ring runs counter-clockwise or a hole
        // clockwise; the wall faces the other way.
        const bool solidLeft = (r == 0) == (ringArea2(ring) > 0.0);
        for (uint32_t i = begin; i < end; ++i) {
            const uint32_t j = i + 1 < end ? i + 1 : begin;
            const glm::dvec2 a = in.plane[i], b = in.plane[j], d = b - a;
            if (glm::dot(d, d) < 1e-22) continue;
            const glm::dvec2 right = glm::normalize(glm::dvec2(d.y, -d.x)), out2 = solidLeft ? right : -right;
            const glm::dvec2 ll = plane.lonLat(0.5 * (a + b));
            const glm::dmat3 enu = ell.enuFrame(ll.x, ll.y);
            const glm::dvec3 out = glm::normalize(enu[0] * out2.x + enu[1] * out2.y);
            const glm::dvec2 la = plane.lonLat(a), lb = plane.lonLat(b);
            const uint32_t ab = w.vertex(ell.toEcef(la.x, la.y, bottom), out, color, id);
            const uint32_t bb = w.vertex(ell.toEcef(lb.x, lb.y, bottom), out, color, id);
            const uint32_t bt = w.vertex(ell.toEcef(lb.x, lb.y, roof), out, color, id);
            const uint32_t at = w.vertex(ell.toEcef(la.x, la.y, roof), out, color, id);
            w.triangle(ab, bb, bt, out, ChunkWriter::Faces::Front);
            w.triangle(ab, bt, at, out, ChunkWriter::Faces::Front);
        }
    }
}

/// A line's parts as segments at the heights `surfaceAt` gives each coordinate, each cut into
/// pieces no longer than kMaxEdgeDeg (lon/lat and height interpolated).
template <typename SurfaceAt>
void emitLines(ChunkWriter& w, const Feature& f, const SurfaceAt& surfaceAt, const FeatureStyle& style, uint32_t id) {
    const auto& ell = globe::Ellipsoid::wgs84();
    const uint32_t color = packColor(style.color, style.opacity);
    for (size_t p = 0; p < f.parts.size(); ++p) {
        const uint32_t begin = f.parts[p], end = f.partEnd(p);
        double along = 0.0;   // metres from the part's start: where the dashes fall
        for (uint32_t c = begin; c + 1 < end && c + 1 < f.coords.size(); ++c) {
            const glm::dvec3 a(glm::dvec2(f.coords[c]), surfaceAt(c)), b(glm::dvec2(f.coords[c + 1]), surfaceAt(c + 1));
            const double k = std::cos(glm::radians(0.5 * (a.y + b.y)));
            const int n = int(std::clamp(std::ceil(std::max(std::abs(b.x - a.x) * k, std::abs(b.y - a.y)) / kMaxEdgeDeg), 1.0, 4096.0));
            glm::vec3 from = w.relative(ell.toEcef(a.x, a.y, a.z));
            for (int i = 1; i <= n; ++i) {
                const glm::dvec3 q = glm::mix(a, b, double(i) / n);
                const glm::vec3 to = w.relative(ell.toEcef(q.x, q.y, q.z));
                w.chunk.segments.push_back({from, color, to, float(style.widthPx), id, float(along), glm::vec2(style.dashPx)});
                along += double(glm::length(to - from));
                from = to;
            }
        }
    }
}

}  // namespace

std::optional<AltitudeMode> parseAltitudeMode(std::string_view name) {
    if (name == "clamped") return AltitudeMode::Clamped;
    if (name == "relative") return AltitudeMode::Relative;
    if (name == "absolute") return AltitudeMode::Absolute;
    return std::nullopt;
}

const char* altitudeModeName(AltitudeMode mode) {
    switch (mode) {
        case AltitudeMode::Clamped: return "clamped";
        case AltitudeMode::Relative: return "relative";
        case AltitudeMode::Absolute: return "absolute";
    }
    return "?";
}

bool drawnIn3d(const Feature& feature, const FeatureStyle& style, AltitudeMode mode) {
    if (feature.coords.empty()) return false;
    if (feature.kind != GeometryKind::Polygons) return mode != AltitudeMode::Clamped;
    if (feature.polygons.empty()) return false;
    if (std::any_of(feature.containsPole.begin(), feature.containsPole.end(), [](int8_t p) { return p != 0; })) return false;
    return style.extrudeM.has_value() || mode != AltitudeMode::Clamped;
}

MeshGround::MeshGround(const VectorContent& content, const ContentStyles& styles, AltitudeMode mode) : content_(&content) {
    for (size_t l = 0; l < content.layers.size() && l < styles.size(); ++l) {
        const auto& features = content.layers[l].data.features;
        for (size_t i = 0; i < features.size() && i < styles[l].size(); ++i) {
            if (!drawnIn3d(features[i], styles[l][i], mode)) continue;
            features_.emplace_back(uint32_t(l), uint32_t(i));
            first_.push_back(first_.back() + features[i].coords.size());
        }
    }
}

bool MeshGround::sample(const HeightFn& ground, size_t maxSamples) {
    size_t budget = maxSamples;
    heights_.resize(first_.back(), 0.0f);
    while (next_ < heights_.size() && budget > 0) {
        while (first_[nextFeature_ + 1] <= next_) ++nextFeature_;
        const auto [l, i] = features_[nextFeature_];
        const Feature& f = content_->layers[l].data.features[i];
        const glm::dvec3& c = f.coords[next_ - first_[nextFeature_]];
        const std::optional<double> h = ground ? ground(normalizeLonDeg(c.x), c.y) : std::nullopt;
        heights_[next_++] = float(h && std::isfinite(*h) ? *h : 0.0);
        --budget;
    }
    if (done()) content_ = nullptr;
    return done();
}

uint64_t FeatureMesh::bytes() const {
    uint64_t b = 0;
    for (const MeshChunk& c : chunks)
        b += c.vertices.size() * sizeof(shader::VectorMeshVertex) + (c.indices.size() + c.translucent.size()) * 4 +
             c.segments.size() * sizeof(shader::VectorSegment) + c.markers.size() * sizeof(shader::VectorMarker);
    return b;
}

uint32_t meshFeatureId(const VectorContent& content, size_t layer, size_t feature) {
    size_t before = 0;
    for (size_t l = 0; l < layer && l < content.layers.size(); ++l) before += content.layers[l].data.features.size();
    return uint32_t(before + feature + 1);
}

FeatureMesh buildFeatureMesh(const VectorContent& content, const ContentStyles& styles, const MeshGround& ground,
                             const MeshOptions& options, const jobs::CancelToken* cancel) {
    FeatureMesh out;
    std::vector<size_t> layerBase(content.layers.size() + 1, 0);
    for (size_t l = 0; l < content.layers.size(); ++l) layerBase[l + 1] = layerBase[l] + content.layers[l].data.features.size();
    // Chunks by tile and range; each chunk's vertex bounds while it fills.
    std::map<std::tuple<uint32_t, uint32_t, double, double>, size_t> chunkOf;
    std::vector<std::pair<glm::dvec3, glm::dvec3>> bounds;
    const auto& ell = globe::Ellipsoid::wgs84();
    PolygonInput in;
    for (size_t k = 0; k < ground.features().size(); ++k) {
        if (cancel && (k & 255u) == 0 && cancel->cancelled()) return {};
        const auto [l, i] = ground.features()[k];
        const ContentLayer& layer = content.layers[l];
        const Feature& f = layer.data.features[i];
        const FeatureStyle& style = styles[l][i];
        if (!style.visible || (layer.times.timed() && !layer.times.spans[i].shows(options.time))) continue;
        const std::span<const float> g = ground.heights(k);
        const auto surfaceAt = [&](size_t c) {
            const double z = f.hasZ && std::isfinite(f.coords[c].z) ? f.coords[c].z : 0.0;
            switch (options.mode) {
                case AltitudeMode::Clamped: return double(g[c]);
                case AltitudeMode::Relative: return double(g[c]) + z;
                case AltitudeMode::Absolute: return z;
            }
            return 0.0;
        };
        const glm::dvec3& first = f.coords.front();
        const globe::TileKey key = globe::TileKey::containing(normalizeLonDeg(first.x), std::clamp(first.y, -90.0, 90.0), kChunkLevel);
        auto [it, added] = chunkOf.try_emplace({key.x, key.y, style.minRangeM, style.maxRangeM}, out.chunks.size());
        if (added) {
            MeshChunk chunk;
            const globe::GeoExtent e = key.extent();
            chunk.origin = ell.toEcef(e.centerLon(), e.centerLat(), 0.0);
            chunk.minRangeM = style.minRangeM;
            chunk.maxRangeM = style.maxRangeM;
            out.chunks.push_back(std::move(chunk));
            bounds.emplace_back(glm::dvec3(1e300), glm::dvec3(-1e300));
        }
        ChunkWriter w{out.chunks[it->second], bounds[it->second].first, bounds[it->second].second};
        const int64_t fid = layer.data.features[i].fid;
        const uint32_t id = options.idsByFid && fid >= 0 ? uint32_t(fid + 1) : uint32_t(layerBase[l] + i + 1);
        // Solids are opaque; a surface at altitude has its fill's opacity.
        const uint32_t color = packColor(style.fill, style.extrudeM ? 1.0 : style.fillOpacity);
        const bool extruded = style.extrudeM.has_value();
        const double height = extruded ? std::max(0.0, *style.extrudeM * options.extrusionScale) : 0.0;
        const size_t verticesBefore = w.chunk.vertices.size(), indicesBefore = w.chunk.indices.size() + w.chunk.translucent.size();
        const size_t segmentsBefore = w.chunk.segments.size(), markersBefore = w.chunk.markers.size();
        if (f.kind == GeometryKind::Lines) emitLines(w, f, surfaceAt, style, id);
        if (f.kind == GeometryKind::Points) {
            // Its icon when it has one the atlas holds (its index within the atlas's cells).
            uint32_t icon = 0;
            float aspect = 1.0f;
            if (!style.icon.empty() && options.icons)
                if (const auto got = options.icons->indexed(style.icon);
                    got && got->first < shader::kMeshIconCells * shader::kMeshIconCells && got->second->height > 0) {
                    icon = got->first + 1;
                    aspect = float(got->second->width) / float(got->second->height);
                }
            for (size_t c = 0; c < f.coords.size(); ++c) {
                const glm::vec3 at = w.relative(ell.toEcef(f.coords[c].x, f.coords[c].y, surfaceAt(c)));
                w.chunk.markers.push_back({at, packColor(style.color, style.opacity), float(style.iconSizePx), id, icon, aspect,
                                           glm::vec3(float(style.iconNearM), float(style.iconFarM), float(style.iconFarScale)), at,
                                           glm::vec2(0.0f)});
            }
        }
        for (size_t p = 0; f.kind == GeometryKind::Polygons && p < f.polygons.size(); ++p) {
            const LocalPlane plane(f.coords[f.parts[f.polygons[p]]].x, f.coords[f.parts[f.polygons[p]]].y);
            in.plane.clear();
            in.surface.clear();
            in.ground.clear();
            in.starts.clear();
            for (uint32_t r = f.polygons[p]; r < f.polygonEnd(p); ++r) {
                // Rings without their closing point (the triangulation wants them open).
                uint32_t begin = f.parts[r], end = f.partEnd(r);
                if (end - begin > 1 && f.coords[end - 1] == f.coords[begin]) --end;
                if (end - begin < 3) continue;
                in.starts.push_back(uint32_t(in.plane.size()));
                for (uint32_t c = begin; c < end; ++c) {
                    in.plane.push_back(plane.to(f.coords[c]));
                    in.surface.push_back(surfaceAt(c));
                    in.ground.push_back(g[c]);
                }
            }
            if (in.starts.empty()) continue;
            TriangulateStats stats;
            auto tris = triangulate(in.plane, in.starts, in.plane.size(), &stats);
            if (!tris) {
                if (out.warnings.size() < 20)
                    out.warnings.push_back(layer.data.name + ": feature " + std::to_string(f.fid) + ": no roof: " + tris.message());
                continue;
            }
            out.forced += stats.forced;
            if (extruded) {
                const double roof = *std::max_element(in.surface.begin(), in.surface.end()) + height;
                const double low = *std::min_element(in.ground.begin(), in.ground.end());
                const double bottom = std::min(low, roof) - std::max(kSkirtMetres, 0.1 * (roof - low));
                emitSolid(w, in, plane, *tris, roof, bottom, color, id);
            } else {
                emitSurface(w, in, plane, *tris, color, id);
            }
        }
        const size_t segments = w.chunk.segments.size() - segmentsBefore, markers = w.chunk.markers.size() - markersBefore;
        if (w.chunk.vertices.size() > verticesBefore || segments > 0 || markers > 0) ++out.features;
        out.triangles += (w.chunk.indices.size() + w.chunk.translucent.size() - indicesBefore) / 3;
        out.segments += segments;
        out.markers += markers;
    }
    // Bounding spheres; chunks left empty are dropped.
    std::vector<MeshChunk> kept;
    for (size_t c = 0; c < out.chunks.size(); ++c) {
        MeshChunk& chunk = out.chunks[c];
        if (chunk.empty()) continue;
        chunk.center = chunk.origin + 0.5 * (bounds[c].first + bounds[c].second);
        chunk.radius = 0.5 * glm::length(bounds[c].second - bounds[c].first);
        kept.push_back(std::move(chunk));
    }
    out.chunks = std::move(kept);
    return out;
}

}  // namespace orbis::vector
