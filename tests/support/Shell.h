#pragma once
// Runs a shell command line for tests that drive the apps (orbis, its generators): stdout and
// stderr together, and the exit code (128 + signal when killed).
#include <string>

namespace orbis::test {

struct ShellRun {
    int exitCode = -1;
    std::string output;   ///< stdout + stderr
};

ShellRun runShell(const std::string& commandLine);

}  // namespace orbis::test
