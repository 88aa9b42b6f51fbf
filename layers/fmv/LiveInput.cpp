#include "layers/fmv/LiveInput.h"

extern "C" {
#include <libavformat/avformat.h>
#include <libavutil/base64.h>
}

#include <arpa/inet.h>
#include <netdb.h>

#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <mutex>
#include <thread>
#include <unordered_map>

namespace orbis::fmv {

namespace {

/// The demuxers whose gaps are counted; the log callback looks its context up here.
std::mutex registryMutex;
std::unordered_map<const void*, ContinuityGaps*> registry;

}  // namespace

std::string hostToResolve(const std::string& url) {
    char host[256] = {};
    int port = -1;
    av_url_split(nullptr, 0, nullptr, 0, host, sizeof host, &port, nullptr, 0, url.c_str());
    const std::string h = host;
    if (h.empty() || h.find(':') != std::string::npos) return {};   // none, or IPv6
    in_addr v4{};
    if (inet_pton(AF_INET, h.c_str(), &v4) == 1) return {};
    return h;
}

std::string resolveHost(const std::string& host, const std::function<bool()>& keepWaiting) {
    struct Lookup {
        std::mutex m;
        std::condition_variable done;
        bool finished = false;
        int rc = 0;
    };
    auto lookup = std::make_shared<Lookup>();
    std::thread([lookup, host] {
        addrinfo hints{};
        hints.ai_family = AF_UNSPEC;
        addrinfo* found = nullptr;
        const int rc = getaddrinfo(host.c_str(), nullptr, &hints, &found);
        if (found) freeaddrinfo(found);
        std::lock_guard lock(lookup->m);
        lookup->rc = rc;
        lookup->finished = true;
        lookup->done.notify_all();
    }).detach();
    std::unique_lock lock(lookup->m);
    while (!lookup->finished) {
        lookup->done.wait_for(lock, std::chrono::milliseconds(50));
        if (!lookup->finished && !keepWaiting()) return "no answer yet looking up the host " + host;
    }
    return lookup->rc == 0 ? std::string() : "cannot find the host " + host + " (" + gai_strerror(lookup->rc) + ")";
}

std::string rtpSdpUri(const std::string& url) {
    char host[256] = {}, path[8] = {};
    int port = -1;
    av_url_split(nullptr, 0, nullptr, 0, host, sizeof host, &port, path, sizeof path, url.c_str());
    const std::string h = host;
    const bool ip6 = h.find(':') != std::string::npos;
    const int first = ip6 ? 0 : std::atoi(h.c_str());
    const bool multicast = ip6 ? h.rfind("ff", 0) == 0 : first >= 224 && first <= 239;
    const std::string sdp = std::string("v=0\r\no=- 0 0 IN ") + (ip6 ? "IP6 " : "IP4 ") + h + "\r\ns=Orbis live feed\r\nc=IN " +
                            (ip6 ? "IP6 " : "IP4 ") + h + (multicast && !ip6 ? "/16" : "") + "\r\nt=0 0\r\nm=video " +
                            std::to_string(port) + " RTP/AVP 33\r\na=rtpmap:33 MP2T/90000\r\n";
    std::string encoded(AV_BASE64_SIZE(sdp.size()), '\0');
    av_base64_encode(encoded.data(), int(encoded.size()), reinterpret_cast<const uint8_t*>(sdp.data()), int(sdp.size()));
    encoded.resize(std::strlen(encoded.c_str()));
    return "data:application/sdp;base64," + encoded;
}

ContinuityGaps::ContinuityGaps(const void* format, int videoPid) : format_(format), videoPid_(videoPid) {
    std::lock_guard lock(registryMutex);
    registry[format_] = this;
}

ContinuityGaps::~ContinuityGaps() {
    std::lock_guard lock(registryMutex);
    registry.erase(format_);
}

ContinuityGaps::Taken ContinuityGaps::take(int64_t pos, int size) {
    std::lock_guard lock(registryMutex);
    Taken t;
    const int64_t end = pos + (int64_t(size) + 40) / 184 * 188 + 188;
    while (!videoGaps_.empty() && (pos < 0 || videoGaps_.front() < 0 || videoGaps_.front() <= end)) {
        t.inPacket |= pos < 0 || videoGaps_.front() < 0 || videoGaps_.front() > pos;
        videoGaps_.pop_front();
    }
    t.gaps = all_;
    all_ = 0;
    return t;
}

void liveLogCallback(void* object, int level, const char* format, va_list args) {
    static constexpr char kGap[] = "Continuity check failed for pid ";
    if (object && format && std::strncmp(format, kGap, sizeof kGap - 1) == 0) {
        std::lock_guard lock(registryMutex);
        if (const auto it = registry.find(object); it != registry.end()) {
            va_list copy;
            va_copy(copy, args);
            const int pid = va_arg(copy, int);
            va_end(copy);
            ContinuityGaps& gaps = *it->second;
            ++gaps.all_;
            if (pid == gaps.videoPid_) {
                const AVFormatContext* f = static_cast<const AVFormatContext*>(object);
                gaps.videoGaps_.push_back(f->pb ? avio_tell(f->pb) : -1);
                if (gaps.videoGaps_.size() > 4096) gaps.videoGaps_.pop_front();
            }
            return;
        }
    }
    if (object && level > AV_LOG_FATAL) {
        const AVClass* c = *static_cast<const AVClass* const*>(object);
        if (c && (c->get_category ? c->get_category(object) : c->category) == AV_CLASS_CATEGORY_DECODER) return;
    }
    av_log_default_callback(object, level, format, args);
}

}  // namespace orbis::fmv
