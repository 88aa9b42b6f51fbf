#include "formats/motion/TrajectoryGpx.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace orbis::motion {
namespace {

struct Attribute {
    std::string_view name;   // without its namespace prefix
    std::string value;       // entities decoded
};

struct Open {
    std::string_view name;   // local name
    std::string_view qname;  // as written, for messages
    std::size_t line = 0;
};

std::string_view localName(std::string_view qname) {
    const auto colon = qname.find(':');
    return colon == std::string_view::npos ? qname : qname.substr(colon + 1);
}

bool isNameChar(char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' || c == ':' || c == '-' ||
           c == '.' || (unsigned char)c >= 0x80;
}

bool isSpace(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }

void appendUtf8(std::string& out, uint32_t cp) {
    if (cp < 0x80) {
        out.push_back(char(cp));
    } else if (cp < 0x800) {
        out.push_back(char(0xC0 | (cp >> 6)));
        out.push_back(char(0x80 | (cp & 0x3F)));
    } else if (cp < 0x10000) {
        out.push_back(char(0xE0 | (cp >> 12)));
        out.push_back(char(0x80 | ((cp >> 6) & 0x3F)));
        out.push_back(char(0x80 | (cp & 0x3F)));
    } else {
        out.push_back(char(0xF0 | (cp >> 18)));
        out.push_back(char(0x80 | ((cp >> 12) & 0x3F)));
        out.push_back(char(0x80 | ((cp >> 6) & 0x3F)));
        out.push_back(char(0x80 | (cp & 0x3F)));
    }
}

/// Character data with its entities decoded; false (and `bad` set) on an unknown entity.
bool decodeText(std::string_view raw, std::string& out, std::string& bad) {
    for (std::size_t i = 0; i < raw.size(); ++i) {
        if (raw[i] != '&') {
            out.push_back(raw[i]);
            continue;
        }
        const auto semi = raw.find(';', i);
        const std::string_view entity = semi == std::string_view::npos ? raw.substr(i, 12) : raw.substr(i + 1, semi - i - 1);
        if (semi == std::string_view::npos || semi - i > 12) {
            bad = std::string(raw.substr(i, 12));
            return false;
        }
        if (entity == "lt") out.push_back('<');
        else if (entity == "gt") out.push_back('>');
        else if (entity == "amp") out.push_back('&');
        else if (entity == "quot") out.push_back('"');
        else if (entity == "apos") out.push_back('\'');
        else if (entity.size() > 1 && entity[0] == '#') {
            const bool hex = entity[1] == 'x' || entity[1] == 'X';
            uint32_t cp = 0;
            const std::string_view digits = entity.substr(hex ? 2 : 1);
            const auto r = std::from_chars(digits.data(), digits.data() + digits.size(), cp, hex ? 16 : 10);
            if (digits.empty() || r.ec != std::errc() || r.ptr != digits.data() + digits.size() || cp > 0x10FFFF) {
                bad = std::string("&").append(entity) + ";";
                return false;
            }
            appendUtf8(out, cp);
        } else {
            bad = std::string("&").append(entity) + ";";
            return false;
        }
        i = semi;
    }
    return true;
}

bool parseNumber(std::string_view s, double& out) {
    while (!s.empty() && isSpace(s.front())) s.remove_prefix(1);
    while (!s.empty() && isSpace(s.back())) s.remove_suffix(1);
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
    return !s.empty() && r.ec == std::errc() && r.ptr == s.data() + s.size() && std::isfinite(out);
}

std::string trimmed(std::string s) {
    const auto first = s.find_first_not_of(" \t\r\n");
    if (first == std::string::npos) return {};
    return s.substr(first, s.find_last_not_of(" \t\r\n") - first + 1);
}

/// The GPX content of one document, built as the scanner reports elements.
class GpxBuilder {
public:
    explicit GpxBuilder(const std::string& name) : name_(name) {}

    Result<void> start(const std::vector<Open>& stack, const std::vector<Attribute>& attrs, std::size_t line) {
        const std::string_view el = stack.back().name;
        const std::string_view parent = stack.size() > 1 ? stack[stack.size() - 2].name : std::string_view();
        // Elements count only where GPX puts them (depth 1 is <gpx>): a <trkpt> or <trk> inside
        // a <wpt> or any other element is someone's extension, not a track.
        const std::size_t depth = stack.size();
        if (depth == 1) {
            if (el != "gpx")
                return fail(line, std::string("not a GPX file: the root element is <").append(stack.back().qname) + ">, not <gpx>");
            gpx_.version = attribute(attrs, "version").value_or("");
        } else if ((el == "trk" || el == "rte") && depth == 2) {
            GpxTrack t;
            t.route = el == "rte";
            t.segments = t.route ? 1 : 0;
            t.line = line;
            gpx_.tracks.push_back(std::move(t));
        } else if (el == "trkseg" && parent == "trk" && depth == 3) {
            ++gpx_.tracks.back().segments;
        } else if ((el == "trkpt" && parent == "trkseg" && depth == 4 && stack[1].name == "trk") || (el == "rtept" && parent == "rte" && depth == 3) ||
                   (el == "wpt" && depth == 2)) {
            GpxPoint p;
            p.line = line;
            auto lat = coordinate(attrs, "lat", el, line, 90.0, p.latDeg);
            if (!lat) return lat;
            auto lon = coordinate(attrs, "lon", el, line, 180.0, p.lonDeg);
            if (!lon) return lon;
            point_ = p;
            pointDepth_ = depth;
        } else if (el == "bounds" && ((parent == "metadata" && depth == 3) || depth == 2)) {
            GpxBounds b;
            double* values[4] = {&b.minLatDeg, &b.minLonDeg, &b.maxLatDeg, &b.maxLonDeg};
            const char* names[4] = {"minlat", "minlon", "maxlat", "maxlon"};
            for (int i = 0; i < 4; ++i) {
                const auto v = attribute(attrs, names[i]);
                if (!v || !parseNumber(*v, *values[i]))
                    return fail(line, std::string("<bounds> without a numeric ") + names[i] + " attribute");
            }
            gpx_.bounds = b;
        }
        text_.clear();
        return {};
    }

    /// Character data of the innermost element (only what the end handler reads matters).
    void text(const std::string& s) { text_ += s; }

    Result<void> end(const std::vector<Open>& stack) {
        const Open& open = stack.back();
        const std::string_view el = open.name;
        const std::string_view parent = stack.size() > 1 ? stack[stack.size() - 2].name : std::string_view();
        const std::size_t depth = stack.size();
        const bool inPoint = point_ && depth == pointDepth_ + 1;
        const bool pointEnds = point_ && depth == pointDepth_;
        if (el == "ele" && inPoint) {
            double v = 0.0;
            if (!parseNumber(text_, v)) return fail(open.line, "<ele> '" + trimmed(text_) + "' is not a number");
            point_->ele = v;
        } else if (el == "time" && inPoint) {
            auto t = parseIso8601(trimmed(text_));
            if (!t) return fail(open.line, "<time>: " + t.message());
            point_->time = *t;
        } else if (el == "name" && (parent == "trk" || parent == "rte") && depth == 3) {
            gpx_.tracks.back().name = trimmed(text_);
        } else if (pointEnds && (el == "trkpt" || el == "rtept")) {
            gpx_.tracks.back().points.push_back(*point_);
            point_.reset();
        } else if (pointEnds && el == "wpt") {
            gpx_.waypoints.push_back(*point_);
            point_.reset();
        }
        text_.clear();
        return {};
    }

    Gpx take() { return std::move(gpx_); }

private:
    static std::optional<std::string> attribute(const std::vector<Attribute>& attrs, std::string_view name) {
        for (const Attribute& a : attrs)
            if (a.name == name) return a.value;
        return std::nullopt;
    }

    Result<void> coordinate(const std::vector<Attribute>& attrs, const char* which, std::string_view el, std::size_t line,
                            double range, double& out) const {
        const auto v = attribute(attrs, which);
        if (!v) return fail(line, std::string("<").append(el) + "> without a " + which + " attribute");
        if (!parseNumber(*v, out)) return fail(line, std::string("<").append(el) + "> " + which + " '" + *v + "' is not a number");
        if (out < -range || out > range)
            return fail(line, std::string("<").append(el) + "> " + which + " " + *v + " is outside -" + std::to_string(int(range)) + ".." +
                                  std::to_string(int(range)));
        return {};
    }

    Error fail(std::size_t line, const std::string& what) const {
        return makeError(name_ + ": line " + std::to_string(line) + ": " + what);
    }

    const std::string& name_;
    Gpx gpx_;
    std::optional<GpxPoint> point_;
    std::size_t pointDepth_ = 0;   ///< where point_'s element is in the stack
    std::string text_;
};

/// Scans the XML of one document and hands its elements, attributes and character data to the
/// builder as they come: comments, processing instructions, CDATA and a DOCTYPE are understood,
/// namespaces reduced to local names. Errors name the line they are on.
class XmlScanner {
public:
    XmlScanner(std::string_view text, const std::string& name, GpxBuilder& gpx) : text_(text), name_(name), gpx_(gpx) {}

    /// The whole document, which must hold exactly one root element.
    Result<void> run() {
        while (pos_ < text_.size()) {
            auto r = text_[pos_] == '<' ? markup() : characterData();
            if (!r) return r;
        }
        if (!stack_.empty())
            return makeError(name_ + std::string(": XML: the file ends inside <").append(stack_.back().qname) +
                             "> (opened at line " + std::to_string(stack_.back().line) + ")");
        if (!sawRoot_) return makeError(name_ + ": not a GPX file: no XML element in it");
        return {};
    }

private:
    /// The line of byte `at`, counted lazily: the scanner only moves forward.
    std::size_t lineAt(std::size_t at) {
        if (at > lineCountedTo_) {
            line_ += std::size_t(std::count(text_.begin() + std::ptrdiff_t(lineCountedTo_), text_.begin() + std::ptrdiff_t(at), '\n'));
            lineCountedTo_ = at;
        }
        return line_;
    }

    Error fail(std::size_t at, const std::string& what) {
        return makeError(name_ + ": line " + std::to_string(lineAt(at)) + ": XML: " + what);
    }

    /// Moves past the first `end` at or after `from`.
    Result<void> skipPast(std::size_t from, std::string_view end, const char* what) {
        const auto e = text_.find(end, from);
        if (e == std::string_view::npos) return fail(from, std::string("unterminated ") + what);
        pos_ = e + end.size();
        return {};
    }

    /// Text up to the next '<': only whitespace outside the root element.
    Result<void> characterData() {
        const std::size_t end = std::min(text_.find('<', pos_), text_.size());
        const std::string_view raw = text_.substr(pos_, end - pos_);
        if (stack_.empty()) {
            if (const auto at = raw.find_first_not_of(" \t\r\n"); at != std::string_view::npos)
                return fail(pos_ + at, sawRoot_ ? "text after the root element" : "text before the root element");
        } else {
            std::string decoded, bad;
            if (!decodeText(raw, decoded, bad)) return fail(pos_, "unknown entity '" + bad + "'");
            gpx_.text(decoded);
        }
        pos_ = end;
        return {};
    }

    /// Whatever starts with '<'.
    Result<void> markup() {
        const std::string_view rest = text_.substr(pos_);
        if (rest.starts_with("<!--")) return skipPast(pos_ + 4, "-->", "comment");
        if (rest.starts_with("<![CDATA[")) return cdata();
        if (rest.starts_with("<?")) return skipPast(pos_ + 2, "?>", "processing instruction");
        if (rest.starts_with("<!")) {   // <!DOCTYPE ...>, with an internal subset in [ ]
            const auto bracket = text_.find('[', pos_), close = text_.find('>', pos_);
            return bracket < close ? skipPast(bracket, "]>", "DOCTYPE") : skipPast(pos_, ">", "declaration");
        }
        if (rest.starts_with("</")) return endTag();
        return startTag();
    }

    Result<void> cdata() {
        const std::size_t start = pos_;
        if (auto e = skipPast(start + 9, "]]>", "CDATA section"); !e) return e;
        if (stack_.empty()) return fail(start, "CDATA outside the root element");
        gpx_.text(std::string(text_.substr(start + 9, pos_ - 3 - (start + 9))));
        return {};
    }

    Result<void> endTag() {
        std::size_t i = pos_ + 2;
        while (i < text_.size() && isNameChar(text_[i])) ++i;
        const std::string_view qname = text_.substr(pos_ + 2, i - pos_ - 2);
        while (i < text_.size() && isSpace(text_[i])) ++i;
        if (i >= text_.size() || text_[i] != '>') return fail(pos_, std::string("malformed end tag </").append(qname) + ">");
        if (stack_.empty()) return fail(pos_, std::string("end tag </").append(qname) + "> without a start tag");
        if (stack_.back().qname != qname)
            return fail(pos_, std::string("</").append(qname) + std::string("> closes <").append(stack_.back().qname) + "> (opened at line " +
                                  std::to_string(stack_.back().line) + ")");
        lineAt(pos_);
        if (auto r = gpx_.end(stack_); !r) return r;
        stack_.pop_back();
        pos_ = i + 1;
        return {};
    }

    Result<void> startTag() {
        const std::size_t tagLine = lineAt(pos_);
        std::size_t i = pos_ + 1;
        while (i < text_.size() && isNameChar(text_[i])) ++i;
        const std::string_view qname = text_.substr(pos_ + 1, i - pos_ - 1);
        if (qname.empty()) return fail(pos_, "'<' not followed by a tag name");
        if (stack_.empty() && sawRoot_) return fail(pos_, std::string("a second root element <").append(qname) + ">");
        bool selfClosing = false;
        auto end = attributes(i, qname, selfClosing);
        if (!end) return end.error();
        stack_.push_back({localName(qname), qname, tagLine});
        sawRoot_ = true;
        if (auto r = gpx_.start(stack_, attrs_, tagLine); !r) return r;
        if (selfClosing) {
            if (auto r = gpx_.end(stack_); !r) return r;
            stack_.pop_back();
        }
        pos_ = *end;
        return {};
    }

    /// The attributes of the tag <qname ...> from `i` into attrs_; the position after the tag.
    Result<std::size_t> attributes(std::size_t i, std::string_view qname, bool& selfClosing) {
        attrs_.clear();
        for (;;) {
            while (i < text_.size() && isSpace(text_[i])) ++i;
            if (i >= text_.size()) return fail(pos_, std::string("the file ends inside the tag <").append(qname) + ">");
            if (text_[i] == '>') return i + 1;
            if (text_[i] == '/' && i + 1 < text_.size() && text_[i + 1] == '>') {
                selfClosing = true;
                return i + 2;
            }
            auto next = attribute(i, qname);
            if (!next) return next.error();
            i = *next;
        }
    }

    /// One name="value" from `i`; the position after it.
    Result<std::size_t> attribute(std::size_t i, std::string_view qname) {
        const std::size_t a = i;
        while (i < text_.size() && isNameChar(text_[i])) ++i;
        const std::string_view attrName = text_.substr(a, i - a);
        while (i < text_.size() && isSpace(text_[i])) ++i;
        if (i >= text_.size()) return fail(pos_, std::string("the file ends inside the tag <").append(qname) + ">");
        if (attrName.empty() || text_[i] != '=') return fail(i, std::string("malformed attribute in <").append(qname) + ">");
        ++i;
        while (i < text_.size() && isSpace(text_[i])) ++i;
        const char quote = i < text_.size() ? text_[i] : '\0';
        if (quote != '"' && quote != '\'') return fail(i, std::string("attribute ").append(attrName) + " without quotes");
        const auto close = text_.find(quote, i + 1);
        if (close == std::string_view::npos) return fail(i, std::string("unterminated value of attribute ").append(attrName));
        std::string value, bad;
        if (!decodeText(text_.substr(i + 1, close - i - 1), value, bad)) return fail(i, "unknown entity '" + bad + "'");
        attrs_.push_back({localName(attrName), std::move(value)});
        return close + 1;
    }

    std::string_view text_;
    const std::string& name_;
    GpxBuilder& gpx_;
    std::vector<Open> stack_;         // the elements open at pos_
    std::vector<Attribute> attrs_;    // of the last start tag
    std::size_t pos_ = 0, line_ = 1, lineCountedTo_ = 0;
    bool sawRoot_ = false;
};

}  // namespace

Result<Gpx> parseGpx(std::string_view text, const std::string& name) {
    if (text.size() >= 3 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);   // UTF-8 byte order mark
    GpxBuilder gpx(name);
    if (auto r = XmlScanner(text, name, gpx).run(); !r) return r.error();
    return gpx.take();
}

Result<Gpx> readGpx(const std::string& path) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) return makeError(path + ": cannot read (" + ec.message() + ")");
    if (size > kMaxGpxBytes)
        return makeError(path + ": " + std::to_string(size) + " bytes is more than the " + std::to_string(kMaxGpxBytes >> 20) +
                         " MiB a GPX file may have");
    std::ifstream in(path, std::ios::binary);
    std::string text(size, '\0');
    if (!in || !in.read(text.data(), std::streamsize(size))) return makeError(path + ": cannot read the file");
    return parseGpx(text, path);
}

namespace {

std::string describe(const GpxTrack& t, std::size_t index) {
    return std::string(t.route ? "route " : "track ") + std::to_string(index + 1) + (t.name.empty() ? "" : " '" + t.name + "'");
}

}  // namespace

Result<std::vector<TrajectorySample>> gpxSamples(const GpxTrack& track, const std::string& name) {
    if (track.points.empty())
        return makeError(name + ": line " + std::to_string(track.line) + ": the " + (track.route ? "route" : "track") + " has no points");
    std::vector<TrajectorySample> out;
    out.reserve(track.points.size());
    for (const GpxPoint& p : track.points) {
        if (!p.time)
            return makeError(name + ": line " + std::to_string(p.line) + ": a point without <time> (a trajectory needs a time at every point)");
        TrajectorySample s;
        s.t = *p.time;
        s.lonDeg = p.lonDeg;
        s.latDeg = p.latDeg;
        s.alt = p.ele.value_or(0.0);
        s.altRef = p.ele ? AltitudeRef::MeanSeaLevel : AltitudeRef::Ground;
        s.line = p.line;
        out.push_back(s);
    }
    return out;
}

Result<std::vector<TrajectorySample>> gpxTrajectorySamples(const Gpx& gpx, const std::string& name, const std::string& track) {
    if (gpx.tracks.empty())
        return makeError(name + ": no track or route in the file (" + std::to_string(gpx.waypoints.size()) +
                         " waypoints: a trajectory needs a <trk> or <rte>)");
    if (!track.empty()) {
        for (std::size_t i = 0; i < gpx.tracks.size(); ++i)
            if (gpx.tracks[i].name == track || std::to_string(i + 1) == track) return gpxSamples(gpx.tracks[i], name);
        std::string there;
        for (std::size_t i = 0; i < gpx.tracks.size(); ++i) there.append(i ? ", " : "").append(describe(gpx.tracks[i], i));
        return makeError(name + ": no track or route '" + track + "' (there are: " + there + ")");
    }
    std::string why;
    for (std::size_t i = 0; i < gpx.tracks.size(); ++i) {
        const GpxTrack& t = gpx.tracks[i];
        const auto timed = std::count_if(t.points.begin(), t.points.end(), [](const GpxPoint& p) { return p.time.has_value(); });
        if (!t.points.empty() && std::size_t(timed) == t.points.size()) return gpxSamples(t, name);
        why.append(why.empty() ? "" : "; ").append(describe(t, i)).append(": ").append(std::to_string(t.points.size()))
            .append(" points, ").append(std::to_string(timed)).append(" with a time");
    }
    return makeError(name + ": no track or route has a time at every point (" + why + ")");
}

}  // namespace orbis::motion
