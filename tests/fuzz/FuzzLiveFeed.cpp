// Live position feeds: NMEA 0183 sentences and XML position messages, through the decoder that
// picks the protocol from the first byte, fed in pieces as a socket delivers them (the first
// input byte sets the piece size), then the end of the datagram and a flush.
#include "formats/livefeed/FixDecoder.h"
#include "tests/fuzz/FuzzInput.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size == 0) return 0;
    const size_t piece = size_t(data[0]) + 1;
    const std::string_view bytes = orbis::fuzz::text(data + 1, size - 1);
    for (bool requireChecksum : {true, false}) {
        orbis::livefeed::DecoderOptions options;
        options.requireChecksum = requireChecksum;
        auto decoder = orbis::livefeed::makeDecoder(orbis::livefeed::FeedProtocol::Auto, options);
        std::vector<orbis::livefeed::Fix> fixes;
        const auto now = orbis::livefeed::FixDecoder::Clock::now();
        for (size_t at = 0; at < bytes.size(); at += piece) decoder->feed(bytes.substr(at, piece), now, fixes);
        decoder->endOfRecord(now, fixes);
        decoder->flush(now, fixes);
    }
    return 0;
}
