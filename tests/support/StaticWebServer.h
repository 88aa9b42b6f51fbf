#pragma once
// A throw-away static web server for the tests of clouds read over HTTP: lighttpd (Debian
// package, as a user's server would be) on 127.0.0.1 on a free port in a temporary folder,
// serving the files put in its folder with range requests honoured, and its access log (one line
// a request: method, target, status, bytes sent) read once it has stopped. Every wait is bounded;
// the destructor stops lighttpd and removes the folder.
//
//   orbis::test::StaticWebServer web;
//   if (!web.available()) GTEST_SKIP() << web.error();
//   std::filesystem::copy_file(cloud, web.folder() / "cloud.copc.laz");
//   ASSERT_TRUE(web.start()) << web.error();
//   open(web.url() + "/cloud.copc.laz");

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <string>

namespace orbis::test {

class StaticWebServer {
public:
    StaticWebServer();
    ~StaticWebServer();
    StaticWebServer(const StaticWebServer&) = delete;
    StaticWebServer& operator=(const StaticWebServer&) = delete;

    /// False when lighttpd is missing (error() names the package).
    bool available() const { return available_; }
    const std::string& error() const { return error_; }
    /// Where the served files go (the document root).
    const std::filesystem::path& folder() const { return docs_; }
    /// Starts serving (within 20 s); false with error() when it does not.
    bool start();
    /// Stops the server (its access log is complete from then on).
    void stop();
    bool running() const { return pid_ > 0; }
    /// "http://127.0.0.1:PORT", no trailing slash.
    std::string url() const;
    /// After stop(): the requests served and the body bytes sent, from the access log.
    uint64_t requests() const;
    uint64_t bytesSent() const;

private:
    bool available_ = false;
    std::string error_;
    std::filesystem::path root_, docs_;
    int port_ = 0;
    pid_t pid_ = -1;
};

}  // namespace orbis::test
