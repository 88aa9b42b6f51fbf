#pragma once
// What the viewer asks of a processing server, whatever its protocol: the processes it offers,
// one's description, an Execute (synchronous or as a job with a status to poll), a job's
// status, a wait with progress and a stop, and an output fetched by reference, all in the
// protocol-neutral structures of WpsDocuments.h. The Processes panel and WpsJob talk to this
// interface only, so that a WPS 2.0 or an OGC API - Processes (JSON) client is added beside
// WpsClient (the OGC WPS 1.0.0 one) and chosen by connectProcessing() without changing them.

#include "formats/wps/WpsDocuments.h"

#include <functional>
#include <memory>
#include <span>
#include <string>

namespace orbis::wps {

struct WaitOptions {
    double firstDelaySeconds = 0.2;   ///< then doubled after each poll
    double maxDelaySeconds = 2.0;
    double timeoutSeconds = 3600.0;   ///< from the first poll
};

class ProcessingClient {
public:
    virtual ~ProcessingClient() = default;
    /// The server's address, as given.
    virtual const std::string& url() const = 0;
    /// "OGC WPS 1.0.0", ... for the panel and messages.
    virtual const char* protocol() const = 0;
    virtual Result<Capabilities> capabilities() const = 0;
    virtual Result<ProcessDescription> describe(const std::string& process) const = 0;
    /// Checks the inputs against `process` first (checkInputs), then sends the request.
    virtual Result<ExecuteResponse> execute(const ProcessDescription& process, std::span<const InputValue> inputs,
                                            std::span<const OutputRequest> outputs, bool async) const = 0;
    virtual Result<ExecuteResponse> status(const ExecuteResponse& job) const = 0;
    /// Polls `job` until it has succeeded or failed; `progress` returns false to stop waiting.
    virtual Result<ExecuteResponse> wait(ExecuteResponse job, const std::function<bool(const ExecuteResponse&)>& progress = {},
                                         const WaitOptions& options = {}) const = 0;
    /// An output given by reference, whole (at most kMaxDocumentBytes).
    virtual Result<std::string> fetch(const std::string& url) const = 0;
};

/// The client for a server's address. Today every http(s) address is an OGC WPS 1.0.0 server
/// (WpsClient); this is where WPS 2.0 and OGC API - Processes clients are chosen when they are
/// written (by what the address or the server's answer says). An error for an address that is
/// not http(s).
Result<std::unique_ptr<ProcessingClient>> connectProcessing(const std::string& url, double timeoutSeconds = 30.0);

}  // namespace orbis::wps
