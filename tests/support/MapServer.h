#pragma once
// A throw-away MapServer for the tests of OGC services: lighttpd on 127.0.0.1 on a free port in
// a temporary folder, running MapServer's CGI (`mapserv`) over a mapfile made from the test's
// LAYER blocks (WMS 1.1.1/1.3.0, WFS 2.0 and WMTS-free GetMap; every request enabled), with its
// access log kept so that a test can see what the client asked. Every wait is bounded; the
// destructor stops lighttpd and removes the folder.
//
//   orbis::test::MapServer ms({R"(LAYER NAME "world" TYPE RASTER STATUS ON DATA "/x/world.tif"
//                                PROJECTION AUTO END END)"});
//   if (!ms.available()) GTEST_SKIP() << ms.error();
//   ASSERT_TRUE(ms.running()) << ms.error();
//   open("WMS:" + ms.url() + "SERVICE=WMS&VERSION=1.1.1&REQUEST=GetMap&LAYERS=world&SRS=EPSG:4326&BBOX=-180,-90,180,90");

#include <sys/types.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace orbis::test {

class MapServer {
public:
    /// `layers`: MapServer LAYER ... END blocks, in drawing order.
    explicit MapServer(const std::vector<std::string>& layers);
    ~MapServer();
    MapServer(const MapServer&) = delete;
    MapServer& operator=(const MapServer&) = delete;

    /// False when lighttpd or MapServer's CGI is missing (error() names the packages).
    bool available() const { return available_; }
    bool running() const { return pid_ > 0; }
    const std::string& error() const { return error_; }
    int port() const { return port_; }
    /// "http://127.0.0.1:PORT/ows?": the services' address, ready for parameters.
    std::string url() const;
    /// GET `target` ("/ows?SERVICE=..."), within 20 s: the HTTP status (0: no answer) and body.
    std::pair<int, std::string> get(const std::string& target) const;
    /// The requests served so far, one line each: "GET QUERY_STRING" (noted by the CGI as it
    /// starts; lighttpd's own access log, access.log, is written late).
    std::string accessLog() const;
    const std::filesystem::path& folder() const { return root_; }

private:
    bool start();
    void stop();

    std::filesystem::path root_;
    bool available_ = false;
    int port_ = 0;
    pid_t pid_ = -1;
    std::string error_;
};

}  // namespace orbis::test
