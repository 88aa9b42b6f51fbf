#include "formats/livefeed/FixDecoder.h"

#include "formats/livefeed/NmeaDecoder.h"
#include "formats/livefeed/XmlFix.h"

namespace orbis::livefeed {
namespace {

/// Picks NMEA or XML from the first significant byte after each resetInput(), then hands every
/// byte to that decoder. Both decoders are kept (a reconnect may find the other protocol), and
/// the counters are their sum plus the bytes skipped before detection.
class AutoDecoder final : public FixDecoder {
public:
    explicit AutoDecoder(const DecoderOptions& options) : options_(options) {}

    void feed(std::string_view bytes, Clock::time_point received, std::vector<Fix>& out) override {
        while (!active_ && !bytes.empty()) {
            const char c = bytes.front();
            if (c == '$' || c == '!') {
                if (!nmea_) nmea_ = std::make_unique<NmeaDecoder>(options_);
                active_ = nmea_.get();
            } else if (c == '<') {
                if (!xml_) xml_ = std::make_unique<XmlFixDecoder>();
                active_ = xml_.get();
            } else {
                ++own_.bytes;
                if (c != ' ' && c != '\t' && c != '\r' && c != '\n' && !skipping_) {
                    skipping_ = true;
                    ++own_.malformed;
                    own_.lastError = "live feed: bytes before the first '$' (NMEA) or '<' (XML), skipped";
                }
                bytes.remove_prefix(1);
            }
        }
        if (active_ && !bytes.empty()) active_->feed(bytes, received, out);
        sum();
    }
    void endOfRecord(Clock::time_point received, std::vector<Fix>& out) override {
        if (active_) active_->endOfRecord(received, out);
        sum();
    }
    void flush(Clock::time_point received, std::vector<Fix>& out) override {
        if (active_) active_->flush(received, out);
        sum();
    }
    void resetInput() override {
        if (active_) active_->resetInput();
        active_ = nullptr;
        skipping_ = false;
    }
    std::size_t bufferedBytes() const override { return active_ ? active_->bufferedBytes() : 0; }
    FeedProtocol protocol() const override { return active_ ? active_->protocol() : FeedProtocol::Auto; }

private:
    void sum() {
        counters_ = own_;
        if (nmea_) counters_ += nmea_->counters();
        if (xml_) counters_ += xml_->counters();
        if (active_ && !active_->counters().lastError.empty()) counters_.lastError = active_->counters().lastError;
    }

    DecoderOptions options_;
    std::unique_ptr<NmeaDecoder> nmea_;
    std::unique_ptr<XmlFixDecoder> xml_;
    FixDecoder* active_ = nullptr;
    FeedCounters own_;
    bool skipping_ = false;
};

}  // namespace

const char* protocolName(FeedProtocol protocol) {
    switch (protocol) {
        case FeedProtocol::Auto: return "auto";
        case FeedProtocol::Nmea: return "nmea";
        case FeedProtocol::Xml: return "xml";
    }
    return "?";
}

std::unique_ptr<FixDecoder> makeDecoder(FeedProtocol protocol, const DecoderOptions& options) {
    switch (protocol) {
        case FeedProtocol::Nmea: return std::make_unique<NmeaDecoder>(options);
        case FeedProtocol::Xml: return std::make_unique<XmlFixDecoder>();
        case FeedProtocol::Auto: break;
    }
    return std::make_unique<AutoDecoder>(options);
}

}  // namespace orbis::livefeed
