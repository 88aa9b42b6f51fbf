#pragma once
// Minimal levelled logging to stderr: log::info("loaded ", n, " tiles from ", path).
// Thread-safe: each call writes one whole line.

#include <sstream>
#include <string_view>

namespace orbis::log {

enum class Level { Error = 0, Warn = 1, Info = 2, Debug = 3, Trace = 4 };

void setLevel(Level level);
Level level();
bool enabled(Level level);
void write(Level level, std::string_view message);

template <typename... Args>
void print(Level lvl, Args&&... args) {
    if (!enabled(lvl)) return;
    std::ostringstream s;
    (s << ... << std::forward<Args>(args));
    write(lvl, s.str());
}

template <typename... Args> void error(Args&&... a) { print(Level::Error, std::forward<Args>(a)...); }
template <typename... Args> void warn(Args&&... a) { print(Level::Warn, std::forward<Args>(a)...); }
template <typename... Args> void info(Args&&... a) { print(Level::Info, std::forward<Args>(a)...); }
template <typename... Args> void debug(Args&&... a) { print(Level::Debug, std::forward<Args>(a)...); }
template <typename... Args> void trace(Args&&... a) { print(Level::Trace, std::forward<Args>(a)...); }

}  // namespace orbis::log
