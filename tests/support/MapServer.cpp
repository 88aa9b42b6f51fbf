#include "tests/support/MapServer.h"

#include "tests/support/Loopback.h"
#include "tests/support/Shell.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <thread>

namespace orbis::test {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

const char* kLighttpd = "/usr/sbin/lighttpd";
const char* kMapserv = "/usr/lib/cgi-bin/mapserv";
const char* kMapcache = "/usr/lib/cgi-bin/mapcache";

/// GET http://127.0.0.1:port/target (HTTP/1.0: the server closes after the reply), within
/// `limit`: the status code (0 when there is no answer) and the body.
std::pair<int, std::string> httpGet(int port, const std::string& target, std::chrono::milliseconds limit) {
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (fd < 0) return {0, {}};
    timeval tv{long(limit.count() / 1000), long(limit.count() % 1000) * 1000};
    ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    ::setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    addr.sin_port = htons(uint16_t(port));
    std::string reply;
    if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) == 0) {
        const std::string request = "GET " + target + " HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n";
        if (::send(fd, request.data(), request.size(), MSG_NOSIGNAL) == ssize_t(request.size())) {
            char buf[65536];
            for (ssize_t n; (n = ::recv(fd, buf, sizeof buf, 0)) > 0 && reply.size() < (64u << 20);) reply.append(buf, size_t(n));
        }
    }
    ::close(fd);
    int status = 0;
    if (reply.rfind("HTTP/", 0) == 0) status = std::atoi(reply.c_str() + reply.find(' ') + 1);
    const size_t body = reply.find("\r\n\r\n");
    return {status, body == std::string::npos ? std::string() : reply.substr(body + 4)};
}

void writeScript(const fs::path& path, const std::string& text) {
    std::ofstream(path) << text;
    fs::permissions(path, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec | fs::perms::others_read |
                              fs::perms::others_exec);
}

std::string readAll(const fs::path& file) {
    std::ifstream in(file);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
}

}  // namespace

MapServer::MapServer(const std::vector<std::string>& layers, const std::vector<std::string>& wmtsLayers) {
    if (!fs::exists(kLighttpd) || !fs::exists(kMapserv)) {
        error_ = "MapServer behind lighttpd is not installed (Debian: cgi-mapserver lighttpd; tools/install-deps.sh installs them)";
        return;
    }
    if (!wmtsLayers.empty() && !fs::exists(kMapcache)) {
        error_ = "MapCache is not installed (Debian: mapcache-cgi; tools/install-deps.sh installs it)";
        return;
    }
    available_ = true;
    std::string pattern = (fs::temp_directory_path() / "orbis-ms-XXXXXX").string();
    if (!::mkdtemp(pattern.data())) {
        error_ = "mkdtemp " + pattern + ": " + std::strerror(errno);
        return;
    }
    root_ = pattern;
    // A port: bound, noted, released for lighttpd (which says so if it was taken meanwhile).
    std::string why;
    const int fd = bindLoopback(0, port_, why);
    if (fd < 0) {
        error_ = why;
        return;
    }
    ::close(fd);
    {
        std::ofstream map(root_ / "orbis.map");
        map << "MAP\n  NAME \"orbis\"\n  EXTENT -180 -90 180 90\n  SIZE 1024 512\n  MAXSIZE 4096\n"
               "  PROJECTION \"init=epsg:4326\" END\n"
               "  WEB\n    METADATA\n"
               "      \"ows_title\" \"Orbis test services\"\n"
               "      \"ows_onlineresource\" \"" << url() << "\"\n"
               "      \"ows_srs\" \"EPSG:4326 EPSG:3857\"\n"
               "      \"ows_enable_request\" \"*\"\n"
               "      \"wfs_getfeature_formatlist\" \"gml,geojson\"\n"
               "    END\n  END\n"
               "  OUTPUTFORMAT NAME \"png\" DRIVER \"AGG/PNG\" MIMETYPE \"image/png\" IMAGEMODE RGBA EXTENSION \"png\" END\n"
               "  OUTPUTFORMAT NAME \"tiff32\" DRIVER \"GDAL/GTiff\" MIMETYPE \"image/tiff\" IMAGEMODE FLOAT32 EXTENSION \"tif\" END\n"
               "  OUTPUTFORMAT NAME \"geojson\" DRIVER \"OGR/GEOJSON\" MIMETYPE \"application/json; subtype=geojson\"\n"
               "    FORMATOPTION \"STORAGE=stream\" FORMATOPTION \"FORM=SIMPLE\" END\n";
        for (const std::string& layer : layers) map << layer << "\n";
        map << "END\n";
        std::ofstream conf(root_ / "mapserver.conf");
        conf << "CONFIG\n  ENV\n    MS_MAPFILE \"" << (root_ / "orbis.map").string() << "\"\n    MS_ERRORFILE \""
             << (root_ / "mapserver.log").string() << "\"\n  END\nEND\n";
        // The CGI: a script that notes each query (unbuffered, unlike lighttpd's access log)
        // and runs mapserv.
        const std::string note = "printf '%s %s\\n' \"$REQUEST_METHOD\" \"$QUERY_STRING\" >> '" + (root_ / "requests.log").string() + "'\n";
        writeScript(root_ / "ows.sh", "#!/bin/sh\n" + note + "exec " + kMapserv + "\n");
        // The faulty front: "MODE COUNT [SECONDS]" in the file `fault` (taken under a lock, one
        // request at a time), COUNT faults then the services as they are.
        const std::string fault = (root_ / "fault").string(), served = (root_ / "faults-served").string();
        writeScript(root_ / "faulty.sh",
                    "#!/bin/sh\n" + note +
                        "exec 9>>'" + fault + ".lock'\nflock 9\nmode=ok\ncount=0\nsecs=5\n"
                        "[ -s '" + fault + "' ] && read mode count secs < '" + fault + "'\n"
                        "if [ \"${count:-0}\" -gt 0 ]; then\n"
                        "  echo \"$mode $((count - 1)) $secs\" > '" + fault + "'\n  echo x >> '" + served + "'\n"
                        "else\n  mode=ok\nfi\nflock -u 9\n"
                        "case $mode in\n"
                        "  500) printf 'Status: 500 Internal Server Error\\r\\nContent-Type: text/plain\\r\\n\\r\\nthe map server failed\\n' ;;\n"
                        "  slow) sleep \"$secs\"; exec " + kMapserv + " ;;\n"
                        "  truncated) out=$(mktemp); " + kMapserv + " > \"$out\"; n=$(stat -c %s \"$out\"); head -c $((n / 2)) \"$out\"; rm -f \"$out\" ;;\n"
                        "  exception) printf 'Content-Type: application/vnd.ogc.se_xml\\r\\n\\r\\n<?xml version=\"1.0\"?>"
                        "<ServiceExceptionReport version=\"1.1.1\"><ServiceException code=\"LayerNotDefined\">"
                        "msWMSLoadGetMapParams(): WMS server error. Invalid layer(s) given in the LAYERS parameter.</ServiceException>"
                        "</ServiceExceptionReport>\\n' ;;\n"
                        "  *) exec " + kMapserv + " ;;\nesac\n");
        // MapCache: WMTS tile sets over the layers' WMS, cached on disk in the folder.
        {
            std::ofstream mc(root_ / "mapcache.xml");
            mc << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<mapcache>\n";
            for (const std::string& name : wmtsLayers)
                mc << "  <source name=\"" << name << "\" type=\"wms\"><getmap><params><FORMAT>image/png</FORMAT><LAYERS>" << name
                   << "</LAYERS></params></getmap><http><url>" << url() << "</url></http></source>\n"
                   << "  <tileset name=\"" << name << "\"><source>" << name
                   << "</source><cache>disk</cache><grid>WGS84</grid><format>PNG</format><metatile>1 1</metatile></tileset>\n";
            mc << "  <cache name=\"disk\" type=\"disk\"><base>" << (root_ / "mapcache-tiles").string() << "</base></cache>\n"
               << "  <service type=\"wmts\" enabled=\"true\"/>\n"
               << "  <locker type=\"disk\"><directory>" << root_.string() << "</directory></locker>\n"
               << "  <log_level>warn</log_level>\n</mapcache>\n";
            writeScript(root_ / "mapcache.sh", "#!/bin/sh\nprintf '%s %s%s\\n' \"$REQUEST_METHOD\" \"$PATH_INFO\" \"${QUERY_STRING:+?$QUERY_STRING}\" >> '" +
                                                   (root_ / "requests.log").string() + "'\nexec " + kMapcache + "\n");
        }
        std::ofstream(root_ / "users") << user() << ":" << password() << "\n";
        const std::string token = tokenHeader().substr(0, tokenHeader().find(':'));
        const std::string tokenValue = tokenHeader().substr(tokenHeader().find(':') + 2);
        std::ofstream http(root_ / "lighttpd.conf");
        http << "server.modules = (\"mod_access\", \"mod_auth\", \"mod_authn_file\", \"mod_alias\", \"mod_cgi\", \"mod_setenv\", \"mod_accesslog\")\n"
             << "server.document-root = \"" << root_.string() << "\"\n"
             << "server.bind = \"127.0.0.1\"\n"
             << "server.port = " << port_ << "\n"
             << "server.errorlog = \"" << (root_ / "error.log").string() << "\"\n"
             << "accesslog.filename = \"" << (root_ / "access.log").string() << "\"\n"
             << "alias.url = (\"/ows\" => \"" << (root_ / "ows.sh").string() << "\", \"/basic\" => \""
             << (root_ / "ows.sh").string() << "\", \"/token\" => \"" << (root_ / "ows.sh").string() << "\", \"/faulty\" => \""
             << (root_ / "faulty.sh").string() << "\", \"/mapcache\" => \"" << (root_ / "mapcache.sh").string() << "\")\n"
             << "$HTTP[\"url\"] =~ \"^/(ows|basic|token|faulty|mapcache)\" { cgi.assign = (\"\" => \"\") }\n"
             << "auth.backend = \"plain\"\nauth.backend.plain.userfile = \"" << (root_ / "users").string() << "\"\n"
             << "auth.require = (\"/basic\" => (\"method\" => \"basic\", \"realm\" => \"orbis\", \"require\" => \"valid-user\"))\n"
             << "$HTTP[\"url\"] =~ \"^/token\" { $REQUEST_HEADER[\"" << token << "\"] != \"" << tokenValue
             << "\" { url.access-deny = (\"\") } }\n"
             << "setenv.add-environment = (\"MAPSERVER_CONFIG_FILE\" => \"" << (root_ / "mapserver.conf").string()
             << "\", \"MAPCACHE_CONFIG_FILE\" => \"" << (root_ / "mapcache.xml").string() << "\")\n";
    }
    start();
}

MapServer::~MapServer() {
    stop();
    if (!root_.empty()) {
        std::error_code ec;
        fs::remove_all(root_, ec);
    }
}

std::string MapServer::url() const { return "http://127.0.0.1:" + std::to_string(port_) + "/ows?"; }

std::pair<int, std::string> MapServer::get(const std::string& target) const {
    return httpGet(port_, target, std::chrono::seconds(20));
}

std::string MapServer::accessLog() const { return readAll(root_ / "requests.log"); }

std::string MapServer::wmtsCapabilitiesUrl() const {
    return "http://127.0.0.1:" + std::to_string(port_) + "/mapcache/wmts?SERVICE=WMTS&REQUEST=GetCapabilities";
}

std::string MapServer::faultyUrl() const { return "http://127.0.0.1:" + std::to_string(port_) + "/faulty?"; }
std::string MapServer::basicUrl() const { return "http://127.0.0.1:" + std::to_string(port_) + "/basic?"; }
std::string MapServer::tokenUrl() const { return "http://127.0.0.1:" + std::to_string(port_) + "/token?"; }

void MapServer::setFault(Fault fault, int count, int slowSeconds) {
    const char* mode = fault == Fault::Status500 ? "500" : fault == Fault::Slow ? "slow" : fault == Fault::Truncated ? "truncated" : "exception";
    const fs::path tmp = root_ / "fault.new";
    std::ofstream(tmp) << mode << " " << count << " " << slowSeconds << "\n";
    fs::rename(tmp, root_ / "fault");
}

int MapServer::faultsServed() const {
    const std::string s = readAll(root_ / "faults-served");
    return int(std::count(s.begin(), s.end(), '\n'));
}

bool MapServer::start() {
    const std::string out = (root_ / "lighttpd.out").string(), conf = (root_ / "lighttpd.conf").string();
    pid_ = ::fork();
    if (pid_ == 0) {
        ::setpgid(0, 0);
        ::prctl(PR_SET_PDEATHSIG, SIGKILL);   // a test that dies (a crash, a timeout) takes the server with it
        const int fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
        if (fd >= 0) {
            ::dup2(fd, 1);
            ::dup2(fd, 2);
            ::close(fd);
        }
        ::execl(kLighttpd, kLighttpd, "-D", "-f", conf.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    if (pid_ < 0) {
        error_ = std::string("fork: ") + std::strerror(errno);
        return false;
    }
    // Ready when GetCapabilities answers (within 20 s).
    const auto end = Clock::now() + std::chrono::seconds(20);
    while (Clock::now() < end) {
        if (waitForChild(pid_, std::chrono::milliseconds(0)) >= 0) {
            pid_ = -1;
            error_ = "lighttpd exited at start: " + readAll(out) + readAll(root_ / "error.log");
            return false;
        }
        if (get("/ows?SERVICE=WMS&REQUEST=GetCapabilities").first == 200) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    error_ = "MapServer did not answer on " + url() + " within 20 s: " + readAll(root_ / "error.log");
    stop();
    return false;
}

void MapServer::stop() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGTERM);
    if (waitForChild(pid_, std::chrono::seconds(10)) < 0) {
        ::kill(-pid_, SIGKILL);
        waitForChild(pid_, std::chrono::seconds(5));
    }
    pid_ = -1;
}

}  // namespace orbis::test
