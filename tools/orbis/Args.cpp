#include "tools/orbis/Args.h"

#include <charconv>
#include <cmath>
#include <cstdint>

namespace orbis::cli {

Args::Args(const std::vector<std::string>& argv, const std::set<std::string>& valued,
           const std::set<std::string>& flags, const std::map<std::string, std::string>& aliases) {
    for (size_t i = 0; i < argv.size(); ++i) {
        std::string arg = argv[i];
        if (arg.size() < 2 || arg[0] != '-' || arg == "--") {
            if (arg == "--") {
                positional_.insert(positional_.end(), argv.begin() + long(i) + 1, argv.end());
                break;
            }
            positional_.push_back(arg);
            continue;
        }
        std::optional<std::string> inlineValue;
        if (auto eq = arg.find('='); eq != std::string::npos && arg.rfind("--", 0) == 0) {
            inlineValue = arg.substr(eq + 1);
            arg = arg.substr(0, eq);
        }
        if (auto a = aliases.find(arg); a != aliases.end()) arg = a->second;
        if (valued.count(arg)) {
            if (!inlineValue) {
                if (i + 1 >= argv.size()) throw UsageError{"option " + arg + " needs a value"};
                inlineValue = argv[++i];
            }
            values_[arg] = *inlineValue;
            all_[arg].push_back(*inlineValue);
        } else if (flags.count(arg)) {
            if (inlineValue) throw UsageError{"option " + arg + " takes no value"};
            flags_.insert(arg);
        } else {
            throw UsageError{"unknown option " + arg};
        }
    }
}

int Args::count(const std::string& name) const { return static_cast<int>(flags_.count(name)); }

std::vector<std::string> Args::values(const std::string& name) const {
    auto it = all_.find(name);
    return it == all_.end() ? std::vector<std::string>{} : it->second;
}

std::optional<std::string> Args::value(const std::string& name) const {
    auto it = values_.find(name);
    if (it == values_.end()) return std::nullopt;
    return it->second;
}

std::optional<long> Args::integer(const std::string& name, long min, long max) const {
    auto v = value(name);
    if (!v) return std::nullopt;
    long out = 0;
    auto [ptr, ec] = std::from_chars(v->data(), v->data() + v->size(), out);
    if (ec != std::errc() || ptr != v->data() + v->size())
        throw UsageError{"option " + name + " expects an integer, got '" + *v + "'"};
    if (out < min || out > max)
        throw UsageError{"option " + name + " must be in [" + std::to_string(min) + ", " + std::to_string(max) +
                         "], got " + *v};
    return out;
}

std::optional<double> Args::number(const std::string& name, double min, double max) const {
    auto v = value(name);
    if (!v) return std::nullopt;
    double out = 0;
    auto [ptr, ec] = std::from_chars(v->data(), v->data() + v->size(), out);
    if (ec != std::errc() || ptr != v->data() + v->size() || !std::isfinite(out))
        throw UsageError{"option " + name + " expects a number, got '" + *v + "'"};
    if (out < min || out > max)
        throw UsageError{"option " + name + " must be in [" + std::to_string(min) + ", " + std::to_string(max) +
                         "], got " + *v};
    return out;
}

std::optional<std::pair<uint32_t, uint32_t>> Args::size(const std::string& name) const {
    auto v = value(name);
    if (!v) return std::nullopt;
    const auto x = v->find('x');
    uint32_t w = 0, h = 0;
    bool ok = x != std::string::npos;
    if (ok) {
        auto r1 = std::from_chars(v->data(), v->data() + x, w);
        auto r2 = std::from_chars(v->data() + x + 1, v->data() + v->size(), h);
        ok = r1.ec == std::errc() && r1.ptr == v->data() + x && r2.ec == std::errc() &&
             r2.ptr == v->data() + v->size();
    }
    if (!ok || w < 1 || h < 1 || w > 16384 || h > 16384)
        throw UsageError{"option " + name + " expects WIDTHxHEIGHT with each in [1, 16384], got '" + *v + "'"};
    return std::make_pair(w, h);
}

}  // namespace orbis::cli
