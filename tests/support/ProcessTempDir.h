#pragma once

#include <unistd.h>

#include <filesystem>
#include <map>
#include <mutex>
#include <string>
#include <system_error>

namespace orbis::test {

/// A folder of this test process under the system's temporary folder, named `prefix-<pid>`.
///
/// The first call for a prefix empties it: a folder of that name was left by an earlier process
/// that had the same pid (ctest runs each test in its own process, and a fresh machine hands out
/// the same pids again from one test run to the next), and its files must not leak into this one.
/// The folders are removed when the process exits.
inline std::filesystem::path processTempDir(const std::string& prefix) {
    namespace fs = std::filesystem;
    struct Folders {
        std::mutex mutex;
        std::map<std::string, fs::path> made;
        ~Folders() {
            for (const auto& [name, path] : made) {
                std::error_code ec;
                fs::remove_all(path, ec);
            }
        }
    };
    static Folders folders;
    std::lock_guard lock(folders.mutex);
    auto it = folders.made.find(prefix);
    if (it == folders.made.end()) {
        const fs::path dir = fs::temp_directory_path() / (prefix + "-" + std::to_string(::getpid()));
        std::error_code ec;
        fs::remove_all(dir, ec);
        it = folders.made.emplace(prefix, dir).first;
    }
    fs::create_directories(it->second);   // again each time: a test may remove it
    return it->second;
}

}  // namespace orbis::test
