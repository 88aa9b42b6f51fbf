#pragma once
// The MPEG-TS recording of a live stream's packets as they arrive (private to the FMV video
// library; LiveVideo's worker thread only). A recording starts at a key frame, with the KLV
// packets of the second before it; it goes on across sessions and clock jumps, its times moved
// to follow what was written after the silence; a stream that comes back with another video
// size or codec ends it.

extern "C" {
#include <libavutil/rational.h>
}

#include <cstdint>
#include <deque>
#include <string>

struct AVFormatContext;
struct AVPacket;

namespace orbis::fmv {

class LiveRecording {
public:
    LiveRecording() = default;
    LiveRecording(const LiveRecording&) = delete;
    LiveRecording& operator=(const LiveRecording&) = delete;
    ~LiveRecording();

    /// The file asked for ("" for none), open or waiting for a key frame.
    const std::string& path() const { return path_; }
    /// Ends the current file and makes `path` the next one ("" for none), which waits for a key
    /// frame. Nothing changes when `path` is already open or waiting.
    void restart(const std::string& path);
    /// A new session on `in` (its video and KLV streams; klv -1 for none): an open file goes on,
    /// or ends when the video came back different (the reason is returned, and the path
    /// forgotten); a file not open yet waits for a key frame. Drops the KLV kept so far.
    std::string newSession(AVFormatContext* in, int video, int klv);
    /// The stream's clock jumped within a session: the file goes on after the jump, its video
    /// from the next key frame.
    void clockJumped();
    /// A KLV packet: written into the open file, or kept (the last second) while the file waits
    /// for its key frame. Whether it was written.
    bool klv(const AVPacket& packet, AVRational base);
    /// A video packet of `in`: a waiting file opens at a key frame, with the KLV kept, and the
    /// packet goes in. The packets written; `error` says why a file could not be opened.
    int video(AVFormatContext* in, int video, int klv, const AVPacket& packet, std::string& error);
    void close();

private:
    /// Opens the file for `in`'s streams; "" or why not.
    std::string open(AVFormatContext* in, int video, int klv);
    bool write(const AVPacket& packet);

    std::string path_;
    bool pending_ = false;               // waiting for a key frame to open
    std::deque<AVPacket*> recentKlv_;    // the KLV of the last second while pending
    /// The open file (format null when none).
    struct File {
        AVFormatContext* format = nullptr;
        int inVideo = -1, inKlv = -1, outVideo = -1, outKlv = -1;
        AVRational inBase[2] = {{1, 1}, {1, 1}};
        bool klvSynchronous = false;
        int64_t lastDts[2] = {INT64_MIN, INT64_MIN};   // written, in the output's time bases
        uint8_t klvSequence = 0;
        uint64_t sinceFlush = 0;
        // A stream that comes back (a new session, maybe a new clock) goes on in the same file:
        // its times are moved to follow what was written, after the silence between.
        int width = 0, height = 0, codec = 0;   // the video recorded
        double offsetSeconds = 0.0;             // added to the session's times
        double endSeconds = 0.0, endSteady = 0.0;   // the latest time written, and when
        bool written = false;
        bool rebase = false;    // a new session: its first packet sets offsetSeconds
        bool waitKey = false;   // the new session's video from its first key frame
    } file_;
};

}  // namespace orbis::fmv
