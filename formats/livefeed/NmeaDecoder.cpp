#include "formats/livefeed/NmeaDecoder.h"

namespace orbis::livefeed {
namespace {

constexpr TimeNs kHalfDay = kNsPerDay / 2;

std::int64_t floorDiv(std::int64_t a, std::int64_t b) {
    const std::int64_t q = a / b;
    return (a % b != 0 && (a < 0) != (b < 0)) ? q - 1 : q;
}

}  // namespace

NmeaDecoder::NmeaDecoder(const DecoderOptions& options) {
    parse_.requireChecksum = options.requireChecksum;
    anchorDays_ = floorDiv(options.referenceTime, kNsPerDay);
    anchorTimeOfDay_ = options.referenceTime - anchorDays_ * kNsPerDay;
    line_.reserve(kMaxNmeaLineBytes);
}

void NmeaDecoder::feed(std::string_view bytes, Clock::time_point received, std::vector<Fix>& out) {
    counters_.bytes += bytes.size();
    for (const char c : bytes) {
        if (c == '\n' || c == '\r') {
            if (!skippingLine_ && !line_.empty()) feedLine(line_, received, out);
            line_.clear();
            skippingLine_ = false;
        } else if (skippingLine_) {
            continue;
        } else if (line_.size() >= kMaxNmeaLineBytes) {
            drop(&FeedCounters::oversized, "NMEA line longer than " + std::to_string(kMaxNmeaLineBytes) +
                                               " bytes, dropped (starts '" + line_.substr(0, 20) + "...')");
            line_.clear();
            skippingLine_ = true;
        } else {
            line_ += c;
        }
    }
}

void NmeaDecoder::endOfRecord(Clock::time_point received, std::vector<Fix>& out) {
    if (!skippingLine_ && !line_.empty()) feedLine(line_, received, out);
    line_.clear();
    skippingLine_ = false;
}

void NmeaDecoder::flush(Clock::time_point received, std::vector<Fix>& out) {
    if (epoch_.open && !epoch_.emitted && epoch_.hasPosition) emit(received, out);
}

void NmeaDecoder::resetInput() {
    line_.clear();
    skippingLine_ = false;
}

void NmeaDecoder::feedLine(std::string_view line, Clock::time_point received, std::vector<Fix>& out) {
    const std::size_t start = line.find_last_of("$!");
    if (start == std::string_view::npos) {
        if (line.find_first_not_of(" \t\r\n") == std::string_view::npos) return;   // blank
        const NmeaSentence s = parseNmeaSentence(line, parse_);   // says why, quoting the line
        drop(&FeedCounters::malformed, s.error);
        return;
    }
    const NmeaSentence s = parseNmeaSentence(line.substr(start), parse_);
    switch (s.status) {
        case NmeaStatus::Ok: ++counters_.messagesOk; onSentence(s, received, out); break;
        case NmeaStatus::UnknownType: ++counters_.unknownType; break;
        case NmeaStatus::BadChecksum: drop(&FeedCounters::badChecksum, s.error); break;
        case NmeaStatus::Malformed: drop(&FeedCounters::malformed, s.error); break;
    }
}

std::int64_t NmeaDecoder::dayOf(TimeNs timeOfDay) {
    std::int64_t days = anchorDays_;
    const TimeNs delta = timeOfDay - anchorTimeOfDay_;
    if (delta < -kHalfDay) ++days;        // past midnight since the anchor
    else if (delta > kHalfDay) --days;    // a late sentence from before midnight
    anchorDays_ = days;
    anchorTimeOfDay_ = timeOfDay;
    return days;
}

void NmeaDecoder::closeEpoch(Clock::time_point received, std::vector<Fix>& out) {
    if (!epoch_.open) return;
    if (!epoch_.emitted && epoch_.hasPosition) emit(received, out);
    expectedKinds_ = epoch_.kinds;
    epoch_ = Epoch{};
}

bool NmeaDecoder::enterEpoch(std::optional<TimeNs> timeOfDay, unsigned kind, Clock::time_point received, std::vector<Fix>& out) {
    if (!timeOfDay) {
        // VTG (or a GGA/RMC without time, which has no position either): it belongs to the open
        // epoch if that has no sentence of its kind yet; otherwise to none.
        if (!epoch_.open || (epoch_.kinds & kind)) return false;
        epoch_.kinds |= kind;
        return true;
    }
    if (epoch_.open && epoch_.timeOfDay != *timeOfDay) closeEpoch(received, out);
    if (!epoch_.open) {
        epoch_.open = true;
        epoch_.timeOfDay = *timeOfDay;
        epoch_.fix.format = FixFormat::Nmea;
    }
    epoch_.kinds |= kind;
    return true;
}

void NmeaDecoder::onSentence(const NmeaSentence& s, Clock::time_point received, std::vector<Fix>& out) {
    Fix& fix = epoch_.fix;
    if (const auto* gga = std::get_if<NmeaGga>(&s.data)) {
        if (!gga->hasPosition()) ++counters_.noFix;
        if (!enterEpoch(gga->timeOfDay, kGga, received, out)) return;
        if (gga->timeOfDay) {
            const std::int64_t days = epoch_.rmcDays ? *epoch_.rmcDays : dayOf(*gga->timeOfDay);
            fix.time = days * kNsPerDay + *gga->timeOfDay;
        }
        fix.quality = gga->quality;
        fix.satellites = gga->satellites;
        fix.hdop = gga->hdop;
        if (gga->hasPosition()) {
            fix.latDeg = *gga->latDeg;
            fix.lonDeg = *gga->lonDeg;
            fix.altitudeMsl = gga->altitudeMsl;
            // Height above the ellipsoid = MSL altitude + geoid separation (NMEA 0183 GGA).
            fix.heightEllipsoid.reset();
            if (gga->altitudeMsl && gga->geoidSeparation) fix.heightEllipsoid = *gga->altitudeMsl + *gga->geoidSeparation;
            epoch_.ggaPosition = epoch_.hasPosition = true;
        }
    } else if (const auto* rmc = std::get_if<NmeaRmc>(&s.data)) {
        if (!rmc->hasPosition()) ++counters_.noFix;
        if (!enterEpoch(rmc->timeOfDay, kRmc, received, out)) return;
        if (rmc->timeOfDay && rmc->date) {
            const std::int64_t days = daysFromCivil(rmc->date->year, rmc->date->month, rmc->date->day);
            epoch_.rmcDays = days;
            anchorDays_ = days;
            anchorTimeOfDay_ = *rmc->timeOfDay;
            fix.time = days * kNsPerDay + *rmc->timeOfDay;
        } else if (rmc->timeOfDay && !epoch_.ggaPosition) {
            fix.time = dayOf(*rmc->timeOfDay) * kNsPerDay + *rmc->timeOfDay;
        }
        if (rmc->speedMps) fix.speedMps = rmc->speedMps;
        if (rmc->courseDeg) fix.courseDeg = rmc->courseDeg;
        if (rmc->hasPosition()) {
            if (!epoch_.ggaPosition) {
                fix.latDeg = *rmc->latDeg;
                fix.lonDeg = *rmc->lonDeg;
            }
            epoch_.hasPosition = true;
        }
    } else if (const auto* vtg = std::get_if<NmeaVtg>(&s.data)) {
        if (!enterEpoch(std::nullopt, kVtg, received, out)) return;
        if (const std::optional<double> speed = vtg->speedMps()) fix.speedMps = speed;
        if (vtg->courseTrueDeg && vtg->mode != 'N') fix.courseDeg = vtg->courseTrueDeg;
    }
    const bool complete = expectedKinds_ != 0 && (epoch_.kinds & expectedKinds_) == expectedKinds_;
    if (epoch_.hasPosition && !epoch_.emitted && complete) emit(received, out);
}

void NmeaDecoder::emit(Clock::time_point received, std::vector<Fix>& out) {
    epoch_.emitted = true;
    Fix fix = epoch_.fix;
    fix.received = received;
    out.push_back(std::move(fix));
    ++counters_.fixes;
}

}  // namespace orbis::livefeed
