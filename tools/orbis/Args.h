#pragma once
// A small command-line parser: options with values (--size 640x480 or --size=640x480), flags,
// and positional arguments. Problems are usage errors (exit code 2) with a message.

#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace orbis::cli {

struct UsageError {
    std::string message;
};

class Args {
public:
    /// `valued`: options that take a value; `flags`: options that do not. Short aliases map to
    /// long names, e.g. {"-o", "--output"}. Throws UsageError.
    Args(const std::vector<std::string>& argv, const std::set<std::string>& valued, const std::set<std::string>& flags,
         const std::map<std::string, std::string>& aliases = {});

    bool flag(const std::string& name) const { return flags_.count(name) != 0; }
    int count(const std::string& name) const;
    /// The last value given (an option given twice keeps the second).
    std::optional<std::string> value(const std::string& name) const;
    /// Every value given, in order (options that may repeat: --input a=1 --input b=2).
    std::vector<std::string> values(const std::string& name) const;
    const std::vector<std::string>& positional() const { return positional_; }

    /// Integer in [min, max]; throws UsageError naming the option.
    std::optional<long> integer(const std::string& name, long min, long max) const;
    /// Finite number in [min, max]; throws UsageError naming the option.
    std::optional<double> number(const std::string& name, double min, double max) const;
    /// "WxH" with both in [1, 16384]; throws UsageError.
    std::optional<std::pair<uint32_t, uint32_t>> size(const std::string& name) const;

private:
    std::map<std::string, std::string> values_;
    std::map<std::string, std::vector<std::string>> all_;
    std::multiset<std::string> flags_;
    std::vector<std::string> positional_;
};

}  // namespace orbis::cli
