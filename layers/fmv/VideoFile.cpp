#include "layers/fmv/VideoFile.h"

#include "layers/fmv/AvError.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/imgutils.h>
#include <libswscale/swscale.h>
}

#include <sys/stat.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>

namespace orbis::fmv {
namespace {

Error fail(const std::string& path, const std::string& what) { return makeError(path + ": " + what); }

/// A video packet's presentation time (stream time base) and key flag, in demuxing order.
struct PacketEntry {
    int64_t pts;
    bool key;
};

/// A KLV packet's bytes and time stamp on its own stream's clock.
struct RawKlv {
    int64_t ts;
    AVRational base;
    std::vector<uint8_t> bytes;
};

/// What one pass over the packets finds, without decoding.
struct PacketIndex {
    std::vector<PacketEntry> entries;   // the video frames
    std::vector<RawKlv> klv;
    int64_t frameDuration = 0;          // the longest video packet's, stream time base
};

/// The frames in presentation order, a repeated time stamp once.
struct FrameIndex {
    std::vector<int64_t> pts;
    std::vector<uint8_t> isKey;
    std::vector<double> times;
};

/// What the file at a path is: which inode, its size and time, and a hash of its first 64 KiB
/// (to tell an append from a rewrite). Not known for URLs and devices.
struct OnDisk {
    bool known = false;
    dev_t device = 0;
    ino_t inode = 0;
    off_t size = 0;
    timespec modified{};
    uint64_t prefixHash = 0;   // of the first `hashed` bytes
    off_t hashed = 0;
};

uint64_t prefixHash(const std::string& path, off_t count) {
    std::vector<char> bytes(static_cast<size_t>(count));
    std::ifstream in(path, std::ios::binary);
    if (!in.read(bytes.data(), std::streamsize(bytes.size()))) return 0;
    uint64_t h = 1469598103934665603ull;   // FNV-1a
    for (char c : bytes) h = (h ^ uint8_t(c)) * 1099511628211ull;
    return h;
}

OnDisk statOnDisk(const std::string& path, bool hash) {
    struct stat st {};
    if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return {};
    OnDisk d{true, st.st_dev, st.st_ino, st.st_size, st.st_mtim, 0, std::min<off_t>(st.st_size, 64 * 1024)};
    if (hash) d.prefixHash = prefixHash(path, d.hashed);
    return d;
}

}  // namespace

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
    OnDisk opened;                                            // the file as it was opened
    std::string changed;                                      // why it cannot be read on, once it changed

    ~Impl() {
        sws_freeContext(sws);
        av_frame_free(&frame);
        av_packet_free(&packet);
        avcodec_free_context(&codec);
        avformat_close_input(&format);
    }
    double seconds(int64_t pts) const { return double(pts - firstPts) * av_q2d(timeBase); }

    // Opening, in this order.
    Result<int> openInput(const std::string& path);
    Result<const AVCodec*> describeVideo(const std::string& path, VideoInfo& info);
    Result<PacketIndex> indexPackets(const std::string& path, int klvStream);
    Result<bool> indexPacket(const std::string& path, int klvStream, PacketIndex& index, size_t& klvBytes,
                             int64_t& lastDts);
    FrameIndex frameIndex(std::vector<PacketEntry>& entries);
    std::vector<TimedKlv> klvOnVideoClock(std::vector<RawKlv>& klv) const;
    Result<void> openDecoder(const std::string& path, const AVCodec* decoder, int64_t startPts);

    // Decoding.
    Result<void> seekToKey(const std::string& path, int64_t keyPts, int64_t firstFramePts, bool fromStart);
    Result<bool> receiveFrame(const std::string& path, int64_t target, uint64_t& decoded);
    Result<bool> feedDecoder(const std::string& path);
    Result<VideoFrame> toRgba(const std::string& path, size_t index, double time, int width, int height);
    Result<void> checkOnDisk(const std::string& path);
};

/// Opens the container and picks the video stream (the first that is not a cover picture) and
/// the KLV stream; returns the KLV stream's index, -1 without one.
Result<int> VideoFile::Impl::openInput(const std::string& path) {
    if (int rc = avformat_open_input(&format, path.c_str(), nullptr, nullptr); rc < 0)
        return fail(path, "cannot open as a video (" + avError(rc) + ")");
    if (int rc = avformat_find_stream_info(format, nullptr); rc < 0)
        return fail(path, "cannot read the streams (" + avError(rc) + ")");
    int klvStream = -1;
    for (unsigned i = 0; i < format->nb_streams; ++i) {
        const AVCodecParameters* p = format->streams[i]->codecpar;
        if (p->codec_type == AVMEDIA_TYPE_VIDEO && stream < 0 && !(format->streams[i]->disposition & AV_DISPOSITION_ATTACHED_PIC))
            stream = int(i);
        if (p->codec_id == AV_CODEC_ID_SMPTE_KLV && klvStream < 0) klvStream = int(i);
    }
    return klvStream;
}

/// The video stream's decoder, size, codec and frame rate.
Result<const AVCodec*> VideoFile::Impl::describeVideo(const std::string& path, VideoInfo& info) {
    AVStream* st = format->streams[stream];
    const AVCodec* decoder = avcodec_find_decoder(st->codecpar->codec_id);
    if (!decoder) return fail(path, std::string("no decoder for its video codec ").append(avcodec_get_name(st->codecpar->codec_id)));
    if (st->codecpar->width <= 0 || st->codecpar->height <= 0 || st->codecpar->width > kMaxDimension ||
        st->codecpar->height > kMaxDimension)
        return fail(path, "video size " + std::to_string(st->codecpar->width) + "x" + std::to_string(st->codecpar->height) +
                              " is outside 1.." + std::to_string(kMaxDimension));
    timeBase = st->time_base;
    info.width = st->codecpar->width;
    info.height = st->codecpar->height;
    info.codec = avcodec_get_name(st->codecpar->codec_id);
    const AVRational rate = st->avg_frame_rate.num > 0 ? st->avg_frame_rate : st->r_frame_rate;
    info.frameRate = rate.num > 0 && rate.den > 0 ? av_q2d(rate) : 0.0;
    return decoder;
}

/// One pass over the packets: the video frames' times and key flags, and the KLV packets.
Result<PacketIndex> VideoFile::Impl::indexPackets(const std::string& path, int klvStream) {
    packet = av_packet_alloc();
    frame = av_frame_alloc();
    PacketIndex index;
    size_t klvBytes = 0;
    int64_t lastDts = AV_NOPTS_VALUE;
    while (true) {
        const int rc = av_read_frame(format, packet);
        if (rc == AVERROR_EOF) break;
        if (rc < 0) return fail(path, "read error in the container (" + avError(rc) + ")");
        auto ok = indexPacket(path, klvStream, index, klvBytes, lastDts);
        av_packet_unref(packet);
        if (!ok) return ok.error();
    }
    return index;
}

/// The packet just read into the index. Errors on frames without time stamps and over the limits.
Result<bool> VideoFile::Impl::indexPacket(const std::string& path, int klvStream, PacketIndex& index, size_t& klvBytes,
                                          int64_t& lastDts) {
    const AVPacket& p = *packet;
    if (p.stream_index == stream) {
        int64_t pts = p.pts != AV_NOPTS_VALUE ? p.pts : p.dts;
        if (pts == AV_NOPTS_VALUE) {   // no time stamps at all: count on from the last
            if (lastDts == AV_NOPTS_VALUE) return fail(path, "video frames without time stamps");
            pts = lastDts + std::max<int64_t>(p.duration, 1);
        }
        lastDts = pts;
        index.frameDuration = std::max<int64_t>(index.frameDuration, p.duration);
        index.entries.push_back({pts, (p.flags & AV_PKT_FLAG_KEY) != 0});
        if (index.entries.size() > kMaxFrames) return fail(path, "more than " + std::to_string(kMaxFrames) + " frames");
    } else if (p.stream_index == klvStream && p.size > 0) {
        klvBytes += size_t(p.size);
        if (klvBytes > kMaxKlvBytes)
            return fail(path, "more than " + std::to_string(kMaxKlvBytes >> 20) + " MB of KLV metadata");
        const int64_t ts = p.pts != AV_NOPTS_VALUE ? p.pts : p.dts;
        index.klv.push_back({ts, format->streams[klvStream]->time_base, std::vector<uint8_t>(p.data, p.data + p.size)});
    }
    return true;
}

/// The frames in presentation order; sets firstPts. `entries` must not be empty.
FrameIndex VideoFile::Impl::frameIndex(std::vector<PacketEntry>& entries) {
    std::stable_sort(entries.begin(), entries.end(), [](const PacketEntry& a, const PacketEntry& b) { return a.pts < b.pts; });
    firstPts = entries.front().pts;
    FrameIndex out;
    for (const PacketEntry& e : entries) {
        if (!out.pts.empty() && e.pts == out.pts.back()) continue;   // a repeated time stamp
        out.pts.push_back(e.pts);
        out.isKey.push_back(e.key ? 1 : 0);
        out.times.push_back(seconds(e.pts));
    }
    out.isKey[0] = 1;   // decoding starts at the start whatever the flags say
    return out;
}

/// KLV times on the video's clock (both streams share the container's clock), in time order.
std::vector<TimedKlv> VideoFile::Impl::klvOnVideoClock(std::vector<RawKlv>& klv) const {
    std::vector<TimedKlv> out;
    for (RawKlv& k : klv) {
        const double t = k.ts == AV_NOPTS_VALUE ? 0.0
                                                : double(av_rescale_q(k.ts, k.base, timeBase) - firstPts) * av_q2d(timeBase);
        out.push_back({t, std::move(k.bytes)});
    }
    std::stable_sort(out.begin(), out.end(), [](const TimedKlv& a, const TimedKlv& b) { return a.time < b.time; });
    return out;
}

/// The decoder, then back to the start.
Result<void> VideoFile::Impl::openDecoder(const std::string& path, const AVCodec* decoder, int64_t startPts) {
    codec = avcodec_alloc_context3(decoder);
    if (!codec || avcodec_parameters_to_context(codec, format->streams[stream]->codecpar) < 0)
        return fail(path, "cannot set up the video decoder");
    codec->flags &= ~AV_CODEC_FLAG_OUTPUT_CORRUPT;   // frames before a key frame are dropped, not shown broken
    codec->thread_count = 1;                         // the layer decodes on a worker already
    if (int rc = avcodec_open2(codec, decoder, nullptr); rc < 0) return fail(path, "cannot open the video decoder (" + avError(rc) + ")");
    if (av_seek_frame(format, stream, startPts, AVSEEK_FLAG_BACKWARD) < 0)
        avformat_seek_file(format, -1, INT64_MIN, 0, INT64_MAX, AVSEEK_FLAG_BYTE);
    return {};
}

VideoFile::~VideoFile() = default;

Result<std::unique_ptr<VideoFile>> VideoFile::open(const std::string& path) {
    std::unique_ptr<VideoFile> v(new VideoFile);
    v->path_ = path;
    v->impl_ = std::make_unique<Impl>();
    Impl& m = *v->impl_;
    av_log_set_level(AV_LOG_ERROR);
    const OnDisk before = statOnDisk(path, false);
    const auto klvStream = m.openInput(path);
    if (!klvStream) return klvStream.error();
    if (const OnDisk after = statOnDisk(path, true); before.known && after.known && before.inode == after.inode)
        m.opened = after;
    v->info_.hasKlv = *klvStream >= 0;
    if (m.stream < 0) return fail(path, *klvStream >= 0 ? "has KLV metadata but no video stream" : "has no video stream");
    const auto decoder = m.describeVideo(path, v->info_);
    if (!decoder) return decoder.error();

    auto packets = m.indexPackets(path, *klvStream);
    if (!packets) return packets.error();
    if (packets->entries.empty()) return fail(path, "the video stream has no frames");
    FrameIndex frames = m.frameIndex(packets->entries);
    v->framePts_ = std::move(frames.pts);
    v->frameIsKey_ = std::move(frames.isKey);
    v->frameTimes_ = std::move(frames.times);
    const double last = v->frameTimes_.back();
    const double step = packets->frameDuration > 0 ? double(packets->frameDuration) * av_q2d(m.timeBase)
                        : v->info_.frameRate > 0   ? 1.0 / v->info_.frameRate
                                                   : 0.0;
    v->info_.duration = last + step;
    if (v->info_.frameRate <= 0.0 && v->frameTimes_.size() > 1) v->info_.frameRate = double(v->frameTimes_.size() - 1) / last;
    v->klv_ = m.klvOnVideoClock(packets->klv);

    if (auto r = m.openDecoder(path, *decoder, v->framePts_[0]); !r) return r.error();
    return v;
}

size_t VideoFile::frameAt(double t) const {
    const auto it = std::upper_bound(frameTimes_.begin(), frameTimes_.end(), t);
    return it == frameTimes_.begin() ? 0 : size_t(it - frameTimes_.begin()) - 1;
}

/// Seeks to the key frame at `keyPts` (the start when `fromStart`) and resets the decoder.
Result<void> VideoFile::Impl::seekToKey(const std::string& path, int64_t keyPts, int64_t firstFramePts, bool fromStart) {
    int rc = fromStart ? avformat_seek_file(format, stream, INT64_MIN, firstFramePts, firstFramePts, 0)
                       : av_seek_frame(format, stream, keyPts, AVSEEK_FLAG_BACKWARD);
    if (rc < 0) rc = avformat_seek_file(format, -1, INT64_MIN, 0, INT64_MAX, AVSEEK_FLAG_BYTE);
    if (rc < 0) return makeError(path + ": cannot seek (" + avError(rc) + ")");
    avcodec_flush_buffers(codec);
    lastPts = std::numeric_limits<int64_t>::min();
    drained = false;
    return {};
}

/// Decodes on until the frame at `target` comes out: true with it in `frame`; false when it
/// does not come from here (the stream ended, or the seek landed after it).
Result<bool> VideoFile::Impl::receiveFrame(const std::string& path, int64_t target, uint64_t& decoded) {
    while (true) {
        const int rc = avcodec_receive_frame(codec, frame);
        if (rc == 0) {
            const int64_t pts = frame->best_effort_timestamp != AV_NOPTS_VALUE ? frame->best_effort_timestamp : frame->pts;
            ++decoded;
            lastPts = pts;
            if (pts == target) return true;
            av_frame_unref(frame);
            if (pts > target) return false;   // the seek landed after the frame: an earlier key frame
            continue;
        }
        if (rc == AVERROR_EOF) return false;   // drained without the frame
        if (rc != AVERROR(EAGAIN)) return makeError(path + ": decoding failed (" + avError(rc) + ")");
        auto fed = feedDecoder(path);
        if (!fed) return fed.error();
        if (!*fed) return false;
    }
}

/// The decoder wants input: the next packet of the video stream, or the end. False when the end
/// was given already.
Result<bool> VideoFile::Impl::feedDecoder(const std::string& path) {
    if (drained) return false;
    const int rc = av_read_frame(format, packet);
    if (rc == AVERROR_EOF || rc < 0) {
        avcodec_send_packet(codec, nullptr);
        drained = true;
        return true;
    }
    if (packet->stream_index == stream) {
        const int sent = avcodec_send_packet(codec, packet);
        if (sent < 0 && sent != AVERROR(EAGAIN) && sent != AVERROR_INVALIDDATA) {
            av_packet_unref(packet);
            return makeError(path + ": decoding failed (" + avError(sent) + ")");
        }
    }
    av_packet_unref(packet);
    return true;
}

/// The decoded `frame` as RGBA at the size the stream was opened with (a stream that changes
/// size mid-way is scaled: its consumers hold images of the first size); releases it.
Result<VideoFrame> VideoFile::Impl::toRgba(const std::string& path, size_t index, double time, int width, int height) {
    VideoFrame out;
    out.index = index;
    out.time = time;
    out.width = width;
    out.height = height;
    sws = sws_getCachedContext(sws, frame->width, frame->height, AVPixelFormat(frame->format), out.width, out.height,
                               AV_PIX_FMT_RGBA, SWS_BILINEAR, nullptr, nullptr, nullptr);
    if (!sws) {
        av_frame_unref(frame);
        return makeError(path + ": cannot convert the frames' pixel format to RGBA");
    }
    out.rgba.resize(size_t(out.width) * size_t(out.height) * 4);
    uint8_t* dst[4] = {out.rgba.data(), nullptr, nullptr, nullptr};
    const int dstStride[4] = {out.width * 4, 0, 0, 0};
    sws_scale(sws, frame->data, frame->linesize, 0, frame->height, dst, dstStride);
    av_frame_unref(frame);
    return out;
}

/// The open handle keeps reading the file it opened when another is renamed over the path, so
/// only a change to that file itself matters: an append (a recording still being written) reads
/// on; a rewrite (new size or time, and other first bytes, or a shorter file) stops the reads
/// with a message, rather than decoding another file's bytes at this one's offsets.
Result<void> VideoFile::Impl::checkOnDisk(const std::string& path) {
    if (!changed.empty()) return makeError(changed);
    if (!opened.known) return {};
    OnDisk now = statOnDisk(path, false);
    if (!now.known || now.device != opened.device || now.inode != opened.inode) return {};   // renamed over or removed
    if (now.size == opened.size && now.modified.tv_sec == opened.modified.tv_sec &&
        now.modified.tv_nsec == opened.modified.tv_nsec)
        return {};
    if (now.size > opened.size && prefixHash(path, opened.hashed) == opened.prefixHash) {
        opened.size = now.size, opened.modified = now.modified;   // appended to
        return {};
    }
    changed = path + ": the file was rewritten since it was opened (" + std::to_string(opened.size) + " bytes then, " +
              std::to_string(now.size) + " now); open the scene again to read the new file";
    return makeError(changed);
}

Result<VideoFrame> VideoFile::decode(size_t index) {
    Impl& m = *impl_;
    if (index >= framePts_.size())
        return makeError(path_ + ": frame " + std::to_string(index) + " does not exist (" + std::to_string(framePts_.size()) + " frames)");
    if (auto r = m.checkOnDisk(path_); !r) return r.error();
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
            if (auto r = m.seekToKey(path_, framePts_[key], framePts_[0], fromStart); !r) return r.error();
            ++seeks_;
        }
        auto found = m.receiveFrame(path_, target, decoded_);
        if (!found) return found.error();
        if (*found) return m.toRgba(path_, index, frameTimes_[index], info_.width, info_.height);
        // Not found from here: try again from an earlier key frame (the start, at the end).
        if (key > 0) --key;
    }
    return makeError(path_ + ": frame " + std::to_string(index) + " (at " + std::to_string(frameTimes_[index]) +
                     " s) could not be decoded");
}

}  // namespace orbis::fmv
