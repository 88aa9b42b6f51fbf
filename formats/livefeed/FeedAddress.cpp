#include "formats/livefeed/FeedAddress.h"

#include <charconv>

namespace orbis::livefeed {

std::string FeedAddress::hostPort() const {
    const bool v6 = host.find(':') != std::string::npos;
    return (v6 ? "[" + host + "]" : host) + ":" + std::to_string(port);
}

Result<FeedAddress> parseFeedAddress(std::string_view url) {
    const std::string what = "live feed '" + std::string(url) + "'";
    FeedAddress a;
    a.text = std::string(url);
    std::string_view rest = url;
    if (rest.substr(0, 6) == "tcp://") {
        a.transport = Transport::Tcp;
    } else if (rest.substr(0, 6) == "udp://") {
        a.transport = Transport::Udp;
    } else {
        return makeError(what + ": expected tcp://host:port or udp://host:port");
    }
    rest.remove_prefix(6);
    if (!rest.empty() && rest.back() == '/') rest.remove_suffix(1);   // "tcp://host:port/" is common

    std::string_view portText;
    if (!rest.empty() && rest.front() == '[') {
        const std::size_t close = rest.find(']');
        if (close == std::string_view::npos) return makeError(what + ": '[' without ']' around the IPv6 address");
        a.host = std::string(rest.substr(1, close - 1));
        if (close + 1 >= rest.size() || rest[close + 1] != ':') return makeError(what + ": no port after the IPv6 address");
        portText = rest.substr(close + 2);
        if (a.host.empty()) return makeError(what + ": empty IPv6 address");
    } else {
        const std::size_t colon = rest.rfind(':');
        if (colon == std::string_view::npos) return makeError(what + ": no port (expected host:port)");
        a.host = std::string(rest.substr(0, colon));
        portText = rest.substr(colon + 1);
        if (a.host.find(':') != std::string::npos) return makeError(what + ": an IPv6 address must be in brackets, e.g. [::1]:10110");
        if (a.host.find_first_of("/?#@ ") != std::string::npos) return makeError(what + ": host '" + a.host + "' has a character a host name cannot have");
    }
    if (a.host == "*") a.host = "0.0.0.0";
    if (a.host.empty()) {
        if (a.transport == Transport::Tcp) return makeError(what + ": no host");
        a.host = "0.0.0.0";
    }
    if (portText.empty()) return makeError(what + ": no port (expected host:port)");
    long port = 0;
    const auto [end, ec] = std::from_chars(portText.data(), portText.data() + portText.size(), port);
    if (ec == std::errc::result_out_of_range) return makeError(what + ": port " + std::string(portText) + " is out of range");
    if (ec != std::errc() || end != portText.data() + portText.size())
        return makeError(what + ": port '" + std::string(portText) + "' is not a number");
    const long minPort = a.transport == Transport::Tcp ? 1 : 0;
    if (port < minPort || port > 65535)
        return makeError(what + ": port " + std::string(portText) + " is out of range " + std::to_string(minPort) + "..65535");
    a.port = static_cast<std::uint16_t>(port);
    return a;
}

}  // namespace orbis::livefeed
