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

/// Builds the document as nlohmann's own parser does, and knows where it is (the JSON pointer of
/// the value being read), so that an error other than syntax names the key: a number too large
/// for a double ("1e400") or a string that is not UTF-8 would otherwise say neither.
class LocatingSax {
public:
    using Json = nlohmann::json;
    explicit LocatingSax(Json& result) : dom_(result, /*allow_exceptions=*/false) {}

    bool null() { return scalar(dom_.null()); }
    bool boolean(bool v) { return scalar(dom_.boolean(v)); }
    bool number_integer(Json::number_integer_t v) { return scalar(dom_.number_integer(v)); }
    bool number_unsigned(Json::number_unsigned_t v) { return scalar(dom_.number_unsigned(v)); }
    bool number_float(Json::number_float_t v, const Json::string_t& text) { return scalar(dom_.number_float(v, text)); }
    bool string(Json::string_t& v) { return scalar(dom_.string(v)); }
    bool binary(Json::binary_t& v) { return scalar(dom_.binary(v)); }
    bool start_object(std::size_t n) {
        levels_.push_back({false, 0, {}});
        return dom_.start_object(n);
    }
    bool key(Json::string_t& k) {
        levels_.back().key = k;
        return dom_.key(k);
    }
    bool end_object() { return end(dom_.end_object()); }
    bool start_array(std::size_t n) {
        levels_.push_back({true, 0, {}});
        return dom_.start_array(n);
    }
    bool end_array() { return end(dom_.end_array()); }
    bool parse_error(std::size_t position, const std::string& token, const nlohmann::detail::exception& e) {
        position_ = position;
        tokenStart_ = position >= token.size() ? position - token.size() : 0;
        what_ = e.what();
        failed_ = true;
        return false;
    }

    bool failed() const { return failed_; }
    std::size_t position() const { return position_; }
    /// The byte where the token in error starts.
    std::size_t tokenStart() const { return tokenStart_; }
    const std::string& what() const { return what_; }
    /// The JSON pointer of the value being read ("" at the top).
    std::string pointer() const {
        std::string p;
        for (const Level& l : levels_) p += "/" + (l.array ? std::to_string(l.index) : l.key);
        return p;
    }

private:
    struct Level {
        bool array;
        std::size_t index;   ///< arrays: the element being read
        std::string key;     ///< objects: the member being read
    };
    bool scalar(bool ok) {
        if (!levels_.empty() && levels_.back().array) ++levels_.back().index;
        return ok;
    }
    bool end(bool ok) {
        levels_.pop_back();
        return scalar(ok);
    }

    nlohmann::detail::json_sax_dom_parser<Json> dom_;
    std::vector<Level> levels_;
    bool failed_ = false;
    std::size_t position_ = 0, tokenStart_ = 0;
    std::string what_;
};

}  // namespace

Result<nlohmann::json> parseJsonText(std::string_view text, const std::string& file) {
    nlohmann::json result;
    LocatingSax sax(result);
    nlohmann::json::sax_parse(text.begin(), text.end(), &sax, nlohmann::json::input_format_t::json, /*strict=*/true);
    if (!sax.failed()) return result;
    // "[json.exception.parse_error.101] parse error at line 1, column 2: syntax error ..." -> keep the tail
    std::string what = sax.what();
    if (const auto syntax = what.find("syntax error"); syntax != std::string::npos)
        return Error{file + ": " + lineColumn(text, sax.position() ? sax.position() - 1 : 0) + ": " + what.substr(syntax)};
    const std::string where = lineColumn(text, sax.tokenStart());
    // Anything else (a number out of range) is about a value: name its key.
    if (const auto tag = what.find("] "); tag != std::string::npos) what = what.substr(tag + 2);
    const std::string pointer = sax.pointer();
    return Error{file + ": " + (pointer.empty() ? "/" : pointer) + " (" + where + "): " + what};
}

std::string formatJsonNumber(double v) {
    if (std::floor(v) == v && std::abs(v) < 1e15) return std::to_string(static_cast<long long>(v));
    return nlohmann::json(v).dump();
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
