#include "layers/fmv/LiveRecording.h"

#include "layers/fmv/AvError.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
}

#include <algorithm>
#include <chrono>
#include <cmath>

namespace orbis::fmv {
namespace {

double steadySeconds() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

}  // namespace

LiveRecording::~LiveRecording() {
    close();
    for (AVPacket* p : recentKlv_) av_packet_free(&p);
}

void LiveRecording::close() {
    if (!file_.format) return;
    av_write_trailer(file_.format);
    if (file_.format->pb) avio_closep(&file_.format->pb);
    avformat_free_context(file_.format);
    file_.format = nullptr;
}

void LiveRecording::restart(const std::string& path) {
    if (path == path_ && (file_.format || pending_)) return;
    close();
    file_ = File();
    path_ = path;
    pending_ = !path.empty();
}

std::string LiveRecording::newSession(AVFormatContext* in, int video, int klv) {
    for (AVPacket* p : recentKlv_) av_packet_free(&p);
    recentKlv_.clear();
    if (!file_.format) {
        pending_ = !path_.empty();
        return {};
    }
    File& r = file_;
    const AVCodecParameters* p = in->streams[video]->codecpar;
    if (p->width != r.width || p->height != r.height || int(p->codec_id) != r.codec) {
        close();
        const std::string why = path_ + ": the stream came back as " + std::to_string(p->width) + "x" +
                                std::to_string(p->height) + " " + avcodec_get_name(p->codec_id) +
                                ", not as recorded: the recording ends there";
        path_.clear();
        pending_ = false;
        return why;
    }
    r.inVideo = video;
    r.inBase[0] = in->streams[video]->time_base;
    r.inKlv = r.outKlv >= 0 ? klv : -1;
    if (klv >= 0) r.inBase[1] = in->streams[klv]->time_base;
    r.rebase = r.waitKey = true;
    pending_ = false;
    return {};
}

void LiveRecording::clockJumped() {
    if (file_.format) file_.rebase = file_.waitKey = true;
}

bool LiveRecording::klv(const AVPacket& packet, AVRational base) {
    if (file_.format) return write(packet);
    if (!pending_) return false;
    AVPacket* p = av_packet_clone(&packet);
    if (!p) return false;
    recentKlv_.push_back(p);
    const auto seconds = [&](const AVPacket* q) { return q->dts == AV_NOPTS_VALUE ? 0.0 : double(q->dts) * av_q2d(base); };
    while (recentKlv_.size() > 64 || (recentKlv_.size() > 1 && seconds(recentKlv_.back()) - seconds(recentKlv_.front()) > 1.0)) {
        av_packet_free(&recentKlv_.front());
        recentKlv_.pop_front();
    }
    return false;
}

int LiveRecording::video(AVFormatContext* in, int video, int klv, const AVPacket& packet, std::string& error) {
    int written = 0;
    if (pending_ && (packet.flags & AV_PKT_FLAG_KEY)) {
        pending_ = false;
        error = open(in, video, klv);
        for (AVPacket* k : recentKlv_) {
            if (file_.format) written += write(*k);
            av_packet_free(&k);
        }
        recentKlv_.clear();
    }
    if (file_.format) written += write(packet);
    return written;
}

std::string LiveRecording::open(AVFormatContext* in, int video, int klv) {
    File& r = file_;
    const auto failed = [&](const std::string& why) {
        if (r.format) {
            if (r.format->pb) avio_closep(&r.format->pb);
            avformat_free_context(r.format);
            r.format = nullptr;
        }
        return path_ + ": cannot record (" + why + ")";
    };
    if (int rc = avformat_alloc_output_context2(&r.format, nullptr, "mpegts", path_.c_str()); rc < 0 || !r.format)
        return failed(avError(rc));
    const auto add = [&](int index) {
        AVStream* out = avformat_new_stream(r.format, nullptr);
        if (!out || avcodec_parameters_copy(out->codecpar, in->streams[index]->codecpar) < 0) return -1;
        out->codecpar->codec_tag = 0;
        out->time_base = in->streams[index]->time_base;
        return out->index;
    };
    r.inVideo = video;
    r.outVideo = add(video);
    r.inBase[0] = in->streams[video]->time_base;
    r.width = in->streams[video]->codecpar->width;
    r.height = in->streams[video]->codecpar->height;
    r.codec = int(in->streams[video]->codecpar->codec_id);
    if (klv >= 0) {
        r.inKlv = klv;
        r.outKlv = add(klv);
        r.inBase[1] = in->streams[klv]->time_base;
        r.klvSynchronous = in->streams[klv]->codecpar->profile == FF_PROFILE_KLVA_SYNC;
    }
    if (r.outVideo < 0 || (klv >= 0 && r.outKlv < 0)) return failed("cannot copy the streams");
    if (int rc = avio_open(&r.format->pb, path_.c_str(), AVIO_FLAG_WRITE); rc < 0) return failed(avError(rc));
    if (int rc = avformat_write_header(r.format, nullptr); rc < 0) return failed(avError(rc));
    return {};
}

bool LiveRecording::write(const AVPacket& packet) {
    File& r = file_;
    const bool isVideo = packet.stream_index == r.inVideo, isKlv = r.inKlv >= 0 && packet.stream_index == r.inKlv;
    if (!isVideo && !isKlv) return false;
    const int slot = isVideo ? 0 : 1;
    if (r.rebase && packet.dts != AV_NOPTS_VALUE) {
        r.offsetSeconds = (r.written ? r.endSeconds + std::max(steadySeconds() - r.endSteady, 0.001) : 0.0) -
                          double(packet.dts) * av_q2d(r.inBase[slot]);
        r.rebase = false;
    }
    if (isVideo && r.waitKey) {
        if (!(packet.flags & AV_PKT_FLAG_KEY)) return false;
        r.waitKey = false;
    }
    AVPacket* p = nullptr;
    if (isKlv && r.klvSynchronous) {
        // The demuxer took the Metadata AU cell header off; the muxer wants it back
        // (VideoWriter::writeKlv).
        p = av_packet_alloc();
        if (!p || packet.size > 65535 || av_new_packet(p, packet.size + 5) < 0) {
            av_packet_free(&p);
            return false;
        }
        p->data[0] = 0;
        p->data[1] = r.klvSequence++;
        p->data[2] = 0xDF;
        p->data[3] = uint8_t(packet.size >> 8);
        p->data[4] = uint8_t(packet.size & 0xFF);
        std::copy(packet.data, packet.data + packet.size, p->data + 5);
        av_packet_copy_props(p, &packet);
    } else {
        p = av_packet_clone(&packet);
        if (!p) return false;
    }
    p->stream_index = isVideo ? r.outVideo : r.outKlv;
    p->flags &= ~AV_PKT_FLAG_CORRUPT;
    const AVRational outBase = r.format->streams[p->stream_index]->time_base;
    av_packet_rescale_ts(p, r.inBase[slot], outBase);
    if (r.offsetSeconds != 0.0) {
        const int64_t shift = std::llround(r.offsetSeconds / av_q2d(outBase));
        if (p->pts != AV_NOPTS_VALUE) p->pts += shift;
        if (p->dts != AV_NOPTS_VALUE) p->dts += shift;
    }
    if (p->dts != AV_NOPTS_VALUE) {
        if (p->dts <= r.lastDts[slot]) {   // going back (a clock jump within a session): not muxable
            av_packet_free(&p);
            return false;
        }
        r.lastDts[slot] = p->dts;
        r.endSeconds = std::max(r.endSeconds, double(p->dts) * av_q2d(outBase));
        r.endSteady = steadySeconds();
        r.written = true;
    }
    const int rc = av_interleaved_write_frame(r.format, p);
    av_packet_free(&p);
    if (++r.sinceFlush >= 30 && r.format->pb) {
        avio_flush(r.format->pb);
        r.sinceFlush = 0;
    }
    return rc >= 0;
}

}  // namespace orbis::fmv
