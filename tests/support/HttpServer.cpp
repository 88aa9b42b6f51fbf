#include "tests/support/HttpServer.h"

#include "tests/support/Loopback.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>
#include <vector>

namespace orbis::test {
namespace {

constexpr int kPollMs = 50;              // how often the accept loop looks at stop_
constexpr int kClientTimeoutMs = 2000;   // a client that sends nothing for this long is dropped
constexpr size_t kMaxRequestBytes = 16384;

/// Sends all of `data`; false if the client went away. MSG_NOSIGNAL: no SIGPIPE on a closed peer.
bool sendAll(int fd, const char* data, size_t size) {
    while (size > 0) {
        const ssize_t n = ::send(fd, data, size, MSG_NOSIGNAL);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        data += n;
        size -= size_t(n);
    }
    return true;
}

/// Reads until the end of the request headers; empty if the client disconnects or stalls.
std::string readRequest(int fd) {
    std::string request;
    char buf[2048];
    while (request.find("\r\n\r\n") == std::string::npos && request.find("\n\n") == std::string::npos) {
        pollfd p{fd, POLLIN, 0};
        if (::poll(&p, 1, kClientTimeoutMs) <= 0) return {};
        const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return {};
        request.append(buf, size_t(n));
        if (request.size() > kMaxRequestBytes) return {};
    }
    return request;
}

std::string contentType(const std::filesystem::path& p) {
    const std::string ext = p.extension().string();
    if (ext == ".png") return "image/png";
    if (ext == ".jpg" || ext == ".jpeg") return "image/jpeg";
    if (ext == ".tif" || ext == ".tiff") return "image/tiff";
    if (ext == ".xml") return "text/xml";
    return "application/octet-stream";
}

}  // namespace

HttpServer::HttpServer(std::filesystem::path root) : root_(std::move(root)) {
    listenFd_ = bindLoopback(0, port_, error_);
    if (listenFd_ < 0) return;
    if (::listen(listenFd_, 64) != 0) {
        error_ = std::string("listen: ") + std::strerror(errno);
        ::close(listenFd_);
        listenFd_ = -1;
        return;
    }
    thread_ = std::thread([this] { serve(); });
}

HttpServer::~HttpServer() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    if (stalled_ >= 0) ::close(stalled_);
    if (listenFd_ >= 0) ::close(listenFd_);
}

std::string HttpServer::url() const { return "http://127.0.0.1:" + std::to_string(port_); }

void HttpServer::serve() {
    while (!stop_) {
        pollfd p{listenFd_, POLLIN, 0};
        if (::poll(&p, 1, kPollMs) <= 0) continue;
        const int fd = ::accept(listenFd_, nullptr, nullptr);
        if (fd < 0) continue;
        handle(fd);
        if (fd == stalled_) continue;   // held open, unanswered
        ::close(fd);
    }
}

void HttpServer::handle(int fd) {
    const std::string request = readRequest(fd);
    if (request.empty()) return;  // the client went away or sent nothing
    std::istringstream line(request.substr(0, request.find_first_of("\r\n")));
    std::string method, target;
    line >> method >> target;
    ++requests_;
    switch (fault_.load()) {
        case Fault::None: break;
        case Fault::Unavailable503: {
            static const char kBusy[] = "HTTP/1.0 503 Service Unavailable\r\nContent-Length: 5\r\nConnection: close\r\n\r\nbusy\n";
            sendAll(fd, kBusy, sizeof kBusy - 1);
            return;
        }
        case Fault::Garbage: {
            std::string junk = "HTTP/1.0 200 OK\r\nContent-Type: image/png\r\nContent-Length: 4096\r\nConnection: close\r\n\r\n";
            for (int i = 0; i < 4096; ++i) junk.push_back(char((i * 7919 + 13) & 0xff));
            sendAll(fd, junk.data(), junk.size());
            return;
        }
        case Fault::Reset: {   // SO_LINGER 0: close() sends RST instead of FIN
            const linger l{1, 0};
            ::setsockopt(fd, SOL_SOCKET, SO_LINGER, &l, sizeof l);
            return;
        }
        case Fault::Stall:
            if (stalled_ >= 0) ::close(stalled_);
            stalled_ = fd;
            return;
    }

    // Path only (no query), no way out of root_.
    target = target.substr(0, target.find_first_of("?#"));
    std::vector<char> body;
    bool found = false;
    std::filesystem::path file;
    if ((method == "GET" || method == "HEAD") && !target.empty() && target[0] == '/' && target.find("..") == std::string::npos) {
        file = root_ / target.substr(1);
        std::error_code ec;
        if (std::filesystem::is_regular_file(file, ec)) {
            std::ifstream in(file, std::ios::binary);
            body.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
            found = bool(in) || in.eof();
        }
    }
    std::ostringstream head;
    if (found) {
        head << "HTTP/1.0 200 OK\r\nContent-Type: " << contentType(file) << "\r\nContent-Length: " << body.size()
             << "\r\nConnection: close\r\n\r\n";
    } else {
        ++notFound_;
        static const char kMsg[] = "not found\n";
        body.assign(kMsg, kMsg + sizeof kMsg - 1);
        head << "HTTP/1.0 404 Not Found\r\nContent-Type: text/plain\r\nContent-Length: " << body.size()
             << "\r\nConnection: close\r\n\r\n";
    }
    const std::string h = head.str();
    if (sendAll(fd, h.data(), h.size()) && method != "HEAD") sendAll(fd, body.data(), body.size());
}

}  // namespace orbis::test
