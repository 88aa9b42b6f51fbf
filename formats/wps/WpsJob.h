#pragma once
// One processing job run in the background (through ProcessingClient, any protocol), as the viewer's Processes panel starts it: the
// Execute sent (stored with status updates where the process allows, else synchronous), the
// status polled with back-off, the progress and the server's message readable at any time, a
// stop that ends the wait (WPS 1.0.0 has no dismiss: the server finishes on its own), and the
// outputs saved into a folder (references fetched), each with the kind of layer or panel that
// shows it: a raster (GeoTIFF) as an overlay, vectors (GeoJSON, GML, KML) as a vector layer, a
// table (CSV) as a plot, a literal as text. No Vulkan, no ImGui.
//
//   WpsJob job(url, description, inputs, "/tmp/results");   // starts its thread
//   while (job.snapshot().running) draw(job.snapshot().percent);
//   for (const SavedOutput& o : job.snapshot().outputs) show(o);

#include "formats/wps/ProcessingClient.h"
#include "formats/wps/WpsDocuments.h"

#include <atomic>
#include <chrono>
#include <filesystem>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace orbis::wps {

/// What shows an output.
enum class OutputKind { Raster, Vector, Table, Literal, BoundingBox, Other };
const char* toString(OutputKind kind);

/// The kind for a complex output's MIME type (image/tiff -> Raster, geo+json, gml, kml ->
/// Vector, text/csv -> Table), or Literal / BoundingBox for those outputs.
OutputKind kindOf(const OutputValue& output);
/// A file name extension for a MIME type (".tif", ".geojson", ".csv", ".xml", ".png", ".dat").
std::string extensionFor(const std::string& mimeType);
/// The MIME type a file sent as complex input goes as, from its extension.
std::string mimeTypeFor(const std::filesystem::path& file);

/// An output as the job keeps it.
struct SavedOutput {
    std::string identifier, title;
    OutputKind kind = OutputKind::Other;
    std::string text;               ///< a literal's value (with its unit), or a box as "W, S, E, N (CRS)"
    std::filesystem::path file;     ///< complex outputs: where the data was written
    std::string reference;          ///< the server's URL for it, when given by reference
    std::string mimeType;
    size_t bytes = 0;
};

/// Writes the job's outputs into `folder` (made when missing) as IDENTIFIER.EXT, fetching those
/// given by reference; literals and boxes become text. Errors name the output and the file.
Result<std::vector<SavedOutput>> saveOutputs(const ProcessingClient& client, const ExecuteResponse& response,
                                             const std::filesystem::path& folder);

class WpsJob {
public:
    struct Snapshot {
        JobState state = JobState::Accepted;
        bool running = true;        ///< false once it succeeded, failed, was stopped or lost
        bool stopped = false;       ///< stop() ended the wait
        int percent = 0;
        std::string message;        ///< the server's status text, or what went wrong
        std::vector<SavedOutput> outputs;   ///< once it succeeded
        double seconds = 0.0;       ///< since the start (until the end)
    };

    /// Starts the job on its own thread. Inputs are checked against `process` first (a bad
    /// one ends the job at once with the message). `folder` receives the outputs. The job is
    /// stored and polled where the process allows, unless `synchronous` (the answer awaited on
    /// the request itself: no progress, no stop but the request's timeout).
    WpsJob(std::string url, ProcessDescription process, std::vector<InputValue> inputs, std::filesystem::path folder,
           WaitOptions wait = {}, bool synchronous = false);
    /// Stops waiting and joins the thread (a request under way ends within its timeout).
    ~WpsJob();
    WpsJob(const WpsJob&) = delete;
    WpsJob& operator=(const WpsJob&) = delete;

    const std::string& url() const { return url_; }
    const ProcessDescription& process() const { return process_; }
    const std::vector<InputValue>& inputs() const { return inputs_; }
    const std::filesystem::path& folder() const { return folder_; }

    /// Where the job stands now. Any thread.
    Snapshot snapshot() const;
    /// Ends the wait at the next poll; the job is reported as stopped. Any thread.
    void stop() { stop_ = true; }
    /// Blocks until the job has ended (tests, the command line).
    void join();

private:
    void run();
    void update(const std::function<void(Snapshot&)>& change);

    std::string url_;
    ProcessDescription process_;
    std::vector<InputValue> inputs_;
    std::filesystem::path folder_;
    WaitOptions wait_;
    bool synchronous_ = false;
    std::chrono::steady_clock::time_point start_;
    mutable std::mutex mutex_;
    Snapshot snapshot_;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

/// A table from a CSV output: a header row of names, then rows of numbers (an empty or
/// non-numeric cell is NaN). At most kMaxTableRows rows and kMaxTableColumns columns; errors
/// name `source` and the line.
struct Table {
    std::vector<std::string> columns;
    std::vector<std::vector<double>> values;   ///< per column, one per row
    size_t rows() const { return values.empty() ? 0 : values.front().size(); }
};
inline constexpr size_t kMaxTableRows = 1000000;
inline constexpr size_t kMaxTableColumns = 256;
Result<Table> parseTable(std::string_view text, const std::string& source);

}  // namespace orbis::wps
