#include "layers/vector/VectorReader.h"

#include "base/Secrets.h"
#include "layers/vector/LonLatGeometry.h"
#include "layers/vector/VectorFeature.h"
#include "layers/vector/VectorOgr.h"

#include <ogrsf_frmts.h>

#include <filesystem>
#include <memory>
#include <string>
#include <unordered_map>

namespace orbis::vector {
namespace {

using detail::GdalErrorScope;

/// An ExecuteSQL result set, released through its dataset.
struct SqlResult {
    GDALDataset* dataset = nullptr;
    OGRLayer* layer = nullptr;
    SqlResult() = default;
    SqlResult(const SqlResult&) = delete;
    SqlResult& operator=(const SqlResult&) = delete;
    ~SqlResult() {
        if (layer) dataset->ReleaseResultSet(layer);
    }
};

/// How far a read has come across layers (the total limits are per read).
struct ReadBudget {
    const VectorLimits& limits;
    const std::function<bool(Feature&)>& shape;   ///< VectorReadOptions::shape
    uint64_t features = 0, vertices = 0;
    bool exhausted = false;
};

class LayerReader {
public:
    /// `datasetStyles`: the source's named styles (KML's shared styles), may be null.
    LayerReader(VectorLayer& out, ReadBudget& budget, OGRStyleTable* datasetStyles)
        : out_(out), budget_(budget), warningCount_(out.warnings.size()), datasetStyles_(datasetStyles) {}

    void warn(std::string text) {
        ++warningCount_;
        if (out_.warnings.size() < budget_.limits.maxWarnings) out_.warnings.push_back(std::move(text));
    }

    void read(OGRLayer& layer, OGRCoordinateTransformation* transform) {
        layer.ResetReading();
        std::unique_ptr<OGRFeature> feature;
        std::vector<LonLatBounds> boxes;
        if (budget_.exhausted) warn("not read: the limits of this read were reached in an earlier layer");
        while (!budget_.exhausted) {
            feature.reset(layer.GetNextFeature());
            if (!feature) break;
            if (budget_.features >= budget_.limits.maxFeatures) {
                warn("reading stopped at feature " + std::to_string(feature->GetFID()) + ": the limit of " +
                     std::to_string(budget_.limits.maxFeatures) + " features was reached");
                budget_.exhausted = true;
                break;
            }
            ++budget_.features;
            ++out_.featuresRead;
            auto converted = detail::convertFeature(*feature, transform, budget_.limits.maxVerticesPerFeature);
            if (const int32_t style = styleOf(*feature, layer); style >= 0)
                for (Feature& f : converted.features) f.style = style;
            take(std::move(converted), boxes);
        }
        out_.bounds = coverBounds(boxes);
        if (warningCount_ > out_.warnings.size())
            out_.warnings.push_back(std::to_string(warningCount_ - out_.warnings.size()) + " more warnings not listed");
    }

private:
    /// The feature's own style string ("@name": a named style of the layer or the source),
    /// read once per distinct string.
    int32_t styleOf(OGRFeature& feature, OGRLayer& layer) {
        const char* text = feature.GetStyleString();
        if (!text || !*text) return -1;
        std::string style = text;
        if (style[0] == '@') {
            const char* named = nullptr;
            if (OGRStyleTable* table = layer.GetStyleTable()) named = table->Find(style.c_str() + 1);
            if (!named && datasetStyles_) named = datasetStyles_->Find(style.c_str() + 1);
            if (!named) return -1;
            style = named;
        }
        if (auto it = styleIndex_.find(style); it != styleIndex_.end()) return it->second;
        SourceStyle parsed = parseOgrStyle(style);
        const int32_t index = parsed.empty() ? -1 : int32_t(out_.styles.size());
        if (index >= 0) out_.styles.push_back(std::move(parsed));
        styleIndex_.emplace(std::move(style), index);
        return index;
    }

    void take(detail::ConvertedFeature converted, std::vector<LonLatBounds>& boxes) {
        if (!converted.skipped.empty()) {
            ++out_.featuresSkipped;
            warn("skipped " + converted.skipped);
            return;
        }
        if (budget_.shape)
            std::erase_if(converted.features, [&](Feature& f) { return !budget_.shape(f); });
        if (converted.features.empty()) return;
        uint64_t vertices = 0;
        for (const Feature& f : converted.features) vertices += f.coords.size();
        if (budget_.vertices + vertices > budget_.limits.maxTotalVertices) {
            ++out_.featuresSkipped;
            warn("reading stopped at feature " + std::to_string(converted.features[0].fid) + ": the limit of " +
                 std::to_string(budget_.limits.maxTotalVertices) + " vertices in all was reached");
            budget_.exhausted = true;
            return;
        }
        budget_.vertices += vertices;
        out_.vertexCount += vertices;
        for (Feature& f : converted.features) {
            boxes.push_back(f.bounds);
            out_.features.push_back(std::move(f));
        }
    }

    VectorLayer& out_;
    ReadBudget& budget_;
    size_t warningCount_ = 0;
    OGRStyleTable* datasetStyles_ = nullptr;
    std::unordered_map<std::string, int32_t> styleIndex_;
};

/// `filter` names the where filter or SQL statement for errors that only show when reading
/// (SQLite-based drivers check a filter at the first feature).
/// Restricts the layer to the features near `within` (lon/lat), in the layer's CRS.
Result<void> applyWithin(OGRLayer& layer, const std::string& source, const detail::LayerCrs& crs,
                         const std::optional<LonLatBounds>& within) {
    if (!within) {
        layer.SetSpatialFilter(nullptr);
        return {};
    }
    double minX = within->west, minY = within->south, maxX = within->east, maxY = within->north;
    if (crs.transform) {
        std::unique_ptr<OGRCoordinateTransformation> inverse(crs.transform->GetInverse());
        GdalErrorScope errors;
        if (!inverse || !inverse->TransformBounds(within->west, within->south, within->east, within->north, &minX, &minY, &maxX,
                                                  &maxY, 21))
            return makeError(source + ": layer '" + layer.GetName() + "': the box to read cannot be put in its CRS " + crs.crs +
                             " (" + errors.message("PROJ failed") + ")");
    }
    layer.SetSpatialFilterRect(minX, minY, maxX, maxY);
    return {};
}

Result<VectorLayer> readLayer(OGRLayer& layer, const std::string& source, const std::string& filter, ReadBudget& budget,
                              OGRStyleTable* datasetStyles, const std::optional<LonLatBounds>& within) {
    VectorLayer out;
    out.name = layer.GetName();
    out.geometryType = OGRGeometryTypeToName(layer.GetGeomType());
    out.fields = detail::readFields(*layer.GetLayerDefn());
    auto crs = detail::layerCrs(layer, source);
    if (!crs) return crs.error();
    out.crs = crs->crs;
    out.crsName = crs->crsName;
    if (!crs->warning.empty()) out.warnings.push_back(crs->warning);
    if (auto ok = applyWithin(layer, source, *crs, within); !ok) return ok.error();
    GdalErrorScope errors;   // a driver's complaints about single features stay out of the log
    LayerReader(out, budget, datasetStyles).read(layer, crs->transform.get());
    if (errors.failed() && out.featuresRead == 0)
        return makeError(source + ": layer '" + out.name + "': cannot read its features" +
                         (filter.empty() ? "" : " with \"" + filter + "\"") + " (" + errors.message() + ")");
    return out;
}

Result<void> checkOptions(const VectorReadOptions& o) {
    if (const auto& w = o.within;
        w && !(w->west < w->east && w->south < w->north && w->west >= -180.0 && w->east <= 180.0 && w->south >= -90.0 && w->north <= 90.0))
        return makeError(redactSecrets(o.source) + ": the box to read must have west < east within -180..180 and south < north within -90..90");
    if (!o.sql.empty() && !o.layers.empty())
        return makeError(redactSecrets(o.source) + ": give either an SQL statement or layer names, not both");
    if (!o.sql.empty() && !o.where.empty())
        return makeError(redactSecrets(o.source) + ": give either an SQL statement or a where filter, not both");
    if (auto ok = globe::checkHttpAuth(o.httpAuth); !ok) return makeError(redactSecrets(o.source) + ": " + ok.message());
    return {};
}

Result<std::vector<OGRLayer*>> chooseLayers(GDALDataset& dataset, const VectorReadOptions& o) {
    std::vector<OGRLayer*> layers;
    if (o.layers.empty()) {
        for (int i = 0; i < dataset.GetLayerCount(); ++i) layers.push_back(dataset.GetLayer(i));
        return layers;
    }
    for (const std::string& name : o.layers) {
        OGRLayer* layer = dataset.GetLayerByName(name.c_str());
        if (!layer) {
            std::string known;
            for (int i = 0; i < dataset.GetLayerCount() && i < 20; ++i)
                known.append(known.empty() ? "" : ", ").append(dataset.GetLayer(i)->GetName());
            return makeError(redactSecrets(o.source) + ": no layer '" + name + "' (layers: " + (known.empty() ? "none" : known) + ")");
        }
        layers.push_back(layer);
    }
    return layers;
}

Result<void> applyWhere(OGRLayer& layer, const VectorReadOptions& o) {
    GdalErrorScope errors;
    if (layer.SetAttributeFilter(o.where.empty() ? nullptr : o.where.c_str()) == OGRERR_NONE) return {};
    return makeError(redactSecrets(o.source) + ": layer '" + layer.GetName() + "': bad where filter \"" + o.where + "\" (" +
                     errors.message("OGR rejected it") + ")");
}

Result<VectorData> readSql(GDALDataset& dataset, const VectorReadOptions& o) {
    SqlResult result;
    result.dataset = &dataset;
    {
        GdalErrorScope errors;
        result.layer = dataset.ExecuteSQL(o.sql.c_str(), nullptr, "OGRSQL");
        if (!result.layer) {
            const std::string why = errors.message("");
            return makeError(redactSecrets(o.source) + ": bad SQL statement \"" + o.sql + "\" (" +
                             (why.empty() ? "it selects no layer" : why) + ")");
        }
    }
    ReadBudget budget{o.limits, o.shape};
    auto layer = readLayer(*result.layer, redactSecrets(o.source), o.sql, budget, dataset.GetStyleTable(), o.within);
    if (!layer) return layer.error();
    VectorData data;
    data.source = o.source;
    data.layers.push_back(std::move(*layer));
    return data;
}

LayerSummary summarize(OGRLayer& layer, const std::string& source) {
    LayerSummary out;
    out.name = layer.GetName();
    out.fields = detail::readFields(*layer.GetLayerDefn());
    out.featureCount = layer.GetFeatureCount(TRUE);
    auto crs = detail::layerCrs(layer, source);
    if (const auto b = detail::layerExtent(layer, crs ? crs->transform.get() : nullptr))
        out.bounds = LonLatBounds{b->west, b->south, b->east < b->west ? b->east + 360.0 : b->east, b->north, false};
    return out;
}

}  // namespace

Result<std::vector<LayerSummary>> summarizeVector(const VectorReadOptions& options) {
    if (auto ok = checkOptions(options); !ok) return ok.error();
    const globe::ScopedHttpAuth auth(options.httpAuth);
    auto dataset = detail::openVectorSource(options.source);
    if (!dataset) return dataset.error();
    GdalErrorScope quiet;
    std::vector<LayerSummary> out;
    if (!options.sql.empty()) {
        SqlResult result;
        result.dataset = dataset->get();
        result.layer = (*dataset)->ExecuteSQL(options.sql.c_str(), nullptr, "OGRSQL");
        if (!result.layer) return makeError(redactSecrets(options.source) + ": bad SQL statement \"" + options.sql + "\" (" + quiet.message("it selects no layer") + ")");
        out.push_back(summarize(*result.layer, redactSecrets(options.source)));
        return out;
    }
    auto layers = chooseLayers(**dataset, options);
    if (!layers) return layers.error();
    for (OGRLayer* layer : *layers) {
        if (auto ok = applyWhere(*layer, options); !ok) return ok.error();
        out.push_back(summarize(*layer, redactSecrets(options.source)));
    }
    return out;
}

std::optional<size_t> findField(std::span<const FieldInfo> fields, const std::string& name) {
    for (size_t i = 0; i < fields.size(); ++i)
        if (fields[i].name == name) return i;
    return std::nullopt;
}

std::string fieldNames(std::span<const FieldInfo> fields) {
    std::string out;
    for (const FieldInfo& f : fields) out += (out.empty() ? "" : ", ") + f.name;
    return out.empty() ? "none" : out;
}

namespace {

/// A file's size and modification time, to tell when it was written since it was opened;
/// zero for what is not a file (a connection string, a URL).
std::pair<uintmax_t, int64_t> fileStamp(const std::string& source) {
    if (isConnectionString(source)) return {0, 0};
    std::error_code ec;
    const uintmax_t size = std::filesystem::file_size(source, ec);
    if (ec) return {0, 0};
    const auto time = std::filesystem::last_write_time(source, ec);
    return {size, ec ? 0 : int64_t(time.time_since_epoch().count())};
}

/// This thread's dataset, kept open for the same source's next read.
struct KeptDataset {
    std::string source;
    std::pair<uintmax_t, int64_t> stamp;
    detail::DatasetPtr dataset;
};
thread_local KeptDataset kept;

/// The dataset to read from: opened for this read (`owned`), or the kept one (opened again
/// when the file was written since it was opened: a source that changes is read as it is now).
Result<GDALDataset*> datasetFor(const VectorReadOptions& options, detail::DatasetPtr& owned) {
    const auto stamp = options.reuseDataset ? fileStamp(options.source) : std::pair<uintmax_t, int64_t>{};
    if (options.reuseDataset && kept.dataset && kept.source == options.source && kept.stamp == stamp) return kept.dataset.get();
    if (options.reuseDataset) kept.dataset.reset();
    auto dataset = detail::openVectorSource(options.source);
    if (!dataset) return dataset.error();
    if (!options.reuseDataset) {
        owned = std::move(*dataset);
        return owned.get();
    }
    kept.dataset = std::move(*dataset);
    kept.source = options.source;
    kept.stamp = stamp;
    return kept.dataset.get();
}

Result<VectorData> readVectorOnce(const VectorReadOptions& options) {
    if (auto ok = checkOptions(options); !ok) return ok.error();
    const globe::ScopedHttpAuth auth(options.httpAuth);
    detail::DatasetPtr owned;
    auto dataset = datasetFor(options, owned);
    if (!dataset) return dataset.error();
    if (!options.sql.empty()) return readSql(**dataset, options);
    auto layers = chooseLayers(**dataset, options);
    if (!layers) return layers.error();
    VectorData data;
    data.source = options.source;
    ReadBudget budget{options.limits, options.shape};
    for (OGRLayer* layer : *layers) {
        if (auto ok = applyWhere(*layer, options); !ok) return ok.error();
        auto read = readLayer(*layer, redactSecrets(options.source), options.where, budget, (*dataset)->GetStyleTable(), options.within);
        if (!read) return read.error();
        data.layers.push_back(std::move(*read));
    }
    return data;
}

}  // namespace

Result<VectorData> readVector(const VectorReadOptions& options) {
    const bool reusing = options.reuseDataset && kept.dataset && kept.source == options.source;
    Result<VectorData> read = readVectorOnce(options);
    if (!read && options.reuseDataset) {
        // A kept dataset that failed may hold a broken connection (the server restarted since
        // it was opened): once more on a new one, and the next read opens it again if that fails.
        kept.dataset.reset();
        if (reusing) read = readVectorOnce(options);
        if (!read) kept.dataset.reset();
    }
    return read;
}

}  // namespace orbis::vector
