#include "tests/support/Shell.h"

#include <sys/wait.h>

#include <array>
#include <cstdio>

namespace orbis::test {

ShellRun runShell(const std::string& commandLine) {
    ShellRun r;
    FILE* pipe = popen(("{ " + commandLine + "; } 2>&1").c_str(), "r");
    if (!pipe) return r;
    std::array<char, 4096> buf;
    size_t n;
    while ((n = fread(buf.data(), 1, buf.size(), pipe)) > 0) r.output.append(buf.data(), n);
    const int status = pclose(pipe);
    r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    return r;
}

}  // namespace orbis::test
