#pragma once
// Small pieces shared by the CSV readers (FMV pose sidecars, trajectories): splitting a line,
// guessing the separator, and recognising column names and empty cells. No I/O.

#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace orbis::csv {

/// Lower-case letters and digits of `name` only: "Sensor Latitude (deg)" -> "sensorlatitudedeg".
std::string normalise(std::string_view name);
/// Splits one line at `sep`; double quotes protect separators ("" is a quote inside quotes);
/// cells are trimmed of spaces and tabs.
std::vector<std::string> splitLine(std::string_view line, char sep);
/// The separator a header line uses most of: ',', ';' or tab (',' when none).
char separatorOf(std::string_view header);
/// An empty cell, "-", or NaN, NA, null, none in any case.
bool isNoValue(const std::string& cell);

/// The line of `text` starting at `pos` (without "\n" or "\r\n"); moves `pos` past it.
std::string_view nextLine(std::string_view text, std::size_t& pos);
/// A blank line or a '#' comment.
bool skipLine(std::string_view line);

/// The column a header cell names: the alias one of whose `names` (normalised, null for unused
/// entries) is the normalised cell, bare (unit null) or followed by a unit's `suffix` of the
/// same `quantity` ("lat", "latdeg", "timems"). `units` are tried in order: list the longest
/// suffixes first, so "seconds" is not read as "second" + "s". {null, null} when none matches.
template <class Alias, class Unit>
std::pair<const Alias*, const Unit*> matchColumn(std::span<const Alias> aliases, std::span<const Unit> units,
                                                 std::string_view header) {
    const auto find = [&](std::string_view n) -> const Alias* {
        for (const Alias& a : aliases)
            for (const char* name : a.names)
                if (name && n == name) return &a;
        return nullptr;
    };
    const std::string n = normalise(header);
    if (const Alias* a = find(n)) return {a, nullptr};
    for (const Unit& u : units) {
        const std::string_view suffix = u.suffix;
        if (n.size() <= suffix.size() || n.compare(n.size() - suffix.size(), suffix.size(), suffix) != 0) continue;
        const Alias* a = find(std::string_view(n).substr(0, n.size() - suffix.size()));
        if (a && a->quantity == u.quantity) return {a, &u};
    }
    return {nullptr, nullptr};
}

}  // namespace orbis::csv
