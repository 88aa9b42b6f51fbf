#include "tests/support/StaticWebServer.h"

#include "tests/support/Loopback.h"
#include "tests/support/Shell.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <thread>

namespace orbis::test {
namespace {

namespace fs = std::filesystem;
const char* kLighttpd = "/usr/sbin/lighttpd";

bool accepts(int port) {
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) return false;
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    addr.sin_port = htons(uint16_t(port));
    const bool ok = ::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0;
    ::close(fd);
    return ok;
}

std::string readAll(const fs::path& file) {
    std::ifstream in(file);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

StaticWebServer::StaticWebServer() {
    if (!fs::exists(kLighttpd)) {
        error_ = "lighttpd is not installed (Debian: lighttpd; tools/install-deps.sh installs it)";
        return;
    }
    available_ = true;
    std::string pattern = (fs::temp_directory_path() / "orbis-web-XXXXXX").string();
    if (!::mkdtemp(pattern.data())) {
        error_ = "mkdtemp " + pattern + ": " + std::strerror(errno);
        return;
    }
    root_ = pattern;
    docs_ = root_ / "docs";
    fs::create_directories(docs_);
}

StaticWebServer::~StaticWebServer() {
    stop();
    if (!root_.empty()) {
        std::error_code ec;
        fs::remove_all(root_, ec);
    }
}

bool StaticWebServer::start() {
    if (!available_ || root_.empty()) return false;
    std::string why;
    const int fd = bindLoopback(0, port_, why);   // a free port, released for lighttpd
    if (fd < 0) {
        error_ = why;
        return false;
    }
    ::close(fd);
    const fs::path conf = root_ / "lighttpd.conf", out = root_ / "lighttpd.out";
    std::ofstream(conf) << "server.modules = (\"mod_accesslog\")\n"
                        << "server.document-root = \"" << docs_.string() << "\"\n"
                        << "server.bind = \"127.0.0.1\"\nserver.port = " << port_ << "\n"
                        << "server.errorlog = \"" << (root_ / "error.log").string() << "\"\n"
                        << "accesslog.filename = \"" << (root_ / "access.log").string() << "\"\n"
                        << "accesslog.format = \"%m %U %s %b\"\n";
    pid_ = ::fork();
    if (pid_ == 0) {
        ::setpgid(0, 0);
        ::prctl(PR_SET_PDEATHSIG, SIGKILL);   // a test that dies takes the server with it
        const int o = ::open(out.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
        if (o >= 0) {
            ::dup2(o, 1);
            ::dup2(o, 2);
            ::close(o);
        }
        ::execl(kLighttpd, kLighttpd, "-D", "-f", conf.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    if (pid_ < 0) {
        error_ = std::string("fork: ") + std::strerror(errno);
        return false;
    }
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(20);
    while (std::chrono::steady_clock::now() < end) {
        if (waitForChild(pid_, std::chrono::milliseconds(0)) >= 0) {
            pid_ = -1;
            error_ = "lighttpd exited at start: " + readAll(out) + readAll(root_ / "error.log");
            return false;
        }
        if (accepts(port_)) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    error_ = "lighttpd did not listen on port " + std::to_string(port_) + " within 20 s";
    stop();
    return false;
}

void StaticWebServer::stop() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGTERM);
    if (waitForChild(pid_, std::chrono::seconds(10)) < 0) {
        ::kill(-pid_, SIGKILL);
        waitForChild(pid_, std::chrono::seconds(5));
    }
    pid_ = -1;
}

std::string StaticWebServer::url() const { return "http://127.0.0.1:" + std::to_string(port_); }

uint64_t StaticWebServer::requests() const {
    std::istringstream log(readAll(root_ / "access.log"));
    uint64_t n = 0;
    for (std::string line; std::getline(log, line);) n += line.empty() ? 0 : 1;
    return n;
}

uint64_t StaticWebServer::bytesSent() const {
    std::istringstream log(readAll(root_ / "access.log"));
    uint64_t bytes = 0;
    for (std::string line; std::getline(log, line);) {
        const size_t last = line.rfind(' ');
        if (last != std::string::npos) bytes += std::strtoull(line.c_str() + last + 1, nullptr, 10);   // "-": 0
    }
    return bytes;
}

}  // namespace orbis::test
