#pragma once
// A tiny HTTP/1.0 file server for tests that read over the network (XYZ tiles, /vsicurl/):
// GET only, on 127.0.0.1 with an ephemeral port, serving the files under one folder. It
// accepts one connection at a time on its own thread (clients that connect in parallel wait in
// the listen backlog), answers 404 for anything it does not have, and survives clients that
// disconnect mid-request. POSIX sockets only; no Vulkan, no GDAL.
//
// Faults, for the tests of what a client does with a bad server (setFault, any time): answer
// every request with 503, with 200 and bytes that are no image, by resetting the connection, or
// by stalling (reading the request and never answering; the connection is held until the next
// request comes or the server stops).
//
//   orbis::test::HttpServer server(tileDir);
//   ASSERT_TRUE(server.running()) << server.error();
//   open(server.url() + "/{z}/{x}/{y}.png");

#include <atomic>
#include <filesystem>
#include <string>
#include <thread>

namespace orbis::test {

class HttpServer {
public:
    enum class Fault { None, Unavailable503, Garbage, Reset, Stall };

    /// Starts serving `root` (files are looked up as root + request path). Check running().
    explicit HttpServer(std::filesystem::path root);
    /// Stops the server thread and closes the socket.
    ~HttpServer();
    HttpServer(const HttpServer&) = delete;
    HttpServer& operator=(const HttpServer&) = delete;

    bool running() const { return listenFd_ >= 0; }
    const std::string& error() const { return error_; }
    int port() const { return port_; }
    /// "http://127.0.0.1:<port>", no trailing slash.
    std::string url() const;

    /// Requests answered so far (any status). Any thread.
    int requestCount() const { return requests_.load(); }
    /// Requests answered with 404. Any thread.
    int notFoundCount() const { return notFound_.load(); }
    /// How the following requests are answered. Any thread.
    void setFault(Fault fault) { fault_ = fault; }

private:
    void serve();
    void handle(int fd);

    std::filesystem::path root_;
    int listenFd_ = -1;
    int port_ = 0;
    std::string error_;
    std::atomic<bool> stop_{false};
    std::atomic<int> requests_{0};
    std::atomic<int> notFound_{0};
    std::atomic<Fault> fault_{Fault::None};
    int stalled_ = -1;   // the connection a Stall holds (server thread only)
    std::thread thread_;
};

}  // namespace orbis::test
