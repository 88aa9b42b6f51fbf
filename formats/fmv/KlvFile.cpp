#include "formats/fmv/KlvFile.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>

namespace orbis::fmv {
namespace {

Error fail(const std::string& path, const std::string& what) { return makeError(std::string(path).append(": ").append(what)); }

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return s;
}

}  // namespace

std::size_t KlvStream::decodedCount() const {
    return std::size_t(std::count_if(records.begin(), records.end(), [](const KlvRecord& r) { return r.packet.has_value(); }));
}

std::size_t KlvStream::checksumErrors() const {
    return std::size_t(std::count_if(records.begin(), records.end(), [](const KlvRecord& r) {
        return r.packet && r.packet->checksum == ChecksumVerdict::Mismatch;
    }));
}

KlvStream decodeKlvStream(Bytes bytes) {
    KlvStream s;
    std::size_t pos = 0;
    while (pos < bytes.size()) {
        const std::size_t key = findKey(bytes, kSt0601Key, pos);
        if (key > pos) s.gaps.push_back({pos, key - pos});
        if (key >= bytes.size()) break;
        KlvRecord r;
        r.offset = key;
        auto packet = decodeSt0601(bytes.subspan(key), key);
        if (packet) {
            pos = key + packet->size;
            r.packet = std::move(packet.value());
        } else {
            // Resynchronise after this key: a corrupt length must not hide the packets behind it.
            r.error = packet.message();
            pos = key + kSt0601Key.size();
        }
        s.records.push_back(std::move(r));
    }
    return s;
}

Result<KlvStream> readKlvFile(const std::string& path) {
    std::error_code ec;
    const auto size = std::filesystem::file_size(path, ec);
    if (ec) return fail(path, std::string("cannot read (").append(ec.message()).append(")"));
    if (size == 0) return fail(path, "empty file");
    if (size > kMaxKlvFileBytes)
        return fail(path, std::to_string(size).append(" bytes is more than the ").append(std::to_string(kMaxKlvFileBytes >> 20))
                              .append(" MiB a KLV file may have"));
    std::ifstream in(path, std::ios::binary);
    std::vector<uint8_t> bytes(size);
    if (!in || !in.read(reinterpret_cast<char*>(bytes.data()), std::streamsize(size)))
        return fail(path, "cannot read the file");
    KlvStream s = decodeKlvStream(bytes);
    if (s.records.empty())
        return fail(path, std::string("no MISB ST 0601 packet (key ").append(toHex(kSt0601Key)).append(") in ")
                              .append(std::to_string(size)).append(" bytes"));
    return s;
}

bool looksLikeKlv(const std::string& path) {
    const std::string ext = lower(std::filesystem::path(path).extension().string());
    if (ext == ".bin" || ext == ".klv") return true;
    std::ifstream in(path, std::ios::binary);
    uint8_t head[16];
    return in.read(reinterpret_cast<char*>(head), sizeof head) && sameKey(head, kSt0601Key);
}

}  // namespace orbis::fmv
