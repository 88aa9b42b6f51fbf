#pragma once
// The interface of a byte-stream decoder that turns what a socket delivers into Fixes: NMEA 0183
// (NmeaDecoder.h) or the XML position message (XmlFix.h). Decoders are incremental (a message
// may be split across reads, and one read may hold many), bounded (no buffer grows with the
// input: an endless line or message is dropped and counted), and never throw on bad input.
//
// Not thread-safe: one decoder belongs to one reader thread.

#include "formats/livefeed/Fix.h"

#include <chrono>
#include <memory>
#include <string_view>
#include <vector>

namespace orbis::livefeed {

enum class FeedProtocol : std::uint8_t {
    Auto,   ///< decided by the first significant byte of each connection: '$' or '!' NMEA, '<' XML
    Nmea,
    Xml,
};

/// "auto", "nmea" or "xml".
const char* protocolName(FeedProtocol protocol);

class FixDecoder {
public:
    using Clock = std::chrono::steady_clock;

    virtual ~FixDecoder() = default;

    /// Decodes `bytes` (any split of the stream); fixes they complete are appended to `out` with
    /// `received` as their arrival stamp.
    virtual void feed(std::string_view bytes, Clock::time_point received, std::vector<Fix>& out) = 0;
    /// The end of a datagram: what is pending is all there will be (NMEA: a last line without
    /// newline is decoded; XML: an unfinished message is dropped as malformed).
    virtual void endOfRecord(Clock::time_point received, std::vector<Fix>& out) = 0;
    /// Emits a fix that is held back waiting for more sentences of its epoch (NMEA); called when
    /// the stream goes quiet or ends. `received` stamps it.
    virtual void flush(Clock::time_point received, std::vector<Fix>& out) = 0;
    /// The connection was lost: drops a partial line or message. Counters and date are kept.
    virtual void resetInput() = 0;
    /// Bytes held for an unfinished line or message (bounded by the decoder's size limit).
    virtual std::size_t bufferedBytes() const = 0;
    /// What it decodes; an Auto decoder says Auto until it has seen the first significant byte.
    virtual FeedProtocol protocol() const = 0;

    const FeedCounters& counters() const { return counters_; }

protected:
    /// Counts one dropped input under `counter` and keeps its reason.
    void drop(std::uint64_t FeedCounters::*counter, std::string why) {
        ++(counters_.*counter);
        counters_.lastError = std::move(why);
    }

    FeedCounters counters_;
};

struct DecoderOptions {
    /// NMEA: drop sentences without a checksum (see Nmea.h).
    bool requireChecksum = true;
    /// NMEA: the instant whose UTC date GGA times take until an RMC gives a date (GGA carries no
    /// date). LiveSource passes the system clock at start.
    TimeNs referenceTime = 0;
};

/// A decoder for `protocol`; Auto gives one that picks NMEA or XML from the first significant
/// byte after each resetInput() (bytes before it other than whitespace are counted malformed).
std::unique_ptr<FixDecoder> makeDecoder(FeedProtocol protocol, const DecoderOptions& options);

}  // namespace orbis::livefeed
