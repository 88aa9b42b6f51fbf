#pragma once
// A client of one OGC WPS 1.0.0 server over HTTP (a ProcessingClient) (GDAL's, so its timeouts and its
// GDAL_HTTP_AUTH / GDAL_HTTP_USERPWD / GDAL_HTTP_HEADERS settings apply): the capabilities, a
// process's description, an Execute (POST) synchronous or stored with status updates, the status
// of a job polled with back-off until it ends (progress reported, stopped by the caller), and an
// output fetched by reference. Each call blocks: run them on a worker thread (the Processes
// panel's jobs). Every problem is an error naming the server's address (secrets removed) and
// what went wrong; answers larger than kMaxDocumentBytes are refused.
//
//   WpsClient wps("http://127.0.0.1:5000/wps");
//   auto d = wps.describe("viewshed");
//   auto job = wps.execute(*d, inputs, outputs, /*async=*/d->storeSupported);
//   auto done = wps.wait(*job, [](const ExecuteResponse& r) { show(r.percent); return keepGoing; });

#include "formats/wps/ProcessingClient.h"
#include "formats/wps/WpsDocuments.h"

#include <functional>
#include <string>

namespace orbis::wps {


class WpsClient final : public ProcessingClient {
public:
    /// `url`: the service's address ("http://host:port/wps", with or without '?' and parameters).
    explicit WpsClient(std::string url, double timeoutSeconds = 30.0);

    const std::string& url() const override { return url_; }
    const char* protocol() const override { return "OGC WPS 1.0.0"; }

    Result<Capabilities> capabilities() const override;
    Result<ProcessDescription> describe(const std::string& process) const override;
    /// Checks the inputs against `process` first (checkInputs), then POSTs the Execute request.
    Result<ExecuteResponse> execute(const ProcessDescription& process, std::span<const InputValue> inputs,
                                    std::span<const OutputRequest> outputs, bool async) const override;
    /// The job's status document again (its statusLocation).
    Result<ExecuteResponse> status(const ExecuteResponse& job) const override;
    /// Polls `job` until it has succeeded or failed; `progress` sees each status and returns false
    /// to stop waiting (the job is left to the server: WPS 1.0.0 has no dismiss). A job that
    /// failed is a result, not an error; an error is a server that stopped answering (three polls
    /// in a row without a readable status: one caught half written is polled again), a stop, or
    /// the timeout.
    Result<ExecuteResponse> wait(ExecuteResponse job, const std::function<bool(const ExecuteResponse&)>& progress = {},
                                 const WaitOptions& options = {}) const override;
    /// An output given by reference, whole (at most kMaxDocumentBytes).
    Result<std::string> fetch(const std::string& url) const override;

private:
    Result<std::string> get(const std::string& url) const;
    Result<std::string> post(const std::string& url, const std::string& body) const;
    Result<std::string> request(const std::string& url, const std::string* body) const;

    std::string url_;
    std::string shown_;   ///< url_ without secrets, for messages
    double timeoutSeconds_;
};

}  // namespace orbis::wps
