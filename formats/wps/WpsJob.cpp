#include "formats/wps/WpsJob.h"

#include "base/CsvText.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>

namespace orbis::wps {
namespace fs = std::filesystem;

namespace {

bool has(const std::string& text, const char* part) { return text.find(part) != std::string::npos; }

}  // namespace

const char* toString(OutputKind kind) {
    switch (kind) {
        case OutputKind::Raster: return "raster";
        case OutputKind::Vector: return "vector";
        case OutputKind::Table: return "table";
        case OutputKind::Literal: return "literal";
        case OutputKind::BoundingBox: return "bounding box";
        case OutputKind::Other: break;
    }
    return "data";
}

OutputKind kindOf(const OutputValue& output) {
    if (output.kind == DataKind::Literal) return OutputKind::Literal;
    if (output.kind == DataKind::BoundingBox) return OutputKind::BoundingBox;
    const std::string mime = lowerAscii(output.format.mimeType);
    if (has(mime, "tiff") || has(mime, "x-netcdf") || has(mime, "jp2")) return OutputKind::Raster;
    if (has(mime, "json") || has(mime, "gml") || has(mime, "kml")) return OutputKind::Vector;
    if (has(mime, "csv")) return OutputKind::Table;
    return OutputKind::Other;
}

std::string extensionFor(const std::string& mimeType) {
    const std::string mime = lowerAscii(mimeType);
    if (has(mime, "tiff")) return ".tif";
    if (has(mime, "json")) return ".geojson";
    if (has(mime, "csv")) return ".csv";
    if (has(mime, "kml")) return ".kml";
    if (has(mime, "gml")) return ".gml";
    if (has(mime, "xml")) return ".xml";
    if (has(mime, "png")) return ".png";
    return ".dat";
}

std::string mimeTypeFor(const fs::path& file) {
    const std::string e = lowerAscii(file.extension().string());
    if (e == ".geojson" || e == ".json") return "application/geo+json";
    if (e == ".gml") return "application/gml+xml";
    if (e == ".kml") return "application/vnd.google-earth.kml+xml";
    if (e == ".csv") return "text/csv";
    if (e == ".tif" || e == ".tiff") return "image/tiff; subtype=geotiff";
    return "text/plain";
}

Result<std::vector<SavedOutput>> saveOutputs(const ProcessingClient& client, const ExecuteResponse& response, const fs::path& folder) {
    std::vector<SavedOutput> saved;
    for (const OutputValue& o : response.outputs) {
        SavedOutput s{.identifier = o.identifier, .title = o.title, .kind = kindOf(o), .reference = o.reference, .mimeType = o.format.mimeType};
        if (o.kind == DataKind::Literal) {
            s.text = o.value + (o.uom.empty() ? "" : " " + o.uom);
        } else if (o.kind == DataKind::BoundingBox) {
            char text[160];
            std::snprintf(text, sizeof text, "%.6f, %.6f, %.6f, %.6f", o.bbox[0], o.bbox[1], o.bbox[2], o.bbox[3]);
            s.text = std::string(text) + (o.crs.empty() ? "" : " (" + o.crs + ")");
        } else {
            std::string data = o.value;
            if (!o.reference.empty()) {
                auto fetched = client.fetch(o.reference);
                if (!fetched) return makeError("output \"" + o.identifier + "\": " + fetched.message());
                data = std::move(*fetched);
            }
            std::error_code ec;
            fs::create_directories(folder, ec);
            s.file = folder / (o.identifier + extensionFor(o.format.mimeType));
            std::ofstream out(s.file, std::ios::binary);
            out << data;
            out.close();
            if (!out) return makeError("output \"" + o.identifier + "\": " + s.file.string() + " cannot be written");
            s.bytes = data.size();
            if (s.kind == OutputKind::Table) s.text = data.substr(0, std::min<size_t>(data.size(), 256));
        }
        saved.push_back(std::move(s));
    }
    return saved;
}

WpsJob::WpsJob(std::string url, ProcessDescription process, std::vector<InputValue> inputs, fs::path folder, WaitOptions wait,
               bool synchronous)
    : url_(std::move(url)), process_(std::move(process)), inputs_(std::move(inputs)), folder_(std::move(folder)), wait_(wait),
      synchronous_(synchronous),
      start_(std::chrono::steady_clock::now()) {
    snapshot_.message = "sending the request";
    thread_ = std::thread([this] { run(); });
}

WpsJob::~WpsJob() {
    stop_ = true;
    join();
}

void WpsJob::join() {
    if (thread_.joinable()) thread_.join();
}

WpsJob::Snapshot WpsJob::snapshot() const {
    std::lock_guard lock(mutex_);
    Snapshot s = snapshot_;
    if (s.running) s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    return s;
}

void WpsJob::update(const std::function<void(Snapshot&)>& change) {
    std::lock_guard lock(mutex_);
    change(snapshot_);
}

void WpsJob::run() {
    const auto end = [this](JobState state, std::string message, std::vector<SavedOutput> outputs = {}) {
        update([&](Snapshot& s) {
            s.state = state;
            s.running = false;
            s.stopped = stop_;
            if (state == JobState::Succeeded) s.percent = 100;
            s.message = std::move(message);
            s.outputs = std::move(outputs);
            s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
        });
    };
    auto connected = connectProcessing(url_);
    if (!connected) {
        end(JobState::Failed, connected.message());
        return;
    }
    const ProcessingClient& client = **connected;
    std::vector<OutputRequest> wanted;
    for (const Parameter& o : process_.outputs) wanted.push_back({.identifier = o.identifier, .asReference = o.kind == DataKind::Complex});
    const bool async = process_.storeSupported && process_.statusSupported && !synchronous_;
    auto response = client.execute(process_, inputs_, wanted, async);
    if (response && async && !response->finished()) {
        response = client.wait(*response, [this](const ExecuteResponse& r) {
            update([&](Snapshot& s) {
                s.state = r.state;
                s.percent = r.percent;
                s.message = r.message;
            });
            return !stop_;
        }, wait_);
    }
    if (!response) {
        end(JobState::Failed, stop_ ? "stopped waiting (the server may still finish it)" : response.message());
        return;
    }
    if (response->state == JobState::Failed) {
        end(JobState::Failed, process_.identifier + " failed: " + response->message);
        return;
    }
    update([](Snapshot& s) { s.message = "fetching the outputs"; });
    auto saved = saveOutputs(client, *response, folder_);
    if (!saved) {
        end(JobState::Failed, saved.message());
        return;
    }
    end(JobState::Succeeded, response->message.empty() ? "done" : response->message, std::move(saved).value());
}

Result<Table> parseTable(std::string_view text, const std::string& source) {
    Table table;
    size_t pos = 0, line = 0;
    while (pos < text.size()) {
        const std::string_view row = csv::nextLine(text, pos);
        ++line;
        if (csv::skipLine(row)) continue;
        const auto cells = csv::splitLine(row, ',');
        if (table.columns.empty()) {
            if (cells.size() > kMaxTableColumns)
                return makeError(source + ": line " + std::to_string(line) + ": more than " + std::to_string(kMaxTableColumns) + " columns");
            table.columns = cells;
            table.values.resize(cells.size());
            continue;
        }
        if (cells.size() != table.columns.size())
            return makeError(source + ": line " + std::to_string(line) + ": " + std::to_string(cells.size()) + " cells where the header names " +
                             std::to_string(table.columns.size()));
        if (table.rows() >= kMaxTableRows) return makeError(source + ": more than " + std::to_string(kMaxTableRows) + " rows");
        for (size_t i = 0; i < cells.size(); ++i) {
            const std::string& c = cells[i];
            double v = std::numeric_limits<double>::quiet_NaN();
            const auto [end, ec] = std::from_chars(c.data(), c.data() + c.size(), v);
            if (ec != std::errc() || end != c.data() + c.size() || !std::isfinite(v)) v = std::numeric_limits<double>::quiet_NaN();
            table.values[i].push_back(v);
        }
    }
    if (table.columns.empty()) return makeError(source + ": the table is empty");
    return table;
}

}  // namespace orbis::wps
