#include "base/FileText.h"

#include <fstream>
#include <system_error>

namespace orbis {
namespace {

Error fileError(const std::filesystem::path& file, std::string_view problem) {
    return makeError(file.string().append(": ").append(problem));
}

/// The checks before opening: the file exists, is a regular file and is not over the cap.
Result<void> checkFile(const std::filesystem::path& file, std::uintmax_t maxBytes, const std::string& what) {
    std::error_code ec;
    const auto status = std::filesystem::status(file, ec);
    if (status.type() == std::filesystem::file_type::not_found) return fileError(file, "no such file");
    if (ec) return fileError(file, "cannot read the " + what + " (" + ec.message() + ")");
    if (std::filesystem::is_directory(status)) return fileError(file, "is a folder, not a " + what);
    if (!std::filesystem::is_regular_file(status)) return fileError(file, "is not a regular file");
    const auto size = std::filesystem::file_size(file, ec);
    if (ec) return fileError(file, "cannot read the " + what + " (" + ec.message() + ")");
    if (size > maxBytes) return fileError(file, "the " + what + " is larger than " + formatByteLimit(maxBytes));
    return {};
}

}  // namespace

std::string formatByteLimit(std::uintmax_t bytes) {
    constexpr std::uintmax_t kKiB = 1024, kMiB = 1024 * 1024;
    if (bytes >= kMiB && bytes % kMiB == 0) return std::to_string(bytes / kMiB) + " MB";
    if (bytes >= kKiB && bytes % kKiB == 0) return std::to_string(bytes / kKiB) + " KB";
    return std::to_string(bytes) + (bytes == 1 ? " byte" : " bytes");
}

Result<std::string> readTextFile(const std::filesystem::path& file, std::uintmax_t maxBytes, std::string_view what) {
    const std::string noun(what);
    if (auto ok = checkFile(file, maxBytes, noun); !ok) return ok.error();
    std::ifstream in(file, std::ios::binary);
    if (!in) return fileError(file, "cannot open the " + noun + " for reading");
    // Read in chunks up to the cap rather than trusting the size seen above: the file may grow.
    std::string text;
    char chunk[1 << 16];
    while (in.read(chunk, sizeof chunk) || in.gcount() > 0) {
        text.append(chunk, size_t(in.gcount()));
        if (text.size() > maxBytes) return fileError(file, "the " + noun + " is larger than " + formatByteLimit(maxBytes));
    }
    if (in.bad()) return fileError(file, "cannot read the " + noun + " (read error)");
    return text;
}

}  // namespace orbis
