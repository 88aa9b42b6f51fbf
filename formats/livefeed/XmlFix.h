#pragma once
// The XML position message of the live feed, and its stream decoder.
//
// Format: one <position> element per fix, its values as attributes or as child elements (both
// may be mixed; a child element given after an attribute of the same name wins):
//
//   <position time="2026-03-20T08:00:00.5Z" lat="46.1" lon="7.2" alt="1500" heading="90"
//             speed="55" vspeed="-1.2"/>
//   <position><time>2026-03-20T08:00:00.5Z</time><lat>46.1</lat><lon>7.2</lon></position>
//
//   name     unit / form                                       required
//   time     ISO 8601 / RFC 3339 instant (parseIso8601), UTC     yes
//   lat      degrees north, WGS84, -90..90                       yes
//   lon      degrees east, WGS84, -180..180                      yes
//   alt      metres; above the WGS84 ellipsoid, or above mean     no
//            sea level when altRef="msl"
//   altRef   "ellipsoid" (default, also "hae", "wgs84") or "msl" (also "geoid")
//   heading  degrees clockwise from true north (where the body points)
//   course   degrees clockwise from true north (where it moves)
//   speed    m/s over ground
//   vspeed   m/s, up positive
//   pitch    degrees, nose up positive;  roll: degrees, right wing down positive
//
// Numbers are XML text in C locale ("1.5", "-2e3"); NaN and infinities are refused. Other
// attributes and child elements are ignored, so senders may add their own (id, name, ...).
// Names are case-sensitive and unprefixed.
//
// Stream: any sequence of messages, with or without newlines between them, optionally inside a
// wrapping element (<feed> ... </feed>) and with XML declarations or comments between them.
// The decoder frames each message before parsing it: a message starts at "<position" at the top
// level, and ends at the '>' that closes its start tag if that is "/>", else at "</position>".
// Each framed message is then parsed whole by expat (the parser is reset between messages), so
// a broken message costs only itself: the decoder drops it (counted malformed, with expat's
// reason) and resumes at the next "<position". A message over kMaxXmlMessageBytes is dropped
// (counted oversized) without storing more of it, and the decoder resumes at the next
// "<position"; other markup between messages is skipped without being stored. Memory is bounded by
// kMaxXmlMessageBytes whatever the stream holds. Over UDP, each datagram holds whole messages;
// an unfinished message at its end is dropped.

#include "base/Result.h"
#include "formats/livefeed/FixDecoder.h"

#include <memory>
#include <string>

namespace orbis::livefeed {

/// Largest <position> message accepted, in bytes.
inline constexpr std::size_t kMaxXmlMessageBytes = 4096;

/// Parses one whole message. Errors name the problem: XML syntax (expat's message with line and
/// column), a missing or invalid time/lat/lon, a value that is not a number or out of range.
Result<Fix> parseXmlFix(std::string_view message);

/// Writes `fix` as a one-line message (attribute form, or child elements when `childElements`),
/// with alt as ellipsoid height when known, else as MSL altitude with altRef="msl". No newline.
std::string formatXmlFix(const Fix& fix, bool childElements = false);

class XmlFixDecoder final : public FixDecoder {
public:
    XmlFixDecoder();
    ~XmlFixDecoder() override;

    void feed(std::string_view bytes, Clock::time_point received, std::vector<Fix>& out) override;
    void endOfRecord(Clock::time_point received, std::vector<Fix>& out) override;
    void flush(Clock::time_point, std::vector<Fix>&) override {}
    void resetInput() override;
    std::size_t bufferedBytes() const override { return message_.size(); }
    FeedProtocol protocol() const override { return FeedProtocol::Xml; }

    class Parser;   // expat, behind a pointer so that users do not see expat.h

private:
    enum class State { Text, Markup, SkipTag, SkipComment, Message };

    void onByte(char c, Clock::time_point received, std::vector<Fix>& out);
    void onMessageByte(char c, Clock::time_point received, std::vector<Fix>& out);
    void complete(Clock::time_point received, std::vector<Fix>& out);
    void abandon(std::uint64_t FeedCounters::*counter, std::string why);

    std::unique_ptr<Parser> parser_;
    State state_ = State::Text;
    std::string message_;        // the message being framed; capacity kMaxXmlMessageBytes
    bool inStartTag_ = false;
    char quote_ = 0;             // the quote an attribute value in the start tag opened
    int commentDashes_ = 0;
    bool inGarbage_ = false;     // already counted this run of text outside messages
    bool quiet_ = false;         // resyncing after a dropped message: skip, do not count
};

}  // namespace orbis::livefeed
