#include "base/Secrets.h"

#include <algorithm>
#include <cctype>

namespace orbis {
namespace {

bool startsWithNoCase(std::string_view text, size_t at, std::string_view key) {
    if (text.size() - at < key.size()) return false;
    for (size_t k = 0; k < key.size(); ++k)
        if (std::tolower(static_cast<unsigned char>(text[at + k])) != key[k]) return false;
    return true;
}

/// Where a key=value value that starts at `at` ends: a quoted value past its closing quote,
/// else at the next space, '&' (a URL's query) or the end.
size_t valueEnd(std::string_view text, size_t at) {
    if (at < text.size() && text[at] == '\'') {
        for (size_t k = at + 1; k < text.size(); ++k) {
            if (text[k] == '\\') ++k;
            else if (text[k] == '\'') return k + 1;
        }
        return text.size();
    }
    size_t k = at;
    while (k < text.size() && !std::isspace(static_cast<unsigned char>(text[k])) && text[k] != '&') ++k;
    return k;
}

/// Redacts (`remove` false: "***" for each password) or removes them.
std::string scrub(std::string_view text, bool remove) {
    std::string out;
    out.reserve(text.size());
    size_t k = 0;
    while (k < text.size()) {
        // A password key: at the start, or after a separator (so "old_password=" is left alone).
        const bool keyStart = k == 0 || std::isspace(static_cast<unsigned char>(text[k - 1])) || text[k - 1] == '&' ||
                              text[k - 1] == '?' || text[k - 1] == ':' || text[k - 1] == ';';
        if (keyStart && startsWithNoCase(text, k, "password")) {
            size_t at = k + 8;
            while (at < text.size() && text[at] == ' ') ++at;
            if (at < text.size() && text[at] == '=') {
                ++at;
                while (at < text.size() && text[at] == ' ') ++at;
                if (remove) {
                    // The key, its value and one separator: "a=1 password=x b=2" -> "a=1 b=2".
                    k = valueEnd(text, at);
                    if (!out.empty() && (out.back() == '&' || out.back() == '?') && k < text.size() && text[k] == '&') ++k;
                    else if (!out.empty() && (out.back() == ' ' || out.back() == '&')) {
                        out.pop_back();
                        while (!out.empty() && out.back() == ' ') out.pop_back();
                    }
                } else {
                    out.append(text.substr(k, at - k)).append("***");
                    k = valueEnd(text, at);
                }
                continue;
            }
        }
        // A URL's user info: "://user:password@" (the '@' before the next '/', '?' or '#').
        if (text.compare(k, 3, "://") == 0) {
            const size_t authority = k + 3;
            size_t end = authority;
            while (end < text.size() && text[end] != '/' && text[end] != '?' && text[end] != '#' &&
                   !std::isspace(static_cast<unsigned char>(text[end])))
                ++end;
            const std::string_view host = text.substr(authority, end - authority);
            const size_t at = host.rfind('@');
            const size_t colon = at == std::string_view::npos ? at : host.substr(0, at).find(':');
            if (colon != std::string_view::npos) {
                if (remove) out.append(text.substr(k, 3 + colon));
                else out.append(text.substr(k, 3 + colon + 1)).append("***");
                k = authority + at;   // from the '@'
                continue;
            }
        }
        out += text[k++];
    }
    return out;
}

}  // namespace

std::string redactSecrets(std::string_view text) { return scrub(text, false); }

std::string withoutPasswords(std::string_view text) { return scrub(text, true); }

bool isConnectionString(std::string_view source) {
    const size_t colon = source.find(':');
    return colon != std::string_view::npos && colon >= 2 && source.find('/') > colon &&
           std::all_of(source.begin(), source.begin() + std::ptrdiff_t(colon),
                       [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
}

}  // namespace orbis
