#include "engine/scene/JsonReader.h"

#include <cmath>

namespace orbis::scene {
namespace {

// nlohmann reports a byte offset; users want line and column.
std::string lineColumn(std::string_view text, size_t byte) {
    size_t line = 1, column = 1;
    for (size_t i = 0; i < byte && i < text.size(); ++i) {
        if (text[i] == '\n') ++line, column = 1;
        else ++column;
    }
    return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

}  // namespace

Result<nlohmann::json> parseJsonText(std::string_view text, const std::string& file) {
    try {
        return nlohmann::json::parse(text.begin(), text.end());
    } catch (const nlohmann::json::parse_error& e) {
        std::string what = e.what();
        // "[json.exception.parse_error.101] parse error at line 1, column 2: syntax error ..." -> keep the tail
        const auto pos = what.find("syntax error");
        what = pos != std::string::npos ? what.substr(pos) : "invalid JSON";
        return Error{file + ": " + lineColumn(text, e.byte ? e.byte - 1 : 0) + ": " + what};
    }
}

std::string describeJsonType(const nlohmann::json& v) {
    switch (v.type()) {
        case nlohmann::json::value_t::null: return "null";
        case nlohmann::json::value_t::boolean: return "a boolean";
        case nlohmann::json::value_t::number_integer:
        case nlohmann::json::value_t::number_unsigned:
        case nlohmann::json::value_t::number_float: return "a number";
        case nlohmann::json::value_t::string: return "a string";
        case nlohmann::json::value_t::array: return "an array";
        case nlohmann::json::value_t::object: return "an object";
        default: return "an unsupported value";
    }
}

JsonReader::JsonReader(const nlohmann::json& object, std::string file, std::string path)
    : object_(object), file_(std::move(file)), path_(std::move(path)) {
    if (!object_.is_object())
        error_ = Error{file_ + ": " + (path_.empty() ? "/" : path_) + ": expected an object, got " +
                       describeJsonType(object_)};
}

bool JsonReader::has(const char* key) const { return object_.is_object() && object_.contains(key); }

void JsonReader::fail(const std::string& key, const std::string& what) {
    if (!error_) error_ = Error{file_ + ": " + pathOf(key) + ": " + what};
}

const nlohmann::json* JsonReader::get(const char* key, bool required, const char* expected) {
    used_.insert(key);
    if (error_ || !object_.is_object()) return nullptr;
    auto it = object_.find(key);
    if (it == object_.end()) {
        if (required) fail(key, std::string("missing; expected ") + expected);
        return nullptr;
    }
    return &*it;
}

std::optional<double> JsonReader::number(const char* key, std::optional<double> fallback, double min, double max) {
    const nlohmann::json* v = get(key, !fallback.has_value(), "a number");
    if (!v) return error_ ? std::nullopt : fallback;
    if (!v->is_number()) {
        fail(key, "expected a number, got " + describeJsonType(*v));
        return std::nullopt;
    }
    const double d = v->get<double>();
    if (!std::isfinite(d) || d < min || d > max) {
        fail(key, "value " + v->dump() + " is out of range [" + nlohmann::json(min).dump() + ", " +
                      nlohmann::json(max).dump() + "]");
        return std::nullopt;
    }
    return d;
}

std::optional<std::string> JsonReader::string(const char* key, std::optional<std::string> fallback) {
    const nlohmann::json* v = get(key, !fallback.has_value(), "a string");
    if (!v) return error_ ? std::nullopt : fallback;
    if (!v->is_string()) {
        fail(key, "expected a string, got " + describeJsonType(*v));
        return std::nullopt;
    }
    return v->get<std::string>();
}

std::optional<bool> JsonReader::boolean(const char* key, std::optional<bool> fallback) {
    const nlohmann::json* v = get(key, !fallback.has_value(), "a boolean");
    if (!v) return error_ ? std::nullopt : fallback;
    if (!v->is_boolean()) {
        fail(key, "expected a boolean (true or false), got " + describeJsonType(*v));
        return std::nullopt;
    }
    return v->get<bool>();
}

std::optional<std::vector<double>> JsonReader::numbers(const char* key, size_t count,
                                                       std::optional<std::vector<double>> fallback) {
    const std::string expected = count ? "an array of " + std::to_string(count) + " numbers" : "an array of numbers";
    const nlohmann::json* v = get(key, !fallback.has_value(), expected.c_str());
    if (!v) return error_ ? std::nullopt : fallback;
    if (!v->is_array() || (count && v->size() != count)) {
        fail(key, "expected " + expected + ", got " + (v->is_array() ? "an array of " + std::to_string(v->size()) : describeJsonType(*v)));
        return std::nullopt;
    }
    std::vector<double> out;
    for (size_t i = 0; i < v->size(); ++i) {
        const auto& e = (*v)[i];
        if (!e.is_number() || !std::isfinite(e.get<double>())) {
            fail(std::string(key) + "/" + std::to_string(i), "expected a number, got " + describeJsonType(e));
            return std::nullopt;
        }
        out.push_back(e.get<double>());
    }
    return out;
}

const nlohmann::json* JsonReader::object(const char* key, bool required) {
    const nlohmann::json* v = get(key, required, "an object");
    if (v && !v->is_object()) {
        fail(key, "expected an object, got " + describeJsonType(*v));
        return nullptr;
    }
    return v;
}

const nlohmann::json* JsonReader::array(const char* key, bool required) {
    const nlohmann::json* v = get(key, required, "an array");
    if (v && !v->is_array()) {
        fail(key, "expected an array, got " + describeJsonType(*v));
        return nullptr;
    }
    return v;
}

Result<void> JsonReader::finish() {
    if (!error_ && object_.is_object()) {
        for (auto it = object_.begin(); it != object_.end(); ++it) {
            if (!used_.count(it.key())) {
                std::string known;
                for (const auto& k : used_) known += (known.empty() ? "" : ", ") + k;
                fail(it.key(), "unknown key '" + it.key() + "' (known here: " + known + ")");
                break;
            }
        }
    }
    if (error_) return *error_;
    return {};
}

}  // namespace orbis::scene
