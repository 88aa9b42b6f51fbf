#pragma once
// OGC Web Processing Service 1.0.0 documents, as PyWPS 4.5 and other servers write them: what a
// server offers (GetCapabilities), what a process takes and gives (DescribeProcess: inputs with
// their types, allowed values and ranges, defaults, formats, CRSs; outputs), and where a job
// stands (ExecuteResponse: accepted, started with a percentage, succeeded with its outputs inline
// or by reference, failed with the server's reason). And the other way: the Execute request
// (XML, POST) for a process, its inputs (literal values, complex data inline or by reference,
// bounding boxes) and the outputs wanted, synchronous or stored with status updates; the inputs
// checked against the description first, each problem named. No Vulkan and no network: the
// documents only (fetching them is the client's part); the XML is read with GDAL's cpl_minixml.
//
// Written so that WPS 2.0 and OGC API - Processes (JSON) documents can be read into the same
// structures beside these functions: nothing here is specific to 1.0.0's XML but the parsers
// and executeRequest().

#include "base/Result.h"

#include <array>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace orbis::wps {

enum class DataKind { Literal, Complex, BoundingBox };

struct Format {
    std::string mimeType, encoding, schema;
};

struct ValueRange {
    double min = 0.0, max = 0.0;
    std::optional<double> spacing;
    std::string closure = "closed";   ///< closed | open | closed-open | open-closed
    bool contains(double v) const;
};

/// What a literal input or output takes.
struct LiteralDomain {
    std::string dataType;             ///< string | integer | float | double | boolean | ... ("" unknown)
    bool anyValue = true;             ///< else one of `values` or within one of `ranges`
    std::vector<std::string> values;
    std::vector<ValueRange> ranges;
    std::optional<std::string> defaultValue;
    std::string uom;                  ///< the default unit of measure, if any
};

/// One input or output of a process.
struct Parameter {
    std::string identifier, title, abstract;
    int minOccurs = 1, maxOccurs = 1;   ///< inputs only
    DataKind kind = DataKind::Literal;
    LiteralDomain literal;
    Format defaultFormat;               ///< complex
    std::vector<Format> formats;        ///< complex: every supported one (the default first)
    double maximumMegabytes = 0.0;      ///< complex inputs: 0 unknown
    std::string defaultCrs;             ///< bounding boxes
    std::vector<std::string> crss;
};

struct ProcessSummary {
    std::string identifier, title, abstract, version;
};

struct Capabilities {
    std::string title, abstract, version, provider;
    std::vector<ProcessSummary> processes;
    /// Where the operations are (the GET and POST addresses the server gives; may be empty).
    std::string describeGet, executeGet, executePost;
};

struct ProcessDescription {
    std::string identifier, title, abstract, version;
    bool storeSupported = false, statusSupported = false;   ///< asynchronous jobs possible
    std::vector<Parameter> inputs, outputs;
    const Parameter* input(std::string_view id) const;
    const Parameter* output(std::string_view id) const;
};

enum class JobState { Accepted, Started, Paused, Succeeded, Failed };
const char* toString(JobState state);

struct OutputValue {
    std::string identifier, title;
    DataKind kind = DataKind::Literal;
    std::string value;           ///< a literal's text, or complex data given inline (as sent)
    std::string dataType, uom;   ///< literals
    Format format;               ///< complex data, inline or by reference
    std::string reference;       ///< complex data by reference: the URL to fetch it from
    /// West, south, east, north (x before y, whatever the CRS's axis order: a box in EPSG:4326,
    /// whose corners are written latitude first, is read back as lon, lat).
    std::array<double, 4> bbox{0, 0, 0, 0};
    std::string crs;
};

struct ExecuteResponse {
    std::string processId;
    JobState state = JobState::Accepted;
    int percent = 0;               ///< 0..100 (100 when succeeded)
    std::string message;           ///< the status text, or the failure's exception text
    std::string statusLocation;    ///< where to poll (asynchronous jobs)
    std::string creationTime;
    std::vector<OutputValue> outputs;
    bool finished() const { return state == JobState::Succeeded || state == JobState::Failed; }
};

/// Bounds on what a document may hold: a server that sends more is refused, not followed.
inline constexpr size_t kMaxDocumentBytes = size_t(64) << 20;
inline constexpr size_t kMaxProcesses = 10000;
inline constexpr size_t kMaxParameters = 1000;      ///< inputs or outputs of one process
inline constexpr size_t kMaxAllowedValues = 100000; ///< values and ranges of one literal

/// The documents; `source` names where they came from in messages (a URL without secrets). An
/// ows:ExceptionReport is an error that quotes the server's code and text.
Result<Capabilities> parseCapabilities(std::string_view xml, const std::string& source);
Result<std::vector<ProcessDescription>> parseProcessDescriptions(std::string_view xml, const std::string& source);
Result<ExecuteResponse> parseExecuteResponse(std::string_view xml, const std::string& source);

/// One input value for an Execute request.
struct InputValue {
    std::string identifier;
    DataKind kind = DataKind::Literal;
    std::string value;       ///< a literal, or complex data sent inline (XML is embedded, other text escaped)
    Format format;           ///< complex: what `value` or `reference` is
    std::string reference;   ///< complex: a URL the server fetches instead of `value`
    std::array<double, 4> bbox{0, 0, 0, 0};   ///< west, south, east, north (x first; written in the CRS's axis order)
    std::string crs;         ///< bounding boxes
};

struct OutputRequest {
    std::string identifier;
    bool asReference = false;   ///< complex outputs: a URL to fetch instead of the data inline
    std::string mimeType;       ///< "" the default
};

/// Checks the inputs against the description: each identifier known, required ones given, no
/// more than maxOccurs of each, the right kind, literals of the data type (integers, numbers,
/// booleans) within the allowed values or ranges, complex formats among those supported, boxes
/// with lower <= upper; every problem in one message, naming the input.
Result<void> checkInputs(const ProcessDescription& process, std::span<const InputValue> inputs);

/// The Execute request (XML) for `process` with `inputs` and the outputs wanted (none: every
/// output, as the server's default). `async`: stored with status updates (the response comes at
/// once with a status location to poll).
std::string executeRequest(const std::string& process, std::span<const InputValue> inputs, std::span<const OutputRequest> outputs,
                           bool async);

/// `text` in ASCII lower case: MIME types, data types, identifiers and flags compared as the
/// standards say, whatever case a server writes them in.
std::string lowerAscii(std::string_view text);

/// A key-value-pair GET address: `base` (with or without '?' and earlier parameters) and the
/// parameters, percent-encoded.
std::string kvpUrl(const std::string& base, std::span<const std::pair<std::string, std::string>> parameters);

}  // namespace orbis::wps
