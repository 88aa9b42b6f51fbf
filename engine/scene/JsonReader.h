#pragma once
// Reads one JSON object field by field and reports the first problem as
// "<file>: <json path>: <what is wrong>". Keys that nobody asked for are reported too (a typo
// such as "visble" must not be silently ignored). Layers use it to read their own settings.

#include "base/Result.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

namespace orbis::scene {

class JsonReader {
public:
    /// `object` must outlive the reader. `path` is a JSON pointer such as "/layers/2".
    JsonReader(const nlohmann::json& object, std::string file, std::string path);

    bool isObject() const { return object_.is_object(); }
    bool has(const char* key) const;

    std::optional<double> number(const char* key, std::optional<double> fallback = std::nullopt,
                                 double min = -1e300, double max = 1e300);
    std::optional<std::string> string(const char* key, std::optional<std::string> fallback = std::nullopt);
    std::optional<bool> boolean(const char* key, std::optional<bool> fallback = std::nullopt);
    /// An array of exactly `count` numbers (count 0: any length).
    std::optional<std::vector<double>> numbers(const char* key, size_t count,
                                               std::optional<std::vector<double>> fallback = std::nullopt);
    /// A sub-object, or null when absent and not required.
    const nlohmann::json* object(const char* key, bool required = false);
    /// A sub-array, or null when absent and not required.
    const nlohmann::json* array(const char* key, bool required = false);
    /// Marks a key as known without reading it (read elsewhere).
    void accept(const char* key) { used_.insert(key); }

    /// Records an error about `key` (first error wins).
    void fail(const std::string& key, const std::string& what);
    std::string pathOf(const std::string& key) const { return path_ + "/" + key; }

    /// Checks for unknown keys, then returns the first error, if any.
    Result<void> finish();
    bool ok() const { return !error_; }

private:
    const nlohmann::json* get(const char* key, bool required, const char* expected);

    const nlohmann::json& object_;
    std::string file_, path_;
    std::set<std::string> used_;
    std::optional<Error> error_;
};

/// The JSON type as a user reads it: "a number", "a string", ...
std::string describeJsonType(const nlohmann::json& value);

/// Parses a whole JSON document (scene files, camera paths). A syntax error reads
/// "<file>: line L, column C: syntax error ...", the position counted from 1.
Result<nlohmann::json> parseJsonText(std::string_view text, const std::string& file);

/// The shortest form of a number for messages: "12" rather than "12.000000", and any double
/// (-5e+200, NaN) without converting it to an integer it does not fit.
std::string formatJsonNumber(double v);

}  // namespace orbis::scene
