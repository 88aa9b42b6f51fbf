#include "base/Log.h"

#include <atomic>
#include <cstdio>
#include <mutex>

namespace orbis::log {
namespace {
std::atomic<Level> gLevel{Level::Warn};
std::mutex gMutex;
const char* label(Level l) {
    switch (l) {
        case Level::Error: return "error";
        case Level::Warn: return "warn";
        case Level::Info: return "info";
        case Level::Debug: return "debug";
        case Level::Trace: return "trace";
    }
    return "?";
}
}  // namespace

void setLevel(Level level) { gLevel.store(level); }
Level level() { return gLevel.load(); }
bool enabled(Level l) { return static_cast<int>(l) <= static_cast<int>(gLevel.load()); }

void write(Level l, std::string_view message) {
    std::lock_guard lock(gMutex);
    std::fprintf(stderr, "orbis: %s: %.*s\n", label(l), static_cast<int>(message.size()), message.data());
}

}  // namespace orbis::log
