#include "tests/support/WpsServer.h"

#include "tests/support/Shell.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>
#include <thread>

namespace orbis::test {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr const char* kPython = "/usr/bin/python3";

std::string readAll(const fs::path& p) {
    std::ifstream in(p);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

WpsServer::WpsServer(const std::string& dem) {
    if (::access(kPython, X_OK) != 0 || runShell(std::string(kPython) + " -c 'import pywps, osgeo.gdal, werkzeug'").exitCode != 0) {
        error_ = "PyWPS is not installed (Debian: python3-pywps python3-gdal; tools/install-deps.sh installs them)";
        return;
    }
    available_ = true;
    root_ = fs::temp_directory_path() / ("orbis-wps-" + std::to_string(::getpid()) + "-" + std::to_string(Clock::now().time_since_epoch().count()));
    fs::create_directories(root_);
    const std::string out = (root_ / "serve.out").string(), work = (root_ / "work").string();
    const std::string script = std::string(ORBIS_SOURCE_DIR) + "/tools/wps/serve.py";
    pid_ = ::fork();
    if (pid_ == 0) {
        ::setpgid(0, 0);
        ::prctl(PR_SET_PDEATHSIG, SIGKILL);   // a test that dies takes the server with it
        const int fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
        if (fd >= 0) {
            ::dup2(fd, 1);
            ::dup2(fd, 2);
            ::close(fd);
        }
        ::execl(kPython, kPython, script.c_str(), "--dem", dem.c_str(), "--dir", work.c_str(), "--port", "0", static_cast<char*>(nullptr));
        ::_exit(127);
    }
    if (pid_ < 0) {
        error_ = std::string("fork: ") + std::strerror(errno);
        return;
    }
    // Ready when it prints where it listens (it has bound the port by then), within 30 s.
    const auto end = Clock::now() + std::chrono::seconds(30);
    while (Clock::now() < end) {
        if (waitForChild(pid_, std::chrono::milliseconds(0)) >= 0) {
            pid_ = -1;
            error_ = "the WPS server exited at start: " + readAll(out);
            return;
        }
        const std::string text = readAll(out);
        if (const size_t at = text.find("wps: http://"); at != std::string::npos) {
            const size_t eol = text.find('\n', at);
            if (eol != std::string::npos) {
                url_ = text.substr(at + 5, eol - at - 5);
                return;
            }
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    error_ = "the WPS server did not start within 30 s: " + readAll(out);
    stop();
}

WpsServer::~WpsServer() {
    stop();
    std::error_code ec;
    if (!root_.empty()) fs::remove_all(root_, ec);
}

std::string WpsServer::log() const { return readAll(root_ / "serve.out") + readAll(root_ / "work" / "pywps.log"); }

void WpsServer::stop() {
    if (pid_ <= 0) return;
    ::kill(-pid_, SIGTERM);   // the server and the job processes it started
    if (waitForChild(pid_, std::chrono::seconds(10)) < 0) {
        ::kill(-pid_, SIGKILL);
        waitForChild(pid_, std::chrono::seconds(5));
    }
    pid_ = -1;
}

}  // namespace orbis::test
