#include "layers/fmv/LiveVideo.h"

#include "layers/fmv/AvError.h"
#include "layers/fmv/LiveInput.h"
#include "layers/fmv/LiveRecording.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libswscale/swscale.h>
}

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <fstream>
#include <mutex>
#include <thread>

namespace orbis::fmv {

const char* toString(LiveState state) {
    switch (state) {
        case LiveState::Connecting: return "connecting";
        case LiveState::Live: return "live";
        case LiveState::NoSignal: return "no signal";
    }
    return "?";
}

double wallClockSeconds() {
    return std::chrono::duration<double>(std::chrono::system_clock::now().time_since_epoch()).count();
}

namespace {

double steadySeconds() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

struct QueuedFrame {
    std::shared_ptr<const VideoFrame> frame;
    double streamTime = 0.0;
    double arrival = 0.0;   // wall clock (UTC)
    bool damaged = false;
};

struct StampedPose {
    double time = 0.0;   // stream clock
    SensorPose pose;
    std::optional<double> utc;
};

/// The stream's time stamps jump (a sender restarted, a new clock): what came before no longer
/// lines up with what comes next.
constexpr double kJumpBackSeconds = 0.5, kJumpAheadSeconds = 10.0;
/// A pose holds this long past the last packet (or before the first).
constexpr double kPoseHoldSeconds = 1.0;
/// Poses older than the newest frame by this much are dropped; at most this many kept.
constexpr double kPoseKeepSeconds = 10.0;
constexpr size_t kMaxPoses = 4096;
/// How fast the smallest transit seen is let go (seconds a second), so that a lasting rise in
/// the network's delay is followed.
constexpr double kTransitRelax = 0.002;

/// A session's video decoder.
struct Decoder {
    AVCodecContext* codec = nullptr;
    AVFrame* frame = nullptr;
    SwsContext* sws = nullptr;
    AVRational base{1, 1};
    bool beforeFirstKey = true;   // decoding starts at a key frame
    bool waitKey = false;         // and again after damage
    bool damaged = false;         // a frame since the last key frame lost data on the way
    Decoder() = default;
    Decoder(const Decoder&) = delete;
    Decoder& operator=(const Decoder&) = delete;
    ~Decoder() {
        sws_freeContext(sws);
        av_frame_free(&frame);
        avcodec_free_context(&codec);
    }
};

}  // namespace

struct LiveVideo::Impl {
    std::string url;
    LiveOptions options;
    std::thread thread;
    std::atomic<bool> stop{false};
    std::mutex waitMutex;
    std::condition_variable wake;
    /// Steady-clock seconds after which a blocking FFmpeg call gives up.
    std::atomic<double> deadline{0.0};

    // Shared with the main thread, under `mutex`.
    mutable std::mutex mutex;
    std::deque<QueuedFrame> queue;
    std::deque<StampedPose> poses;
    LiveStats stats;
    std::deque<std::pair<double, uint64_t>> rate;   // (steady seconds, bytes so far)
    double lastData = 0.0;                          // steady seconds of the last packet (or the opening)
    uint64_t epoch = 0;                             // bumped when the stream's clock jumps

    // Main thread only.
    std::optional<LiveFrame> current;
    uint64_t seenEpoch = 0, lastSerial = 0;
    std::optional<double> minTransit;
    double lastDue = 0.0;

    // The worker only.
    uint64_t serial = 0;
    std::optional<double> lastTime;   // the stream clock's last time seen
    std::optional<double> lastFrameTime;
    double frameInterval = 0.0;     // seconds between frames: the stream's rate, else the least gap seen
    bool measuredInterval = false;
    LiveRecording recording;
    GeoidHeight geoid;
    // Recording on request (record()): asked under `mutex`, taken by the worker.
    std::string recordWanted;
    std::atomic<bool> recordChanged{false};

    ~Impl() {
        stop = true;
        wake.notify_all();
        if (thread.joinable()) thread.join();
    }

    static int interrupted(void* opaque) {
        const Impl* m = static_cast<const Impl*>(opaque);
        return m->stop.load() || steadySeconds() > m->deadline.load() ? 1 : 0;
    }

    void run();
    std::string session();
    AVPacket* takeWholeFrames(AVStream* stream, AVCodecContext* codec);
    std::string decode(Decoder& d, const AVPacket& packet, bool lostData);
    /// Whether a continuity gap fell in this video packet (counts the gaps and damaged frames).
    bool lostData(ContinuityGaps& gaps, const AVPacket& packet);
    void noteTime(double t);
    void noteData(size_t bytes);
    void pushFrame(std::shared_ptr<VideoFrame> frame, double streamTime, bool damaged);
    void pushKlv(double time, const uint8_t* data, size_t size);
    void takeRecordRequest();
    /// A new session while recording: the file goes on (or ends if the video changed).
    void continueRecording(AVFormatContext* in, int video, int klv);
    void recordVideo(AVFormatContext* in, int video, int klv, const AVPacket& packet);
    void recordKlv(const AVPacket& packet, AVRational base);
    std::optional<SensorPose> poseAt(double t, std::optional<double>& utc) const;
};

// ---------------------------------------------------------------------------------------------
// The worker: sessions until stopped

void LiveVideo::Impl::run() {
    if (options.makeGeoid) geoid = options.makeGeoid();
    bool first = true;
    while (!stop) {
        if (!first) {
            std::lock_guard lock(mutex);
            ++stats.reconnects;
        }
        first = false;
        const std::string why = session();
        if (stop) break;
        // Between sessions (no signal): a recording stopped or started meanwhile takes effect
        // now, not when data comes again.
        if (recordChanged) takeRecordRequest();
        {
            std::lock_guard lock(mutex);
            stats.state = LiveState::NoSignal;
            stats.lastError = why;
        }
        std::unique_lock lock(waitMutex);
        wake.wait_for(lock, std::chrono::duration<double>(options.retrySeconds), [&] { return stop.load(); });
    }
    recording.close();
}

/// One connection: open, probe, then demux and decode until the stream stops, fails or we are
/// told to stop. Returns why it ended.
std::string LiveVideo::Impl::session() {
    AVFormatContext* format = avformat_alloc_context();
    if (!format) return "out of memory";
    format->interrupt_callback = {&Impl::interrupted, this};
    AVDictionary* opts = nullptr;
    // Joining a stream: its streams are known from the first key frame; the frame rate is not
    // measured (it would hold 20 frames back), the intervals seen stand in for it.
    av_dict_set(&opts, "analyzeduration", "500000", 0);
    av_dict_set(&opts, "probesize", "2000000", 0);
    av_dict_set(&opts, "fpsprobesize", "0", 0);
    if (url.rfind("udp://", 0) == 0 || url.rfind("rtp://", 0) == 0) {
        av_dict_set(&opts, "overrun_nonfatal", "1", 0);
        av_dict_set(&opts, "buffer_size", "4194304", 0);
    }
    // rtp://: FFmpeg's RTP demuxer learns the payload type from a first packet and then opens the
    // port again, losing what came meanwhile (a group of pictures). The stream is MPEG-TS (payload
    // type 33), so it is described up front, in an SDP, and the port is opened once.
    std::string openUrl = url;
    const AVInputFormat* forced = nullptr;
    if (url.rfind("rtp://", 0) == 0) {
        openUrl = rtpSdpUri(url);
        forced = av_find_input_format("sdp");
        av_dict_set(&opts, "protocol_whitelist", "data,udp,rtp", 0);
    }
    deadline = steadySeconds() + options.noSignalSeconds + 2.0;   // the probing reads a second of it
    if (const std::string host = hostToResolve(url); !host.empty())
        if (std::string why = resolveHost(host, [&] { return !interrupted(this); }); !why.empty()) {
            avformat_free_context(format);
            av_dict_free(&opts);
            return stop ? std::string() : why;
        }
    int rc = avformat_open_input(&format, openUrl.c_str(), forced, &opts);   // frees `format` on failure
    av_dict_free(&opts);
    if (rc < 0) return stop ? std::string() : "cannot open (" + avError(rc) + ")";
    struct Closer {
        AVFormatContext*& f;
        ~Closer() { avformat_close_input(&f); }
    } closeFormat{format};
    if (rc = avformat_find_stream_info(format, nullptr); rc < 0) return "cannot read the streams (" + avError(rc) + ")";
    int video = -1, klv = -1;
    for (unsigned i = 0; i < format->nb_streams; ++i) {
        const AVCodecParameters* p = format->streams[i]->codecpar;
        if (p->codec_type == AVMEDIA_TYPE_VIDEO && video < 0 && !(format->streams[i]->disposition & AV_DISPOSITION_ATTACHED_PIC))
            video = int(i);
        if (p->codec_id == AV_CODEC_ID_SMPTE_KLV && klv < 0) klv = int(i);
    }
    if (video < 0) return klv >= 0 ? "KLV metadata but no video stream" : "no video stream";
    AVStream* vs = format->streams[video];
    ContinuityGaps gaps(format, vs->id);   // the video's PID, for MPEG-TS
    const AVCodec* decoder = avcodec_find_decoder(vs->codecpar->codec_id);
    if (!decoder) return std::string("no decoder for its video codec ").append(avcodec_get_name(vs->codecpar->codec_id));
    Decoder d;
    d.codec = avcodec_alloc_context3(decoder);
    if (!d.codec || avcodec_parameters_to_context(d.codec, vs->codecpar) < 0) return "cannot set up the video decoder";
    d.codec->flags |= AV_CODEC_FLAG_LOW_DELAY;
    d.codec->flags &= ~AV_CODEC_FLAG_OUTPUT_CORRUPT;
    d.codec->thread_count = 1;   // a thread a feed already
    if (rc = avcodec_open2(d.codec, decoder, nullptr); rc < 0) return "cannot open the video decoder (" + avError(rc) + ")";
    d.frame = av_frame_alloc();
    d.base = vs->time_base;
    const AVRational rateQ = vs->avg_frame_rate.num > 0 ? vs->avg_frame_rate : vs->r_frame_rate;
    frameInterval = rateQ.num > 0 && rateQ.den > 0 && av_q2d(rateQ) < 1000.0 ? 1.0 / av_q2d(rateQ) : 0.0;
    measuredInterval = frameInterval == 0.0;
    // Frames as the sender packed them: from here on the parser takes each packet as a whole
    // frame instead of waiting for the next one to find where it ends. The frame it holds from
    // the probing comes out first (with its own time stamp), to go in after the packets the
    // probing read.
    AVPacket* held = nullptr;
    if (options.wholeFrames) held = takeWholeFrames(vs, d.codec);
    continueRecording(format, video, klv);
    {   // a new connection may be a new clock: start again
        std::lock_guard lock(mutex);
        ++epoch;
        queue.clear();
        poses.clear();
    }
    lastTime.reset();
    lastFrameTime.reset();

    AVPacket* packet = av_packet_alloc();
    struct Frees {
        AVPacket*& p;
        AVPacket*& h;
        ~Frees() {
            av_packet_free(&p);
            av_packet_free(&h);
        }
    } frees{packet, held};
    if (!packet || !d.frame) return "out of memory";
    std::string ended;
    while (!stop && ended.empty()) {
        deadline = steadySeconds() + options.noSignalSeconds;
        rc = av_read_frame(format, packet);
        if (rc < 0) {
            if (stop) break;
            ended = rc == AVERROR_EXIT ? "no data for " + std::to_string(int(std::lround(options.noSignalSeconds))) + " s"
                    : rc == AVERROR_EOF ? "the stream ended"
                                         : "read error (" + avError(rc) + ")";
            break;
        }
        noteData(size_t(packet->size));
        if (recordChanged) takeRecordRequest();
        if (packet->stream_index == klv) {
            recordKlv(*packet, format->streams[klv]->time_base);
            const AVRational base = format->streams[klv]->time_base;
            const int64_t ts = packet->pts != AV_NOPTS_VALUE ? packet->pts : packet->dts;
            const double t = ts != AV_NOPTS_VALUE ? double(ts) * av_q2d(base) : lastFrameTime.value_or(0.0);
            if (packet->flags & AV_PKT_FLAG_CORRUPT) {
                std::lock_guard lock(mutex);
                ++stats.corruptPackets;
            }
            pushKlv(t, packet->data, size_t(packet->size));   // the checksum judges a damaged one
        } else if (packet->stream_index == video) {
            if (held && (packet->pts == AV_NOPTS_VALUE || held->pts == AV_NOPTS_VALUE || packet->pts > held->pts)) {
                recordVideo(format, video, klv, *held);
                ended = decode(d, *held, false);
                av_packet_free(&held);
                if (!ended.empty()) break;
            }
            recordVideo(format, video, klv, *packet);
            ended = decode(d, *packet, lostData(gaps, *packet));
        }
        av_packet_unref(packet);
    }
    return ended;
}

/// Tells the video stream's parser to take packets as whole frames; returns the frame it held
/// (flushed out, with its time stamp), or null.
AVPacket* LiveVideo::Impl::takeWholeFrames(AVStream* stream, AVCodecContext* codec) {
    AVCodecParserContext* parser = av_stream_get_parser(stream);
    if (!parser) return nullptr;
    uint8_t* data = nullptr;
    int size = 0;
    av_parser_parse2(parser, codec, &data, &size, nullptr, 0, AV_NOPTS_VALUE, AV_NOPTS_VALUE, 0);
    parser->flags |= PARSER_FLAG_COMPLETE_FRAMES;
    if (size <= 0) return nullptr;
    AVPacket* p = av_packet_alloc();
    if (!p || av_new_packet(p, size) < 0) {
        av_packet_free(&p);
        return nullptr;
    }
    std::copy(data, data + size, p->data);
    p->stream_index = stream->index;
    p->pts = parser->pts;
    p->dts = parser->dts != AV_NOPTS_VALUE ? parser->dts : parser->pts;
    if (parser->key_frame == 1) p->flags |= AV_PKT_FLAG_KEY;
    return p;
}

bool LiveVideo::Impl::lostData(ContinuityGaps& gaps, const AVPacket& packet) {
    const ContinuityGaps::Taken t = gaps.take(packet.pos, packet.size);
    std::lock_guard lock(mutex);
    stats.continuityGaps += t.gaps;
    stats.framesDamaged += t.inPacket;
    return t.inPacket;
}

/// One video packet into the decoder, the frames that come out onto the queue. A packet that
/// lost data on the way (`lostData`) is decoded and shown as the decoder conceals it, or with
/// `skipDamaged` left out with the frames after it until the next key frame (they refer to it).
/// A packet flagged corrupt or refused by the decoder is left out that way too, and so are
/// frames the decoder marks as decoded with errors. Decoding starts at a key frame. Returns an
/// error that ends the session, or empty.
std::string LiveVideo::Impl::decode(Decoder& d, const AVPacket& packet, bool lostData) {
    const auto damaged = [&] {
        std::lock_guard lock(mutex);
        ++stats.corruptPackets;
        d.waitKey = true;
    };
    if (lostData && options.skipDamaged) {
        d.waitKey = true;
        return {};
    }
    if (packet.flags & AV_PKT_FLAG_CORRUPT) {
        damaged();
        return {};
    }
    // A key frame that arrived whole starts clean; the frames after a damaged one refer to it.
    d.damaged = lostData || (d.damaged && !(packet.flags & AV_PKT_FLAG_KEY));
    if (avcodec_send_packet(d.codec, &packet) < 0) damaged();
    AVFrame* frame = d.frame;
    while (avcodec_receive_frame(d.codec, frame) == 0) {
        struct Unref {
            AVFrame* f;
            ~Unref() { av_frame_unref(f); }
        } unref{frame};
        const int64_t pts = frame->best_effort_timestamp != AV_NOPTS_VALUE ? frame->best_effort_timestamp : frame->pts;
        const bool broken = frame->decode_error_flags != 0 || (frame->flags & AV_FRAME_FLAG_CORRUPT);
        if (frame->key_frame && !broken) d.waitKey = d.beforeFirstKey = false;
        if (d.waitKey || d.beforeFirstKey) continue;   // refers to what was lost: not shown (the gap counts it lost)
        if (pts == AV_NOPTS_VALUE || frame->width <= 0 || frame->height <= 0 || frame->width > VideoFile::kMaxDimension ||
            frame->height > VideoFile::kMaxDimension) {
            std::lock_guard lock(mutex);
            ++stats.corruptPackets;
            continue;
        }
        if (broken) {
            std::lock_guard lock(mutex);
            ++stats.framesConcealed;
            d.waitKey = true;
            continue;
        }
        d.sws = sws_getCachedContext(d.sws, frame->width, frame->height, AVPixelFormat(frame->format), frame->width, frame->height,
                                     AV_PIX_FMT_RGBA, SWS_BILINEAR, nullptr, nullptr, nullptr);
        if (!d.sws) return "cannot convert its frames to RGBA";
        auto out = std::make_shared<VideoFrame>();
        out->width = frame->width;
        out->height = frame->height;
        out->rgba.resize(size_t(frame->width) * size_t(frame->height) * 4);
        uint8_t* dst[4] = {out->rgba.data(), nullptr, nullptr, nullptr};
        const int dstStride[4] = {frame->width * 4, 0, 0, 0};
        sws_scale(d.sws, frame->data, frame->linesize, 0, frame->height, dst, dstStride);
        pushFrame(std::move(out), double(pts) * av_q2d(d.base), d.damaged);
    }
    return {};
}

void LiveVideo::Impl::noteData(size_t bytes) {
    const double now = steadySeconds();
    std::lock_guard lock(mutex);
    stats.bytes += bytes;
    lastData = now;
    rate.emplace_back(now, stats.bytes);
    while (rate.size() > 2 && rate.front().first < now - 2.0) rate.pop_front();
}

/// A time on the stream's clock: a jump starts a new epoch (the frames and poses queued are
/// from another clock).
void LiveVideo::Impl::noteTime(double t) {
    if (lastTime && (t < *lastTime - kJumpBackSeconds || t > *lastTime + kJumpAheadSeconds)) {
        recording.clockJumped();   // the file goes on after the jump
        std::lock_guard lock(mutex);
        ++epoch;
        queue.clear();
        poses.clear();
        lastFrameTime.reset();
        lastTime = t;
        return;
    }
    lastTime = std::max(t, lastTime.value_or(t));
}

void LiveVideo::Impl::pushFrame(std::shared_ptr<VideoFrame> frame, double streamTime, bool damaged) {
    noteTime(streamTime);
    uint64_t lost = 0;
    if (measuredInterval && lastFrameTime && streamTime > *lastFrameTime &&
        (frameInterval == 0.0 || streamTime - *lastFrameTime < frameInterval))
        frameInterval = streamTime - *lastFrameTime;
    else if (lastFrameTime && frameInterval > 0.0 && streamTime > *lastFrameTime) {
        const double gap = (streamTime - *lastFrameTime) / frameInterval;
        if (gap > 1.5) lost = uint64_t(std::lround(gap) - 1);
    }
    lastFrameTime = streamTime;
    frame->index = ++serial;
    frame->time = streamTime;
    std::lock_guard lock(mutex);
    stats.state = LiveState::Live;
    stats.lastError.clear();
    stats.width = frame->width;
    stats.height = frame->height;
    ++stats.framesDecoded;
    stats.framesLost += lost;
    queue.push_back({std::move(frame), streamTime, wallClockSeconds(), damaged});
    while (queue.size() > std::max<size_t>(options.maxQueuedFrames, 1)) {
        queue.pop_front();
        ++stats.framesSkipped;
    }
    while (!poses.empty() && (poses.size() > kMaxPoses || poses.front().time < streamTime - kPoseKeepSeconds)) poses.pop_front();
}

void LiveVideo::Impl::pushKlv(double time, const uint8_t* data, size_t size) {
    noteTime(time);
    std::vector<TimedKlv> one{{time, std::vector<uint8_t>(data, data + size)}};
    auto decoded = FmvTimeline::fromKlv(one, url, geoid);
    std::lock_guard lock(mutex);
    ++stats.klvPackets;
    if (!decoded) {
        ++stats.klvRejected;
        return;
    }
    stats.klvRejected += decoded->checksumRejected() + decoded->undecodable() + decoded->incompleteRejected();
    for (const TimedPose& p : decoded->poses()) {
        const StampedPose s{p.time, p.pose, p.utc};
        const auto at = std::upper_bound(poses.begin(), poses.end(), s.time, [](double t, const StampedPose& q) { return t < q.time; });
        poses.insert(at, s);
        ++stats.posesReceived;
    }
    while (poses.size() > kMaxPoses) poses.pop_front();
}

// ---------------------------------------------------------------------------------------------
// Recording

/// A change of recording asked for by record(): the current file finished, the next one
/// pending until a key frame.
void LiveVideo::Impl::takeRecordRequest() {
    std::string wanted;
    {
        std::lock_guard lock(mutex);
        wanted = recordWanted;
        recordChanged = false;
    }
    recording.restart(wanted);
}

void LiveVideo::Impl::continueRecording(AVFormatContext* in, int video, int klv) {
    const std::string ended = recording.newSession(in, video, klv);
    if (ended.empty()) return;
    std::lock_guard lock(mutex);
    stats.lastError = ended;
    stats.recording.clear();
    recordWanted.clear();
}

/// A video packet into the recording; a pending one starts here if this is a key frame (the
/// KLV of the second before first).
void LiveVideo::Impl::recordVideo(AVFormatContext* in, int video, int klv, const AVPacket& packet) {
    std::string error;
    const int written = recording.video(in, video, klv, packet, error);
    if (written == 0 && error.empty()) return;
    std::lock_guard lock(mutex);
    stats.packetsRecorded += uint64_t(written);
    if (!error.empty()) {
        stats.lastError = error;
        stats.recording.clear();
    }
}

void LiveVideo::Impl::recordKlv(const AVPacket& packet, AVRational base) {
    if (!recording.klv(packet, base)) return;
    std::lock_guard lock(mutex);
    ++stats.packetsRecorded;
}

// ---------------------------------------------------------------------------------------------
// The main thread

std::optional<SensorPose> LiveVideo::Impl::poseAt(double t, std::optional<double>& utc) const {
    utc.reset();
    if (poses.empty()) return std::nullopt;
    if (t <= poses.front().time) {
        if (poses.front().time - t > kPoseHoldSeconds) return std::nullopt;
        if (poses.front().utc) utc = *poses.front().utc - (poses.front().time - t);
        return poses.front().pose;
    }
    if (t >= poses.back().time) {
        if (t - poses.back().time > kPoseHoldSeconds) return std::nullopt;
        if (poses.back().utc) utc = *poses.back().utc + (t - poses.back().time);
        return poses.back().pose;
    }
    const auto after = std::upper_bound(poses.begin(), poses.end(), t, [](double x, const StampedPose& p) { return x < p.time; });
    const StampedPose& b = *after;
    const StampedPose& a = *(after - 1);
    const double span = b.time - a.time, f = span > 0.0 ? (t - a.time) / span : 1.0;
    if (a.utc && b.utc) utc = *a.utc + f * (*b.utc - *a.utc);
    else if (a.utc) utc = *a.utc + (t - a.time);
    return interpolate(a.pose, b.pose, f);
}

std::optional<LiveFrame> LiveVideo::due(double now) {
    Impl& m = *impl_;
    std::lock_guard lock(m.mutex);
    if (m.epoch != m.seenEpoch) {   // a new clock: what was learnt of the old one goes
        m.seenEpoch = m.epoch;
        m.minTransit.reset();
    }
    if (m.minTransit && now > m.lastDue) *m.minTransit += kTransitRelax * (now - m.lastDue);
    m.lastDue = now;
    for (const QueuedFrame& q : m.queue) {
        if (q.frame->index <= m.lastSerial) continue;
        m.lastSerial = q.frame->index;
        const double transit = q.arrival - q.streamTime;
        if (!m.minTransit || transit < *m.minTransit) m.minTransit = transit;
    }
    // The newest frame whose time has come; the ones before it are skipped.
    size_t chosen = m.queue.size();
    for (size_t i = 0; i < m.queue.size(); ++i)
        if (m.queue[i].streamTime + *m.minTransit + m.options.jitterSeconds <= now) chosen = i;
    const bool fresh = chosen < m.queue.size();
    if (fresh) {
        m.stats.framesSkipped += chosen;
        LiveFrame f;
        f.frame = m.queue[chosen].frame;
        f.streamTime = m.queue[chosen].streamTime;
        f.damaged = m.queue[chosen].damaged;
        m.queue.erase(m.queue.begin(), m.queue.begin() + ptrdiff_t(chosen) + 1);
        m.current = std::move(f);
        ++m.stats.framesShown;
    }
    if (!m.current) return std::nullopt;
    // The pose again each time: KLV that arrives after its frame still places it.
    m.current->pose = m.poseAt(m.current->streamTime, m.current->utc);
    // Latency when a frame is first due: it is draped this frame.
    if (fresh && m.current->utc && plausibleLatency(now - *m.current->utc)) m.stats.latencySeconds = now - *m.current->utc;
    return m.current;
}

LiveStats LiveVideo::stats() const {
    const Impl& m = *impl_;
    std::lock_guard lock(m.mutex);
    LiveStats s = m.stats;
    const double now = steadySeconds();
    s.secondsSinceData = now - m.lastData;
    if (m.rate.size() >= 2 && s.secondsSinceData < 2.0) {
        const double span = m.rate.back().first - m.rate.front().first;
        if (span > 0.0) s.bitsPerSecond = double(m.rate.back().second - m.rate.front().second) * 8.0 / span;
    }
    return s;
}

const std::string& LiveVideo::url() const { return impl_->url; }

namespace {

/// A recording's file can be written (made empty now, so the error comes here, not on the
/// stream's thread).
Result<void> checkWritable(const std::string& path, const std::string& url) {
    std::ofstream probe(path, std::ios::binary | std::ios::trunc);
    if (!probe) return makeError(path + ": cannot write the recording of " + url);
    return {};
}

}  // namespace

Result<void> LiveVideo::record(const std::string& path) {
    Impl& m = *impl_;
    if (!path.empty())
        if (auto ok = checkWritable(path, m.url); !ok) return ok;
    std::lock_guard lock(m.mutex);
    m.recordWanted = path;
    m.stats.recording = path;
    m.recordChanged = true;
    return {};
}

LiveVideo::~LiveVideo() = default;

std::string LiveVideo::inputProtocols() {
    std::string out;
    void* opaque = nullptr;
    while (const char* name = avio_enum_protocols(&opaque, 0)) {
        if (!out.empty()) out += ", ";
        out += name;
    }
    return out;
}

Result<std::unique_ptr<LiveVideo>> LiveVideo::open(const std::string& url, LiveOptions options) {
    static std::once_flag network;
    std::call_once(network, [] {
        avformat_network_init();
        av_log_set_callback(&liveLogCallback);
    });
    av_log_set_level(AV_LOG_ERROR);
    const size_t colon = url.find("://");
    if (url.empty() || colon == std::string::npos || colon == 0)
        return makeError("\"" + url + "\": a live stream is a URL (udp://, tcp://, http://, srt://, rtp://)");
    const std::string scheme = url.substr(0, colon);
    if (scheme == "file") return makeError(url + ": a file is played from \"path\", not as a live stream");
    if (scheme == "srt") startSrtOnce();
    bool known = false;
    void* opaque = nullptr;
    while (const char* name = avio_enum_protocols(&opaque, 0)) known |= scheme == name;
    if (!known) return makeError(url + ": this FFmpeg cannot receive " + scheme + ":// (it has " + inputProtocols() + ")");
    if (scheme == "rtp") {
        char host[256] = {};
        int port = -1;
        av_url_split(nullptr, 0, nullptr, 0, host, sizeof host, &port, nullptr, 0, url.c_str());
        if (!*host || port <= 0 || port > 65535) return makeError(url + ": an RTP stream needs rtp://HOST:PORT (the address it arrives at)");
    }
    if (!(options.jitterSeconds >= 0.0 && options.jitterSeconds <= 10.0) || !(options.noSignalSeconds > 0.0) ||
        !(options.retrySeconds > 0.0))
        return makeError(url + ": jitter from 0 to 10 s, no-signal and retry times above 0");
    if (!options.recordPath.empty())
        if (auto ok = checkWritable(options.recordPath, url); !ok) return ok.error();
    std::unique_ptr<LiveVideo> v(new LiveVideo);
    v->impl_ = std::make_unique<Impl>();
    Impl& m = *v->impl_;
    m.url = url;
    m.recordWanted = m.stats.recording = options.recordPath;
    m.recording.restart(options.recordPath);   // (before the worker starts)
    m.options = std::move(options);
    m.lastData = steadySeconds();
    m.thread = std::thread([&m] { m.run(); });
    return v;
}

}  // namespace orbis::fmv
