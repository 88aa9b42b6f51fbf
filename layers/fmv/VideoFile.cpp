#include "layers/fmv/VideoFile.h"

#include "layers/fmv/AvError.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/imgutils.h>
#include <libswscale/swscale.h>
}

#include <algorithm>
#include <cmath>
#include <limits>

namespace orbis::fmv {

struct VideoFile::Impl {
    AVFormatContext* format = nullptr;
    AVCodecContext* codec = nullptr;
    SwsContext* sws = nullptr;
    AVPacket* packet = nullptr;
    AVFrame* frame = nullptr;
    int stream = -1;
    AVRational timeBase{1, 1};
    int64_t firstPts = 0;
    int64_t lastPts = std::numeric_limits<int64_t>::min();   // the decoder's last frame out
    bool drained = false;                                     // sent the end of the stream

    ~Impl() {
        sws_freeContext(sws);
        av_frame_free(&frame);
        av_packet_free(&packet);
        avcodec_free_context(&codec);
        avformat_close_input(&format);
    }
    double seconds(int64_t pts) const { return double(pts - firstPts) * av_q2d(timeBase); }
};

VideoFile::~VideoFile() = default;

Result<std::unique_ptr<VideoFile>> VideoFile::open(const std::string& path) {
    std::unique_ptr<VideoFile> v(new VideoFile);
    v->path_ = path;
    v->impl_ = std::make_unique<Impl>();
    Impl& m = *v->impl_;
    const auto fail = [&](const std::string& what) { return makeError(path + ": " + what); };
    av_log_set_level(AV_LOG_ERROR);
    if (int rc = avformat_open_input(&m.format, path.c_str(), nullptr, nullptr); rc < 0)
        return fail("cannot open as a video (" + avError(rc) + ")");
    if (int rc = avformat_find_stream_info(m.format, nullptr); rc < 0)
        return fail("cannot read the streams (" + avError(rc) + ")");
    int klvStream = -1;
    for (unsigned i = 0; i < m.format->nb_streams; ++i) {
        const AVCodecParameters* p = m.format->streams[i]->codecpar;
        if (p->codec_type == AVMEDIA_TYPE_VIDEO && m.stream < 0 && !(m.format->streams[i]->disposition & AV_DISPOSITION_ATTACHED_PIC))
            m.stream = int(i);
        if (p->codec_id == AV_CODEC_ID_SMPTE_KLV && klvStream < 0) klvStream = int(i);
    }
    v->info_.hasKlv = klvStream >= 0;
    if (m.stream < 0) return fail(klvStream >= 0 ? "has KLV metadata but no video stream" : "has no video stream");
    AVStream* st = m.format->streams[m.stream];
    const AVCodec* decoder = avcodec_find_decoder(st->codecpar->codec_id);
    if (!decoder) return fail(std::string("no decoder for its video codec ").append(avcodec_get_name(st->codecpar->codec_id)));
    if (st->codecpar->width <= 0 || st->codecpar->height <= 0 || st->codecpar->width > kMaxDimension ||
        st->codecpar->height > kMaxDimension)
        return fail("video size " + std::to_string(st->codecpar->width) + "x" + std::to_string(st->codecpar->height) +
                    " is outside 1.." + std::to_string(kMaxDimension));
    m.timeBase = st->time_base;
    v->info_.width = st->codecpar->width;
    v->info_.height = st->codecpar->height;
    v->info_.codec = avcodec_get_name(st->codecpar->codec_id);
    const AVRational rate = st->avg_frame_rate.num > 0 ? st->avg_frame_rate : st->r_frame_rate;
    v->info_.frameRate = rate.num > 0 && rate.den > 0 ? av_q2d(rate) : 0.0;

    // One pass over the packets: the video frames' times and key flags, and the KLV packets.
    m.packet = av_packet_alloc();
    m.frame = av_frame_alloc();
    struct Entry {
        int64_t pts;
        bool key;
    };
    std::vector<Entry> entries;
    struct RawKlv {
        int64_t ts;
        AVRational base;
        std::vector<uint8_t> bytes;
    };
    std::vector<RawKlv> klv;
    size_t klvBytes = 0;
    int64_t lastDts = AV_NOPTS_VALUE;
    int64_t frameDuration = 0;
    while (true) {
        const int rc = av_read_frame(m.format, m.packet);
        if (rc == AVERROR_EOF) break;
        if (rc < 0) return fail("read error in the container (" + avError(rc) + ")");
        const AVPacket& p = *m.packet;
        if (p.stream_index == m.stream) {
            int64_t pts = p.pts != AV_NOPTS_VALUE ? p.pts : p.dts;
            if (pts == AV_NOPTS_VALUE) {   // no time stamps at all: count on from the last
                if (lastDts == AV_NOPTS_VALUE) {
                    av_packet_unref(m.packet);
                    return fail("video frames without time stamps");
                }
                pts = lastDts + std::max<int64_t>(p.duration, 1);
            }
            lastDts = pts;
            frameDuration = std::max<int64_t>(frameDuration, p.duration);
            entries.push_back({pts, (p.flags & AV_PKT_FLAG_KEY) != 0});
            if (entries.size() > kMaxFrames) {
                av_packet_unref(m.packet);
                return fail("more than " + std::to_string(kMaxFrames) + " frames");
            }
        } else if (p.stream_index == klvStream && p.size > 0) {
            klvBytes += size_t(p.size);
            if (klvBytes > kMaxKlvBytes) {
                av_packet_unref(m.packet);
                return fail("more than " + std::to_string(kMaxKlvBytes >> 20) + " MB of KLV metadata");
            }
            const int64_t ts = p.pts != AV_NOPTS_VALUE ? p.pts : p.dts;
            klv.push_back({ts, m.format->streams[klvStream]->time_base, std::vector<uint8_t>(p.data, p.data + p.size)});
        }
        av_packet_unref(m.packet);
    }
    if (entries.empty()) return fail("the video stream has no frames");
    std::stable_sort(entries.begin(), entries.end(), [](const Entry& a, const Entry& b) { return a.pts < b.pts; });
    m.firstPts = entries.front().pts;
    for (const Entry& e : entries) {
        if (!v->framePts_.empty() && e.pts == v->framePts_.back()) continue;   // a repeated time stamp
        v->framePts_.push_back(e.pts);
        v->frameIsKey_.push_back(e.key ? 1 : 0);
        v->frameTimes_.push_back(m.seconds(e.pts));
    }
    v->frameIsKey_[0] = 1;   // decoding starts at the start whatever the flags say
    const double last = v->frameTimes_.back();
    const double step = frameDuration > 0 ? double(frameDuration) * av_q2d(m.timeBase)
                        : v->info_.frameRate > 0 ? 1.0 / v->info_.frameRate
                                                 : 0.0;
    v->info_.duration = last + step;
    if (v->info_.frameRate <= 0.0 && v->frameTimes_.size() > 1) v->info_.frameRate = double(v->frameTimes_.size() - 1) / last;
    // KLV times on the video's clock (both streams share the container's clock).
    for (RawKlv& k : klv) {
        const double t = k.ts == AV_NOPTS_VALUE ? 0.0
                                                : double(av_rescale_q(k.ts, k.base, m.timeBase) - m.firstPts) * av_q2d(m.timeBase);
        v->klv_.push_back({t, std::move(k.bytes)});
    }
    std::stable_sort(v->klv_.begin(), v->klv_.end(), [](const TimedKlv& a, const TimedKlv& b) { return a.time < b.time; });

    // The decoder, then back to the start.
    m.codec = avcodec_alloc_context3(decoder);
    if (!m.codec || avcodec_parameters_to_context(m.codec, st->codecpar) < 0) return fail("cannot set up the video decoder");
    m.codec->flags &= ~AV_CODEC_FLAG_OUTPUT_CORRUPT;   // frames before a key frame are dropped, not shown broken
    m.codec->thread_count = 1;                         // the layer decodes on a worker already
    if (int rc = avcodec_open2(m.codec, decoder, nullptr); rc < 0) return fail("cannot open the video decoder (" + avError(rc) + ")");
    if (av_seek_frame(m.format, m.stream, v->framePts_[0], AVSEEK_FLAG_BACKWARD) < 0)
        avformat_seek_file(m.format, -1, INT64_MIN, 0, INT64_MAX, AVSEEK_FLAG_BYTE);
    return v;
}

size_t VideoFile::frameAt(double t) const {
    const auto it = std::upper_bound(frameTimes_.begin(), frameTimes_.end(), t);
    return it == frameTimes_.begin() ? 0 : size_t(it - frameTimes_.begin()) - 1;
}

Result<VideoFrame> VideoFile::decode(size_t index) {
    Impl& m = *impl_;
    if (index >= framePts_.size())
        return makeError(path_ + ": frame " + std::to_string(index) + " does not exist (" + std::to_string(framePts_.size()) + " frames)");
    const int64_t target = framePts_[index];
    // Decode on from where the decoder is when no key frame lies between; else seek to the key
    // frame at or before the frame (an earlier one if the seek lands after it).
    size_t key = index;
    while (key > 0 && !frameIsKey_[key]) --key;
    const bool started = m.lastPts != std::numeric_limits<int64_t>::min() && !m.drained;
    const size_t at = size_t(std::lower_bound(framePts_.begin(), framePts_.end(), m.lastPts) - framePts_.begin());
    const bool ahead = started && m.lastPts < target && at + 1 >= key;   // decoding on costs no more
    for (int attempt = 0; attempt < 4; ++attempt) {
        if (!ahead || attempt > 0) {
            while (key > 0 && !frameIsKey_[key]) --key;   // (again, after a step back)
            const bool fromStart = key == 0 || attempt == 3;
            int rc = fromStart ? avformat_seek_file(m.format, m.stream, INT64_MIN, framePts_[0], framePts_[0], 0)
                               : av_seek_frame(m.format, m.stream, framePts_[key], AVSEEK_FLAG_BACKWARD);
            if (rc < 0) rc = avformat_seek_file(m.format, -1, INT64_MIN, 0, INT64_MAX, AVSEEK_FLAG_BYTE);
            if (rc < 0) return makeError(path_ + ": cannot seek (" + avError(rc) + ")");
            avcodec_flush_buffers(m.codec);
            m.lastPts = std::numeric_limits<int64_t>::min();
            m.drained = false;
            ++seeks_;
        }
        while (true) {
            int rc = avcodec_receive_frame(m.codec, m.frame);
            if (rc == 0) {
                const int64_t pts = m.frame->best_effort_timestamp != AV_NOPTS_VALUE ? m.frame->best_effort_timestamp : m.frame->pts;
                ++decoded_;
                m.lastPts = pts;
                if (pts < target) {
                    av_frame_unref(m.frame);
                    continue;
                }
                if (pts > target) {   // the seek landed after the frame: an earlier key frame
                    av_frame_unref(m.frame);
                    break;
                }
                VideoFrame out;
                out.index = index;
                out.time = frameTimes_[index];
                out.width = m.frame->width;
                out.height = m.frame->height;
                m.sws = sws_getCachedContext(m.sws, m.frame->width, m.frame->height, AVPixelFormat(m.frame->format), out.width,
                                             out.height, AV_PIX_FMT_RGBA, SWS_BILINEAR, nullptr, nullptr, nullptr);
                if (!m.sws) {
                    av_frame_unref(m.frame);
                    return makeError(path_ + ": cannot convert the frames' pixel format to RGBA");
                }
                out.rgba.resize(size_t(out.width) * size_t(out.height) * 4);
                uint8_t* dst[4] = {out.rgba.data(), nullptr, nullptr, nullptr};
                const int dstStride[4] = {out.width * 4, 0, 0, 0};
                sws_scale(m.sws, m.frame->data, m.frame->linesize, 0, m.frame->height, dst, dstStride);
                av_frame_unref(m.frame);
                return out;
            }
            if (rc == AVERROR_EOF) break;   // drained without the frame
            if (rc != AVERROR(EAGAIN)) return makeError(path_ + ": decoding failed (" + avError(rc) + ")");
            // The decoder wants input: the next packet of the video stream, or the end.
            if (m.drained) break;
            rc = av_read_frame(m.format, m.packet);
            if (rc == AVERROR_EOF || rc < 0) {
                avcodec_send_packet(m.codec, nullptr);
                m.drained = true;
                continue;
            }
            if (m.packet->stream_index == m.stream) {
                const int sent = avcodec_send_packet(m.codec, m.packet);
                if (sent < 0 && sent != AVERROR(EAGAIN) && sent != AVERROR_INVALIDDATA) {
                    av_packet_unref(m.packet);
                    return makeError(path_ + ": decoding failed (" + avError(sent) + ")");
                }
            }
            av_packet_unref(m.packet);
        }
        // Not found from here: try again from an earlier key frame (the start, at the end).
        if (key > 0) --key;
    }
    return makeError(path_ + ": frame " + std::to_string(index) + " (at " + std::to_string(frameTimes_[index]) +
                     " s) could not be decoded");
}

}  // namespace orbis::fmv
