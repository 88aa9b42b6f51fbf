#pragma once
// Reading a whole text file (a scene, a camera path, an input script, a CRS sidecar) with a
// size cap, so that a wrong path (a folder, a device, a multi-gigabyte data file) is a clear
// error instead of a stall or an out-of-memory. One place for the checks and their messages.

#include "base/Result.h"

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace orbis {

/// The whole of `file` as bytes. `what` names the kind of file in messages ("scene file",
/// "input script"). The errors name the file and the problem: "no such file", "is a folder,
/// not a <what>", "is not a regular file", "the <what> is larger than 16 MB" (the cap), or that
/// it cannot be opened or read. Never throws. Any thread.
Result<std::string> readTextFile(const std::filesystem::path& file, std::uintmax_t maxBytes, std::string_view what);

/// A byte count for messages: "16 MB", "512 KB", "100 bytes" (binary multiples, whole ones only).
std::string formatByteLimit(std::uintmax_t bytes);

}  // namespace orbis
