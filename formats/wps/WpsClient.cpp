#include "formats/wps/WpsClient.h"

#include "base/Secrets.h"
#include "globe/GdalSetup.h"

#include <cpl_error.h>
#include <cpl_http.h>
#include <cpl_string.h>

#include <algorithm>
#include <chrono>
#include <thread>
#include <utility>
#include <vector>

namespace orbis::wps {
namespace {

/// Polls in a row whose status could not be read (a document caught half written) before the
/// wait gives up.
constexpr int kStatusRetries = 3;

}  // namespace

WpsClient::WpsClient(std::string url, double timeoutSeconds)
    : url_(std::move(url)), shown_(redactSecrets(url_)), timeoutSeconds_(std::clamp(timeoutSeconds, 1.0, 3600.0)) {}

Result<std::string> WpsClient::request(const std::string& url, const std::string* body) const {
    if (url.rfind("http://", 0) != 0 && url.rfind("https://", 0) != 0)
        return makeError(redactSecrets(url) + ": not an http(s) address");
    globe::configureGdal();
    const std::string timeout = "TIMEOUT=" + std::to_string(int(timeoutSeconds_));
    std::vector<std::string> options = {timeout, "MAX_RETRY=1", "RETRY_DELAY=1"};
    if (body) {
        options.push_back("POSTFIELDS=" + *body);
        options.push_back("HEADERS=Content-Type: text/xml; charset=UTF-8");
    }
    std::vector<const char*> list;
    for (const auto& o : options) list.push_back(o.c_str());
    list.push_back(nullptr);
    CPLErrorReset();
    CPLPushErrorHandler(CPLQuietErrorHandler);
    CPLHTTPResult* r = CPLHTTPFetch(url.c_str(), const_cast<char**>(list.data()));
    CPLPopErrorHandler();
    const std::string shown = redactSecrets(url);
    if (!r) return makeError(shown + ": no answer");
    std::string error;
    if (r->pszErrBuf && *r->pszErrBuf) error = redactSecrets(r->pszErrBuf);
    else if (r->nStatus != 0) error = "the request failed (" + std::to_string(r->nStatus) + ")";
    std::string data;
    if (error.empty()) {
        if (size_t(r->nDataLen) > kMaxDocumentBytes)
            error = "the answer is larger than " + std::to_string(kMaxDocumentBytes >> 20) + " MB";
        else if (r->pabyData) data.assign(reinterpret_cast<const char*>(r->pabyData), size_t(r->nDataLen));
    }
    CPLHTTPDestroyResult(r);
    if (!error.empty()) return makeError(shown + ": " + error);
    return data;
}

Result<std::string> WpsClient::get(const std::string& url) const { return request(url, nullptr); }
Result<std::string> WpsClient::post(const std::string& url, const std::string& body) const { return request(url, &body); }

Result<Capabilities> WpsClient::capabilities() const {
    const std::vector<std::pair<std::string, std::string>> kvp = {{"service", "WPS"}, {"request", "GetCapabilities"}, {"acceptVersions", "1.0.0"}};
    auto text = get(kvpUrl(url_, kvp));
    if (!text) return text.error();
    return parseCapabilities(*text, shown_);
}

Result<ProcessDescription> WpsClient::describe(const std::string& process) const {
    const std::vector<std::pair<std::string, std::string>> kvp = {
        {"service", "WPS"}, {"version", "1.0.0"}, {"request", "DescribeProcess"}, {"identifier", process}};
    auto text = get(kvpUrl(url_, kvp));
    if (!text) return text.error();
    auto all = parseProcessDescriptions(*text, shown_);
    if (!all) return all.error();
    for (auto& d : *all)
        if (d.identifier == process) return std::move(d);
    return makeError(shown_ + ": the description does not describe \"" + process + "\"");
}

Result<ExecuteResponse> WpsClient::execute(const ProcessDescription& process, std::span<const InputValue> inputs,
                                           std::span<const OutputRequest> outputs, bool async) const {
    if (auto ok = checkInputs(process, inputs); !ok) return ok.error();
    if (async && !process.storeSupported)
        return makeError(shown_ + ": \"" + process.identifier + "\" cannot run as a stored job (storeSupported is false)");
    for (const OutputRequest& o : outputs)
        if (!process.output(o.identifier)) return makeError(shown_ + ": \"" + process.identifier + "\" has no output \"" + o.identifier + "\"");
    std::string base = url_;
    if (const size_t q = base.find('?'); q != std::string::npos) base = base.substr(0, q);
    auto text = post(base, executeRequest(process.identifier, inputs, outputs, async));
    if (!text) return text.error();
    auto r = parseExecuteResponse(*text, shown_);
    if (!r) return r.error();
    if (async && !r->finished() && r->statusLocation.empty())
        return makeError(shown_ + ": the job was accepted without a status location to follow");
    return r;
}

Result<ExecuteResponse> WpsClient::status(const ExecuteResponse& job) const {
    if (job.statusLocation.empty()) return makeError(shown_ + ": the job has no status location");
    auto text = get(job.statusLocation);
    if (!text) return text.error();
    return parseExecuteResponse(*text, redactSecrets(job.statusLocation));
}

Result<ExecuteResponse> WpsClient::wait(ExecuteResponse job, const std::function<bool(const ExecuteResponse&)>& progress,
                                        const WaitOptions& options) const {
    using Clock = std::chrono::steady_clock;
    const auto deadline = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(options.timeoutSeconds));
    double delay = std::max(0.01, options.firstDelaySeconds);
    int failures = 0;
    while (!job.finished()) {
        if (progress && !progress(job)) return makeError(shown_ + ": stopped waiting for \"" + job.processId + "\" at " + std::to_string(job.percent) + " %");
        if (Clock::now() + std::chrono::duration<double>(delay) > deadline)
            return makeError(shown_ + ": \"" + job.processId + "\" did not finish within " + std::to_string(int(options.timeoutSeconds)) + " s");
        std::this_thread::sleep_for(std::chrono::duration<double>(delay));
        delay = std::min(options.maxDelaySeconds, delay * 2.0);
        auto next = status(job);
        if (!next) {
            // A server writes the status document in place (PyWPS does): a poll can catch it half
            // written, or the server busy. A few such polls in a row are retried; more end the wait.
            if (++failures <= kStatusRetries) continue;
            return next.error();
        }
        failures = 0;
        if (next->statusLocation.empty()) next->statusLocation = job.statusLocation;
        if (next->processId.empty()) next->processId = job.processId;
        job = std::move(*next);
    }
    if (progress) progress(job);
    return job;
}

Result<std::string> WpsClient::fetch(const std::string& url) const { return get(url); }

Result<std::unique_ptr<ProcessingClient>> connectProcessing(const std::string& url, double timeoutSeconds) {
    if (url.rfind("http://", 0) != 0 && url.rfind("https://", 0) != 0)
        return makeError(redactSecrets(url) + ": not an http(s) address of a processing server");
    return std::unique_ptr<ProcessingClient>(new WpsClient(url, timeoutSeconds));
}

}  // namespace orbis::wps
