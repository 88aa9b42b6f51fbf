#include "formats/livefeed/XmlFix.h"

#include <expat.h>

#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace orbis::livefeed {
namespace {

enum Field : int { kTime, kLat, kLon, kAlt, kAltRef, kHeading, kCourse, kSpeed, kVspeed, kPitch, kRoll, kFieldCount };
constexpr std::array<const char*, kFieldCount> kFieldNames = {"time",   "lat",   "lon",   "alt",   "altRef", "heading",
                                                              "course", "speed", "vspeed", "pitch", "roll"};

int fieldIndex(const char* name) {
    for (int i = 0; i < kFieldCount; ++i)
        if (std::strcmp(name, kFieldNames[i]) == 0) return i;
    return -1;
}

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

std::string_view trim(std::string_view s) {
    while (!s.empty() && isSpace(s.front())) s.remove_prefix(1);
    while (!s.empty() && isSpace(s.back())) s.remove_suffix(1);
    return s;
}

/// The message as it appears in errors: quoted, newlines shown as spaces, at most 80 characters.
std::string quote(std::string_view s) {
    std::string q(s.substr(0, 80));
    for (char& c : q)
        if (static_cast<unsigned char>(c) < 0x20) c = ' ';
    return "'" + q + (s.size() > 80 ? "...'" : "'");
}

bool isPrefix(std::string_view prefix, std::string_view of) { return of.substr(0, prefix.size()) == prefix; }

}  // namespace

/// One expat parser, reset for each message (XML_ParserReset keeps its allocations).
class XmlFixDecoder::Parser {
public:
    Parser() : parser_(XML_ParserCreate("UTF-8")) {}
    ~Parser() {
        if (parser_) XML_ParserFree(parser_);
    }
    Parser(const Parser&) = delete;
    Parser& operator=(const Parser&) = delete;

    Result<Fix> parse(std::string_view message);

private:
    static void onStart(void* self, const XML_Char* name, const XML_Char** atts);
    static void onEnd(void* self, const XML_Char* name);
    static void onText(void* self, const XML_Char* s, int len);
    void fail(std::string why) {
        if (error_.empty()) error_ = std::move(why);
        XML_StopParser(parser_, XML_FALSE);
    }
    Result<Fix> build(std::string_view message) const;

    XML_Parser parser_ = nullptr;
    int depth_ = 0;
    int child_ = -1;                                  // field of the open child element, -1 if none
    std::string text_;                                // its text so far (bounded by the message size)
    std::array<std::optional<std::string>, kFieldCount> values_;
    std::string error_;
};

void XmlFixDecoder::Parser::onStart(void* self, const XML_Char* name, const XML_Char** atts) {
    auto& p = *static_cast<Parser*>(self);
    ++p.depth_;
    if (p.depth_ == 1) {
        if (std::strcmp(name, "position") != 0) return p.fail(std::string("root element is <") + name + ">, not <position>");
        for (int i = 0; atts[i]; i += 2) {
            const int f = fieldIndex(atts[i]);
            if (f >= 0) p.values_[f] = atts[i + 1];
        }
    } else if (p.depth_ == 2) {
        p.child_ = fieldIndex(name);
        p.text_.clear();
    }
}

void XmlFixDecoder::Parser::onEnd(void* self, const XML_Char*) {
    auto& p = *static_cast<Parser*>(self);
    if (p.depth_ == 2 && p.child_ >= 0) p.values_[p.child_] = p.text_;
    if (p.depth_ == 2) p.child_ = -1;
    --p.depth_;
}

void XmlFixDecoder::Parser::onText(void* self, const XML_Char* s, int len) {
    auto& p = *static_cast<Parser*>(self);
    if (p.depth_ == 2 && p.child_ >= 0) p.text_.append(s, std::size_t(len));
}

Result<Fix> XmlFixDecoder::Parser::parse(std::string_view message) {
    const std::string what = "XML position message " + quote(message);
    if (!parser_) return makeError(what + ": cannot create the XML parser (out of memory)");
    if (message.size() > kMaxXmlMessageBytes)
        return makeError(what + ": " + std::to_string(message.size()) + " bytes, more than the limit of " +
                         std::to_string(kMaxXmlMessageBytes));
    XML_ParserReset(parser_, "UTF-8");
    XML_SetUserData(parser_, this);
    XML_SetElementHandler(parser_, &Parser::onStart, &Parser::onEnd);
    XML_SetCharacterDataHandler(parser_, &Parser::onText);
    depth_ = 0;
    child_ = -1;
    text_.clear();
    values_ = {};
    error_.clear();
    if (XML_Parse(parser_, message.data(), int(message.size()), XML_TRUE) != XML_STATUS_OK) {
        if (!error_.empty()) return makeError(what + ": " + error_);
        return makeError(what + ": " + XML_ErrorString(XML_GetErrorCode(parser_)) + " at line " +
                         std::to_string(XML_GetCurrentLineNumber(parser_)) + ", column " +
                         std::to_string(XML_GetCurrentColumnNumber(parser_) + 1));
    }
    return build(what);
}

Result<Fix> XmlFixDecoder::Parser::build(std::string_view what) const {
    Fix fix;
    fix.format = FixFormat::Xml;
    std::string error;
    auto number = [&](int f) -> std::optional<double> {
        if (!values_[f]) return std::nullopt;
        const std::string_view s = trim(*values_[f]);
        double v = 0.0;
        const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
        if (s.empty() || ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) {
            if (error.empty()) error = std::string(kFieldNames[f]) + " '" + *values_[f] + "' is not a number";
            return std::nullopt;
        }
        return v;
    };
    if (!values_[kTime]) return makeError(std::string(what) + ": no time");
    if (!values_[kLat] || !values_[kLon]) return makeError(std::string(what) + ": no lat or no lon");
    const Result<TimeNs> time = parseIso8601(trim(*values_[kTime]));
    if (!time) return makeError(std::string(what) + ": time: " + time.message());
    fix.time = *time;
    const std::optional<double> lat = number(kLat), lon = number(kLon), alt = number(kAlt);
    fix.headingDeg = number(kHeading);
    fix.courseDeg = number(kCourse);
    fix.speedMps = number(kSpeed);
    fix.verticalSpeedMps = number(kVspeed);
    fix.pitchDeg = number(kPitch);
    fix.rollDeg = number(kRoll);
    if (!error.empty()) return makeError(std::string(what) + ": " + error);
    if (*lat < -90.0 || *lat > 90.0) return makeError(std::string(what) + ": lat " + *values_[kLat] + " is outside -90..90");
    if (*lon < -180.0 || *lon > 180.0) return makeError(std::string(what) + ": lon " + *values_[kLon] + " is outside -180..180");
    fix.latDeg = *lat;
    fix.lonDeg = *lon;
    const std::string_view ref = values_[kAltRef] ? trim(*values_[kAltRef]) : std::string_view("ellipsoid");
    if (ref == "msl" || ref == "geoid") {
        fix.altitudeMsl = alt;
    } else if (ref == "ellipsoid" || ref == "hae" || ref == "wgs84") {
        fix.heightEllipsoid = alt;
    } else {
        return makeError(std::string(what) + ": altRef '" + std::string(ref) + "' is neither 'ellipsoid' nor 'msl'");
    }
    return fix;
}

Result<Fix> parseXmlFix(std::string_view message) {
    XmlFixDecoder::Parser parser;
    return parser.parse(message);
}

std::string formatXmlFix(const Fix& fix, bool childElements) {
    std::string s = childElements ? "<position>" : "<position";
    auto add = [&](const char* name, const std::string& value) {
        if (childElements) {
            s.append("<").append(name).append(">").append(value).append("</").append(name).append(">");
        } else {
            s.append(" ").append(name).append("=\"").append(value).append("\"");
        }
    };
    auto num = [](double v, int decimals) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
        return std::string(buf);
    };
    add("time", formatIso8601(fix.time, 9));
    add("lat", num(fix.latDeg, 9));
    add("lon", num(fix.lonDeg, 9));
    if (fix.heightEllipsoid) {
        add("alt", num(*fix.heightEllipsoid, 3));
    } else if (fix.altitudeMsl) {
        add("alt", num(*fix.altitudeMsl, 3));
        add("altRef", "msl");
    }
    const std::pair<const char*, const std::optional<double>*> optional[] = {
        {"heading", &fix.headingDeg}, {"course", &fix.courseDeg}, {"speed", &fix.speedMps},
        {"vspeed", &fix.verticalSpeedMps}, {"pitch", &fix.pitchDeg}, {"roll", &fix.rollDeg}};
    for (const auto& [name, value] : optional)
        if (*value) add(name, num(**value, 4));
    return s + (childElements ? "</position>" : "/>");
}

// --- the stream decoder: framing ---------------------------------------------------------

XmlFixDecoder::XmlFixDecoder() : parser_(std::make_unique<Parser>()) { message_.reserve(kMaxXmlMessageBytes); }

XmlFixDecoder::~XmlFixDecoder() = default;

void XmlFixDecoder::feed(std::string_view bytes, Clock::time_point received, std::vector<Fix>& out) {
    counters_.bytes += bytes.size();
    for (const char c : bytes) onByte(c, received, out);
}

void XmlFixDecoder::endOfRecord(Clock::time_point, std::vector<Fix>&) {
    if (state_ == State::Message) abandon(&FeedCounters::malformed, "XML position message " + quote(message_) + ": cut off at the end of the datagram");
    resetInput();
}

void XmlFixDecoder::resetInput() {
    state_ = State::Text;
    message_.clear();
    inStartTag_ = false;
    quote_ = 0;
    inGarbage_ = false;
    quiet_ = false;
}

void XmlFixDecoder::abandon(std::uint64_t FeedCounters::*counter, std::string why) {
    drop(counter, std::move(why));
    message_.clear();
    state_ = State::Text;
    quiet_ = true;
}

void XmlFixDecoder::onByte(char c, Clock::time_point received, std::vector<Fix>& out) {
    static constexpr std::string_view kOpen = "<position";
    static constexpr std::string_view kComment = "<!--";
    switch (state_) {
        case State::Text:
            if (c == '<') {
                state_ = State::Markup;
                message_.assign(1, c);
                inGarbage_ = false;
            } else if (!isSpace(c) && !inGarbage_ && !quiet_) {
                inGarbage_ = true;
                drop(&FeedCounters::malformed, std::string("XML feed: text outside a <position> message (starts '") + c + "')");
            }
            return;
        case State::Markup:
            // Collects "<position" (then a space, '/' or '>'), or "<!--"; anything else is other
            // markup (a declaration, a wrapping element) skipped up to its '>'.
            if (message_.size() == kOpen.size() && message_ == kOpen && (isSpace(c) || c == '/' || c == '>')) {
                state_ = State::Message;
                inStartTag_ = true;
                quote_ = 0;
                quiet_ = false;
                onMessageByte(c, received, out);
                return;
            }
            message_ += c;
            if (message_ == kComment) {
                state_ = State::SkipComment;
                commentDashes_ = 0;
                message_.clear();
            } else if (!isPrefix(message_, kOpen) && !isPrefix(message_, kComment)) {
                state_ = c == '>' ? State::Text : State::SkipTag;
                message_.clear();
            }
            return;
        case State::SkipTag:
            if (c == '>') state_ = State::Text;
            return;
        case State::SkipComment:
            if (c == '>' && commentDashes_ >= 2) state_ = State::Text;
            commentDashes_ = c == '-' ? commentDashes_ + 1 : 0;
            return;
        case State::Message:
            onMessageByte(c, received, out);
            return;
    }
}

void XmlFixDecoder::onMessageByte(char c, Clock::time_point received, std::vector<Fix>& out) {
    if (message_.size() >= kMaxXmlMessageBytes) {
        abandon(&FeedCounters::oversized, "XML position message " + quote(message_) + ": longer than " +
                                              std::to_string(kMaxXmlMessageBytes) + " bytes, dropped");
        return;
    }
    if (inStartTag_) {
        if (c == '<') {
            // '<' is allowed neither in a tag nor in an attribute value (XML 1.0 §3.1, AttValue):
            // the message was cut off and this is the next one.
            drop(&FeedCounters::malformed, "XML position message " + quote(message_) + ": start tag not closed");
            state_ = State::Markup;
            message_.assign(1, c);
            return;
        }
        if (quote_ != 0) {
            if (c == quote_) quote_ = 0;
        } else if (c == '"' || c == '\'') {
            quote_ = c;
        } else if (c == '>') {
            message_ += c;
            if (message_[message_.size() - 2] == '/') return complete(received, out);
            inStartTag_ = false;
            return;
        }
        message_ += c;
        return;
    }
    // In the body: the message ends at "</position" + optional spaces + '>'. A new "<position"
    // here means the previous message was never closed: drop it and start over with the new one.
    static constexpr std::string_view kOpen = "<position";
    if ((isSpace(c) || c == '/' || c == '>') && message_.size() > kOpen.size() &&
        std::string_view(message_).substr(message_.size() - kOpen.size()) == kOpen) {
        drop(&FeedCounters::malformed, "XML position message " + quote(message_) + ": not closed before the next <position>");
        message_ = kOpen;
        inStartTag_ = true;
        quote_ = 0;
        return onMessageByte(c, received, out);
    }
    message_ += c;
    if (c != '>') return;
    const std::size_t close = message_.rfind("</");
    if (close != std::string::npos && trim(std::string_view(message_).substr(close + 2, message_.size() - close - 3)) == "position")
        complete(received, out);
}

void XmlFixDecoder::complete(Clock::time_point received, std::vector<Fix>& out) {
    Result<Fix> fix = parser_->parse(message_);
    message_.clear();
    state_ = State::Text;
    if (!fix) {
        drop(&FeedCounters::malformed, fix.message());
        quiet_ = true;
        return;
    }
    ++counters_.messagesOk;
    ++counters_.fixes;
    fix->received = received;
    out.push_back(std::move(*fix));
}

}  // namespace orbis::livefeed
