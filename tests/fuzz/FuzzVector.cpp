// Vector files: what Orbis does with the features OGR reads from a file someone else wrote (KML,
// GeoJSON, CSV with WKT, FlatGeobuf, GPX; the input's first byte picks the extension, the rest
// is the file): the conversion to lon/lat parts unwrapped across 180 with their poles, the source's
// own styles (OGR style strings), the features' times, the scene's style evaluated over the
// attributes, the cut into quadtree tiles, the simplification and the triangulation of every
// polygon. GDAL's own parsers are fuzzed by OSS-Fuzz; the limits keep one input bounded. (GML
// is left out: FuzzGdal.h.)
#include "globe/TileKey.h"
#include "layers/vector/FeatureClip.h"
#include "layers/vector/FeatureTime.h"
#include "layers/vector/Simplify.h"
#include "layers/vector/Triangulate.h"
#include "layers/vector/VectorReader.h"
#include "layers/vector/VectorStyle.h"
#include "tests/fuzz/FuzzGdal.h"

#include <unistd.h>

#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <string>

using namespace orbis::vector;

namespace {

void polygons(const Feature& f) {
    if (f.kind != GeometryKind::Polygons) return;
    for (size_t k = 0; k < f.polygons.size(); ++k) {
        std::vector<glm::dvec2> plane;
        std::vector<uint32_t> starts;
        for (size_t p = f.polygons[k]; p < f.polygonEnd(k) && p < f.parts.size(); ++p) {
            auto ring = f.part(p);
            if (ring.size() > 1 && ring.front() == ring.back()) ring = ring.first(ring.size() - 1);
            starts.push_back(uint32_t(plane.size()));
            for (const auto& c : ring) plane.emplace_back(c.x, c.y);
        }
        (void)triangulate(plane, starts, 4000);
    }
}

void tiles(const Feature& f) {
    const auto keys = tilesCovering(f, 2);
    size_t done = 0;
    for (const auto& key : keys) {
        if (++done > 16) break;
        if (auto clipped = clipFeature(f, key.extent())) {
            if (auto simple = simplifyFeature(*clipped, 0.5)) polygons(*simple);
        }
    }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size < 1) return 0;
    static constexpr std::array<const char*, 5> kinds{"kml", "geojson", "csv", "fgb", "gpx"};
    const std::string path = "/dev/shm/orbis-fuzz-vector-" + std::to_string(getpid()) + "." + kinds[data[0] % kinds.size()];
    if (FILE* f = std::fopen(path.c_str(), "wb")) {
        std::fwrite(data + 1, 1, size - 1, f);
        std::fclose(f);
    } else {
        return 0;
    }
    VectorReadOptions options;
    options.source = path;
    options.limits.maxVerticesPerFeature = 4000;
    options.limits.maxTotalVertices = 20000;
    options.limits.maxFeatures = 2000;
    auto read = readVector(options);
    (void)describeVectorJson(path);
    std::remove(path.c_str());
    if (!read) return 0;

    for (const VectorLayer& layer : read->layers) {
        (void)featureTimes(layer, {});
        // The scene's style names the layer's own fields: a label of two, a rule on the first.
        std::optional<VectorStyle> style;
        if (!layer.fields.empty()) {
            const std::string first = layer.fields.front().name, last = layer.fields.back().name;
            nlohmann::json spec = {{"width", 3},
                                   {"label", "{" + first + "} ({" + last + "})"},
                                   {"rules", {{{"when", {{first, "A"}}}, {"color", {1, 0, 0}}},
                                              {{"when", {{last, {1, 2}}}}, {"width", 8}}}}};
            if (auto s = VectorStyle::read(&spec, "fuzz.json", "/style"); s && s->bind(layer.fields, layer.name)) style = std::move(*s);
        }
        for (const Feature& f : layer.features) {
            const SourceStyle* own = f.style >= 0 && size_t(f.style) < layer.styles.size() ? &layer.styles[size_t(f.style)] : nullptr;
            if (style) (void)style->evaluate(f.attributes, own);
            polygons(f);
            tiles(f);
        }
    }
    return 0;
}
