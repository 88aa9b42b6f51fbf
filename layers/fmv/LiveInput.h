#pragma once
// How LiveVideo reaches a live stream and watches its transport (private to the FMV video
// library): a host name looked up off the stream's thread, RTP described by an SDP, and the
// continuity gaps FFmpeg's MPEG-TS demuxer reports, caught by the process's FFmpeg log callback.

#include <cstdarg>
#include <cstdint>
#include <deque>
#include <functional>
#include <string>

namespace orbis::fmv {

/// The host a URL names when it is a name to look up (not an address, not empty), else "".
std::string hostToResolve(const std::string& url);

/// Looks `host` up on a thread of its own: getaddrinfo cannot be interrupted, and a name that
/// does not resolve can take the resolver's whole timeout. The caller waits while `keepWaiting`
/// says so and gives up otherwise (the lookup then ends on its own, unwatched). "" when found.
std::string resolveHost(const std::string& host, const std::function<bool()>& keepWaiting);

/// rtp://HOST:PORT as a data: URI of the SDP that describes MPEG-TS over RTP (payload type 33)
/// arriving there: unicast to HOST's port, or a multicast group joined.
std::string rtpSdpUri(const std::string& url);

/// The continuity gaps one MPEG-TS demuxer reports, while it is registered (this object's life).
/// libavformat 5.1 sees a gap in a stream's continuity counters (a datagram lost) and marks the
/// PES it falls in corrupt, but its parser drops the mark; the report it logs is the one trace
/// left. liveLogCallback takes it on the demuxing thread, with the byte position the demuxer had
/// reached.
class ContinuityGaps {
public:
    /// Watches `format` (an AVFormatContext) whose video stream has `videoPid`.
    ContinuityGaps(const void* format, int videoPid);
    ~ContinuityGaps();
    ContinuityGaps(const ContinuityGaps&) = delete;
    ContinuityGaps& operator=(const ContinuityGaps&) = delete;

    struct Taken {
        bool inPacket = false;   ///< a gap fell in the video packet asked about
        uint64_t gaps = 0;       ///< gaps in any stream reported since the last take()
    };
    /// Whether a gap fell in the video packet at `pos` of `size` bytes: between its first byte
    /// and the end of the transport packets that can carry it (each carries at most 184). Gaps
    /// before it are dropped; without positions (RTP) any gap since the last packet counts.
    Taken take(int64_t pos, int size);

private:
    friend void liveLogCallback(void*, int, const char*, va_list);
    const void* format_;
    int videoPid_;
    uint64_t all_ = 0;                 // gaps in any stream since the last take()
    std::deque<int64_t> videoGaps_;    // positions just after a gap in the video (-1: unknown)
};

/// FFmpeg's log callback while live streams are open: continuity-gap reports go to the
/// ContinuityGaps registered for their demuxer; decoders' messages are dropped (joining a
/// stream mid-way and lost datagrams make them complain every frame; LiveStats counts the
/// damage); the rest goes to FFmpeg's default callback.
void liveLogCallback(void* object, int level, const char* format, va_list args);

}  // namespace orbis::fmv
