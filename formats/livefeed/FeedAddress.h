#pragma once
// The address of a live feed: "tcp://host:port" (a client that connects to a server which
// streams) or "udp://host:port" (binds host:port and receives datagrams). Pure parsing, no I/O.
//
// host: a name (resolved later with getaddrinfo, IPv4 and IPv6), a dotted IPv4 address, or an
// IPv6 address in brackets ("tcp://[::1]:10110"). For UDP, host is the local address to bind:
// "0.0.0.0" or "::" (or "*", same as "0.0.0.0") for every interface, "127.0.0.1" for loopback;
// port 0 binds an ephemeral port (LiveStats::localPort says which). TCP needs a port 1..65535.

#include "base/Result.h"

#include <cstdint>
#include <string>
#include <string_view>

namespace orbis::livefeed {

enum class Transport : std::uint8_t { Tcp, Udp };

struct FeedAddress {
    Transport transport = Transport::Tcp;
    std::string host;         ///< without brackets
    std::uint16_t port = 0;
    std::string text;         ///< the address as given, for messages

    /// "host:port", or "[v6]:port".
    std::string hostPort() const;
};

/// Parses `url`. Errors quote it: "live feed 'tcp://host:99999': port 99999 is out of range 1..65535".
Result<FeedAddress> parseFeedAddress(std::string_view url);

}  // namespace orbis::livefeed
