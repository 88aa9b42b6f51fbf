#pragma once
// NMEA 0183 byte stream -> Fixes: frames lines, parses sentences (Nmea.h), gives GGA times their
// date, and merges the GGA, RMC and VTG of one epoch into one Fix.
//
// Lines: end at CR or LF (CR LF, LF and CR alone all work; empty lines are skipped). A line over
// kMaxNmeaLineBytes is dropped (counted oversized) and the decoder skips to its end without
// storing it, so an endless line costs at most kMaxNmeaLineBytes. A sentence starts at the last
// '$' (or '!') of its line: bytes before it (binary protocols interleaved on the same port, a
// line cut at connect) are ignored; a line without '$' is malformed.
//
// Dates: GGA has only a time of day. Its date is the one of the most recent timed sentence (an
// RMC date, or the date given to an earlier GGA), starting from `referenceTime` until the first
// RMC. If the time of day is more than 12 h before the previous one, the day has rolled over
// (GGA 00:00:01 after RMC 23:59:59 of 2026-03-19 is 2026-03-20); more than 12 h after it, the
// sentence is from the day before.
//
// Epochs and when a Fix is emitted: sentences with the same time of day form one epoch. VTG has
// no time: it joins the open epoch, i.e. that of the timed sentence before it (receivers send
// RMC or GGA first: u-blox RMC VTG GGA, SiRF GGA ... RMC VTG, MTK RMC VTG GGA); a VTG with no
// epoch open, or in one that already has a VTG (its GGA and RMC were lost), is decoded and
// counted but joins nothing, so a lost sentence never shifts later VTGs onto the wrong epoch.
// Within an epoch, GGA gives position,
// heights, quality, satellites and HDOP; RMC gives the date, and a position when GGA has none;
// speed and course come from the last of RMC and VTG. The decoder learns which sentence types
// the receiver sends per epoch (those of the previous epoch) and emits the epoch's Fix as soon
// as all of them have arrived and one of them gave a valid position: one Fix per epoch, with no
// added delay. The very first epoch (nothing learnt yet) goes out when the second one begins or
// at flush(): until then the decoder cannot know whether an RMC with the date is still to come.
// Likewise, if a sentence the pattern expects is missing (dropped for a bad checksum, say), the
// Fix goes out when the next epoch starts or at flush(), whichever comes first. Sentences that
// arrive after their epoch's Fix went out do not emit a second Fix. LiveSource calls flush()
// after a short silence, so a held-back Fix waits at most that long.

#include "formats/livefeed/FixDecoder.h"
#include "formats/livefeed/Nmea.h"

#include <string>

namespace orbis::livefeed {

class NmeaDecoder final : public FixDecoder {
public:
    explicit NmeaDecoder(const DecoderOptions& options = {});

    void feed(std::string_view bytes, Clock::time_point received, std::vector<Fix>& out) override;
    void endOfRecord(Clock::time_point received, std::vector<Fix>& out) override;
    void flush(Clock::time_point received, std::vector<Fix>& out) override;
    void resetInput() override;
    std::size_t bufferedBytes() const override { return line_.size(); }
    FeedProtocol protocol() const override { return FeedProtocol::Nmea; }

    /// Decodes one whole line (terminator optional), as if it had been fed with a newline.
    void feedLine(std::string_view line, Clock::time_point received, std::vector<Fix>& out);

private:
    enum Kind : unsigned { kGga = 1, kRmc = 2, kVtg = 4 };

    struct Epoch {
        bool open = false;
        bool emitted = false;
        unsigned kinds = 0;
        TimeNs timeOfDay = 0;
        std::optional<std::int64_t> rmcDays;   // the date an RMC of this epoch gave
        bool ggaPosition = false;
        bool hasPosition = false;
        Fix fix;
    };

    void onSentence(const NmeaSentence& s, Clock::time_point received, std::vector<Fix>& out);
    /// Makes `timeOfDay` the open epoch's (closing the open one if it has another time); an
    /// untimed sentence joins the open epoch. False: the sentence belongs to no epoch.
    bool enterEpoch(std::optional<TimeNs> timeOfDay, unsigned kind, Clock::time_point received, std::vector<Fix>& out);
    void closeEpoch(Clock::time_point received, std::vector<Fix>& out);
    void emit(Clock::time_point received, std::vector<Fix>& out);
    /// The day of `timeOfDay` relative to the anchor (12-hour rule above); moves the anchor.
    std::int64_t dayOf(TimeNs timeOfDay);

    NmeaOptions parse_;
    std::string line_;                 // capacity kMaxNmeaLineBytes, never more
    bool skippingLine_ = false;        // the current line is over the limit: skip to its end
    std::int64_t anchorDays_ = 0;      // date of the latest timed sentence
    TimeNs anchorTimeOfDay_ = 0;
    Epoch epoch_;
    unsigned expectedKinds_ = 0;       // sentence types of the previous epoch (0: not learnt yet)
};

}  // namespace orbis::livefeed
