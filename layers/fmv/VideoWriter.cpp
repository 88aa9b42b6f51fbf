#include "layers/fmv/VideoWriter.h"

#include "layers/fmv/AvError.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include <cmath>

namespace orbis::fmv {

struct VideoWriter::Impl {
    AVFormatContext* format = nullptr;
    AVCodecContext* codec = nullptr;
    SwsContext* sws = nullptr;
    AVFrame* frame = nullptr;
    AVPacket* packet = nullptr;
    AVStream* video = nullptr;
    AVStream* klv = nullptr;
    bool headerWritten = false;
    std::function<bool()> interrupted;

    bool stop() const { return interrupted && interrupted(); }

    ~Impl() {
        sws_freeContext(sws);
        av_frame_free(&frame);
        av_packet_free(&packet);
        avcodec_free_context(&codec);
        if (format) {
            if (format->pb) avio_closep(&format->pb);
            avformat_free_context(format);
        }
    }
};

VideoWriter::~VideoWriter() {
    if (!closed_ && impl_ && impl_->headerWritten) (void)close();
}

Result<std::unique_ptr<VideoWriter>> VideoWriter::create(const std::string& path, const VideoWriteOptions& o) {
    std::unique_ptr<VideoWriter> w(new VideoWriter);
    w->path_ = path;
    w->options_ = o;
    w->impl_ = std::make_unique<Impl>();
    Impl& m = *w->impl_;
    const auto fail = [&](const std::string& what) { return makeError(path + ": " + what); };
    if (o.width <= 0 || o.height <= 0 || o.width % 2 || o.height % 2 || o.fps <= 0 || o.gop <= 0)
        return fail("a video needs an even width and height, fps > 0 and gop > 0");
    av_log_set_level(AV_LOG_ERROR);
    const auto scheme = [&](const char* name) { return path.rfind(std::string(name) + "://", 0) == 0; };
    if (o.listen && !(o.live && (scheme("tcp") || scheme("srt") || scheme("http"))))
        return fail("only a live tcp://, srt:// or http:// stream can wait for its receiver");
    const char* muxerName = o.live && scheme("rtp") ? "rtp_mpegts" : "mpegts";
    if (scheme("srt")) startSrtOnce();
    if (int rc = avformat_alloc_output_context2(&m.format, nullptr, muxerName, path.c_str()); rc < 0 || !m.format)
        return fail("cannot make an MPEG-TS (" + avError(rc) + ")");
    if (!o.withVideo && !o.withKlv) return fail("a file needs a video or a KLV stream");
    if (o.withVideo) {
        const AVCodec* encoder = avcodec_find_encoder(AV_CODEC_ID_H264);
        if (!encoder) encoder = avcodec_find_encoder(AV_CODEC_ID_MPEG2VIDEO);
        if (!encoder) return fail("FFmpeg has neither an H.264 nor an MPEG-2 encoder");
        m.video = avformat_new_stream(m.format, nullptr);
        m.codec = avcodec_alloc_context3(encoder);
        m.codec->width = o.width;
        m.codec->height = o.height;
        m.codec->time_base = AVRational{1, o.fps};
        m.codec->framerate = AVRational{o.fps, 1};
        m.codec->gop_size = o.gop;
        m.codec->max_b_frames = 0;   // presentation order = decoding order
        m.codec->pix_fmt = AV_PIX_FMT_YUV420P;
        m.codec->thread_count = 1;
        if (m.format->oformat->flags & AVFMT_GLOBALHEADER) m.codec->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
        if (encoder->id == AV_CODEC_ID_H264) {
            av_opt_set(m.codec->priv_data, "preset", "veryfast", 0);
            av_opt_set(m.codec->priv_data, "crf", std::to_string(o.crf).c_str(), 0);
            av_opt_set(m.codec->priv_data, "x264-params", "scenecut=0", 0);   // key frames every gop exactly
            if (o.live) av_opt_set(m.codec->priv_data, "tune", "zerolatency", 0);
        } else {
            m.codec->bit_rate = int64_t(o.width) * o.height * o.fps;
        }
        if (int rc = avcodec_open2(m.codec, encoder, nullptr); rc < 0)
            return fail("cannot open the video encoder (" + avError(rc) + ")");
        avcodec_parameters_from_context(m.video->codecpar, m.codec);
        m.video->time_base = m.codec->time_base;
    }
    if (o.withKlv) {
        m.klv = avformat_new_stream(m.format, nullptr);
        m.klv->codecpar->codec_type = AVMEDIA_TYPE_DATA;
        m.klv->codecpar->codec_id = AV_CODEC_ID_SMPTE_KLV;
        m.klv->codecpar->profile = o.klvSynchronous ? FF_PROFILE_KLVA_SYNC : FF_PROFILE_KLVA_ASYNC;
        m.klv->time_base = AVRational{1, 90000};
    }
    std::string target = path;
    if (o.live) {
        m.format->flags |= AVFMT_FLAG_FLUSH_PACKETS;
        const auto addOption = [&](const char* key, const char* value) {
            if (target.find(std::string(key) + "=") != std::string::npos) return;
            target += std::string(target.find('?') == std::string::npos ? "?" : "&") + key + "=" + value;
        };
        if (scheme("udp")) addOption("pkt_size", "1316");
        // FFmpeg's RTP muxer fills each datagram with TS packets before it sends it, so the tail
        // of a frame would wait for the next frame: one TS packet a datagram (188 + the RTP
        // header) sends each frame whole as it is written.
        if (scheme("rtp")) addOption("pkt_size", "200");
        // SRT in live mode drops what is still unsent when the socket closes (linger 0): the
        // last frames of a stream would never arrive. Linger up to a second for them.
        if (scheme("srt")) addOption("linger", "1");
        if (o.listen && scheme("tcp")) addOption("listen", "1");
        if (o.listen && scheme("srt")) addOption("mode", "listener");
    }
    // http:// takes its options from the dictionary, not from the URL (which it requests).
    AVDictionary* protocol = nullptr;
    if (o.listen && scheme("http")) av_dict_set(&protocol, "listen", "1", 0);
    m.interrupted = o.interrupted;
    const AVIOInterruptCB interrupt{[](void* self) { return int(static_cast<Impl*>(self)->stop()); }, &m};
    const int opened = avio_open2(&m.format->pb, target.c_str(), AVIO_FLAG_WRITE, &interrupt, &protocol);
    av_dict_free(&protocol);
    if (opened < 0) return fail(std::string(o.live ? "cannot send the stream (" : "cannot write the file (") + avError(opened) + ")");
    AVDictionary* muxer = nullptr;
    // Live: each video PES says its length, so that a receiver's demuxer hands a frame on when
    // its last byte arrives instead of when the next frame starts.
    if (o.live) av_dict_set(&muxer, muxerName == std::string("rtp_mpegts") ? "mpegts_muxer_options" : "omit_video_pes_length",
                            muxerName == std::string("rtp_mpegts") ? "omit_video_pes_length=0" : "0", 0);
    const int header = avformat_write_header(m.format, &muxer);
    av_dict_free(&muxer);
    if (header < 0) return fail("cannot write the header (" + avError(header) + ")");
    m.headerWritten = true;
    if (!o.withVideo) return w;
    m.frame = av_frame_alloc();
    m.frame->format = m.codec->pix_fmt;
    m.frame->width = o.width;
    m.frame->height = o.height;
    if (av_frame_get_buffer(m.frame, 0) < 0) return fail("out of memory for a frame");
    m.packet = av_packet_alloc();
    m.sws = sws_getContext(o.width, o.height, AV_PIX_FMT_RGBA, o.width, o.height, AV_PIX_FMT_YUV420P, SWS_BILINEAR, nullptr,
                           nullptr, nullptr);
    if (!m.sws) return fail("cannot convert RGBA to YUV 4:2:0");
    return w;
}

int VideoWriter::write(AVPacket* packet) {
    // Live: out at once (interleaving would hold a packet until the other stream passes it).
    return options_.live ? av_write_frame(impl_->format, packet) : av_interleaved_write_frame(impl_->format, packet);
}

Result<void> VideoWriter::drain(bool flush) {
    Impl& m = *impl_;
    if (!m.codec) return {};
    if (flush) avcodec_send_frame(m.codec, nullptr);
    while (true) {
        const int rc = avcodec_receive_packet(m.codec, m.packet);
        if (rc == AVERROR(EAGAIN) || rc == AVERROR_EOF) return {};
        if (rc < 0) return makeError(path_ + ": encoding failed (" + avError(rc) + ")");
        av_packet_rescale_ts(m.packet, m.codec->time_base, m.video->time_base);
        m.packet->stream_index = m.video->index;
        if (int w = write(m.packet); w < 0)
            return makeError(path_ + ": cannot write a frame (" + avError(w) + ")");
    }
}

Result<void> VideoWriter::writeFrame(std::span<const uint8_t> rgba) {
    Impl& m = *impl_;
    if (closed_) return makeError(path_ + ": already closed");
    if (!m.codec) return makeError(path_ + ": made without a video stream");
    if (rgba.size() != size_t(options_.width) * size_t(options_.height) * 4)
        return makeError(path_ + ": a frame must be " + std::to_string(options_.width) + "x" + std::to_string(options_.height) + " RGBA");
    if (av_frame_make_writable(m.frame) < 0) return makeError(path_ + ": out of memory for a frame");
    const uint8_t* src[4] = {rgba.data(), nullptr, nullptr, nullptr};
    const int srcStride[4] = {options_.width * 4, 0, 0, 0};
    sws_scale(m.sws, src, srcStride, 0, options_.height, m.frame->data, m.frame->linesize);
    m.frame->pts = frames_++;
    if (int rc = avcodec_send_frame(m.codec, m.frame); rc < 0) return makeError(path_ + ": encoding failed (" + avError(rc) + ")");
    return drain(false);
}

Result<void> VideoWriter::writeKlv(double time, std::span<const uint8_t> bytes) {
    Impl& m = *impl_;
    if (closed_) return makeError(path_ + ": already closed");
    if (!m.klv) return makeError(path_ + ": made without a KLV stream");
    if (!(time >= 0.0) || bytes.empty()) return makeError(path_ + ": a KLV packet needs a time >= 0 and bytes");
    if (bytes.size() > 65535) return makeError(path_ + ": a KLV packet over 65535 bytes");
    // Synchronous metadata goes in Metadata AU cells (ISO 13818-1 2.12.4): a 5-byte header
    // (service id, sequence number, one whole cell, random access, the cell's length) that
    // libavformat's muxer leaves to the caller and its demuxer strips.
    const size_t header = options_.klvSynchronous ? 5 : 0;
    AVPacket* p = av_packet_alloc();
    if (!p || av_new_packet(p, int(bytes.size() + header)) < 0) {
        av_packet_free(&p);
        return makeError(path_ + ": out of memory for a KLV packet");
    }
    if (header) {
        p->data[0] = 0;                                  // metadata_service_id
        p->data[1] = uint8_t(klvPackets_);               // sequence_number
        p->data[2] = 0xDF;                               // 11 (complete cell), 0 (no config), 1 (random access), 1111
        p->data[3] = uint8_t(bytes.size() >> 8);         // AU_cell_data_length
        p->data[4] = uint8_t(bytes.size() & 0xFF);
    }
    ++klvPackets_;
    std::copy(bytes.begin(), bytes.end(), p->data + header);
    p->stream_index = m.klv->index;
    p->pts = p->dts = av_rescale_q(int64_t(std::llround(time * 90000.0)), AVRational{1, 90000}, m.klv->time_base);
    const int rc = write(p);
    av_packet_free(&p);
    if (rc < 0) return makeError(path_ + ": cannot write a KLV packet (" + avError(rc) + ")");
    return {};
}

Result<void> VideoWriter::close() {
    if (closed_) return {};
    closed_ = true;
    Impl& m = *impl_;
    auto drained = drain(true);
    const int rc = av_write_trailer(m.format);
    if (!drained) return drained;
    if (rc < 0) return makeError(path_ + ": cannot finish the file (" + avError(rc) + ")");
    avio_closep(&m.format->pb);
    return {};
}

}  // namespace orbis::fmv
