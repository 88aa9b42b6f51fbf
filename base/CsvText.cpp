#include "base/CsvText.h"

#include <algorithm>
#include <cctype>

namespace orbis::csv {

std::string normalise(std::string_view name) {
    std::string s;
    for (unsigned char c : name)
        if (c < 0x80 && std::isalnum(c)) s.push_back(char(std::tolower(c)));
    return s;
}

/// Splits one line at `sep`; double quotes protect separators ("" is a quote inside quotes).
std::vector<std::string> splitLine(std::string_view line, char sep) {
    std::vector<std::string> cells(1);
    bool quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
        const char c = line[i];
        if (quoted) {
            if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') cells.back().push_back(line[++i]);
            else if (c == '"') quoted = false;
            else cells.back().push_back(c);
        } else if (c == '"') {
            quoted = true;
        } else if (c == sep) {
            cells.emplace_back();
        } else {
            cells.back().push_back(c);
        }
    }
    for (auto& c : cells) {
        const auto first = c.find_first_not_of(" \t");
        c = first == std::string::npos ? std::string() : c.substr(first, c.find_last_not_of(" \t") - first + 1);
    }
    return cells;
}

char separatorOf(std::string_view header) {
    char best = ',';
    std::ptrdiff_t most = 0;
    for (char c : {',', ';', '\t'}) {
        const auto n = std::count(header.begin(), header.end(), c);
        if (n > most) best = c, most = n;
    }
    return best;
}

bool isNoValue(const std::string& cell) {
    const std::string n = normalise(cell);
    return cell.empty() || cell == "-" || n == "nan" || n == "na" || n == "null" || n == "none";
}

std::string_view nextLine(std::string_view text, std::size_t& pos) {
    const std::size_t end = std::min(text.find('\n', pos), text.size());
    std::string_view line = text.substr(pos, end - pos);
    pos = end + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    return line;
}

bool skipLine(std::string_view line) {
    const auto first = line.find_first_not_of(" \t");
    return first == std::string_view::npos || line[first] == '#';
}

}  // namespace orbis::csv
