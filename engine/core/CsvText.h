#pragma once
// Small pieces shared by the CSV readers (FMV pose sidecars, trajectories): splitting a line,
// guessing the separator, and recognising column names and empty cells. No I/O.

#include <string>
#include <string_view>
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

}  // namespace orbis::csv
