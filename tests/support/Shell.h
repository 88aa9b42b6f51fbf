#pragma once
// Runs a shell command line for tests that drive the apps (orbis, its generators): stdout and
// stderr together, and the exit code (128 + signal when killed).
#include <sys/types.h>

#include <chrono>
#include <string>

namespace orbis::test {

struct ShellRun {
    int exitCode = -1;
    std::string output;   ///< stdout + stderr
};

ShellRun runShell(const std::string& commandLine);

/// Waits for the child `pid` within `limit`: its exit status (128 + signal when killed), 255
/// when it is not our child, or -1 when it is still running (the servers' fixtures).
int waitForChild(pid_t pid, std::chrono::milliseconds limit);

}  // namespace orbis::test
