#pragma once
// A throw-away PyWPS server for the processing tests: tools/wps/serve.py (Debian's python3-pywps,
// the demo processes on GDAL) on 127.0.0.1 on a free port, over a DEM, in a temporary folder.
// Every wait is bounded; the destructor stops it and removes the folder.
//
//   orbis::test::WpsServer wps(demPath);
//   if (!wps.available()) GTEST_SKIP() << wps.error();
//   ASSERT_TRUE(wps.running()) << wps.error();
//   WpsClient client(wps.url());

#include <sys/types.h>

#include <filesystem>
#include <string>

namespace orbis::test {

class WpsServer {
public:
    explicit WpsServer(const std::string& dem);
    ~WpsServer();
    WpsServer(const WpsServer&) = delete;
    WpsServer& operator=(const WpsServer&) = delete;

    /// False when Debian's python3 or python3-pywps is missing (error() names the packages).
    bool available() const { return available_; }
    bool running() const { return pid_ > 0; }
    const std::string& error() const { return error_; }
    /// "http://127.0.0.1:PORT/wps".
    const std::string& url() const { return url_; }
    /// The server's log (PyWPS's own), for messages.
    std::string log() const;

private:
    void stop();
    std::filesystem::path root_;
    pid_t pid_ = -1;
    bool available_ = false;
    std::string url_, error_;
};

}  // namespace orbis::test
