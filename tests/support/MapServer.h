#pragma once
// A throw-away MapServer for the tests of OGC services: lighttpd on 127.0.0.1 on a free port in
// a temporary folder, running MapServer's CGI (`mapserv`) over a mapfile made from the test's
// LAYER blocks (WMS 1.1.1/1.3.0 and WFS 2.0, every request enabled; WMTS through MapCache), with its
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
    /// `layers`: MapServer LAYER ... END blocks, in drawing order. `wmtsLayers`: names of those
    /// layers that MapCache (MapServer's tile cache, Debian mapcache-cgi) also serves as WMTS
    /// tile sets on the WGS84 grid (256-pixel tiles, 2 x 1 at level 0), cached in the folder.
    explicit MapServer(const std::vector<std::string>& layers, const std::vector<std::string>& wmtsLayers = {});
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
    /// MapCache's WMTS GetCapabilities: "http://127.0.0.1:PORT/mapcache/wmts?SERVICE=WMTS&REQUEST=GetCapabilities".
    std::string wmtsCapabilitiesUrl() const;
    /// GET `target` ("/ows?SERVICE=..."), within 20 s: the HTTP status (0: no answer) and body.
    std::pair<int, std::string> get(const std::string& target) const;
    /// The requests served so far, one line each: "GET QUERY_STRING" (noted by the CGI as it
    /// starts; lighttpd's own access log, access.log, is written late).
    std::string accessLog() const;

    /// The same services behind a front that misbehaves on demand: "http://127.0.0.1:PORT/faulty?".
    std::string faultyUrl() const;
    /// How the next `count` requests to faultyUrl() fail (then it serves as url() does):
    ///   Status500  "500 Internal Server Error" with a text body;
    ///   Slow       the answer starts after `slowSeconds` (for a client's timeout);
    ///   Truncated  200 and MapServer's own image cut to half its bytes;
    ///   Exception  200 and an OGC ServiceExceptionReport (what MapServer sends for a bad layer).
    enum class Fault { Status500, Slow, Truncated, Exception };
    void setFault(Fault fault, int count, int slowSeconds = 5);
    /// Requests to faultyUrl() that were answered with a fault so far.
    int faultsServed() const;

    /// The same services behind HTTP basic authentication (user `user()`, password `password()`):
    /// "http://127.0.0.1:PORT/basic?"; and behind a header check (`tokenHeader()` must be sent):
    /// "http://127.0.0.1:PORT/token?". Others get 401 and 403.
    std::string basicUrl() const;
    std::string tokenUrl() const;
    static std::string user() { return "orbis"; }
    static std::string password() { return "pa55-w0rd!"; }
    static std::string tokenHeader() { return "X-Orbis-Token: t0ken-5ecret"; }
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
