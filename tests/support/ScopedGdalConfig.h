#pragma once

#include "globe/GdalSetup.h"

#include <cpl_conv.h>

#include <optional>
#include <string>

namespace orbis::test {

/// Sets one GDAL configuration option for a scope and puts back what was there before (a value,
/// or none). GDAL is configured first, so its defaults are in place before the scope changes one.
/// Tests that run in one process (the sanitizer builds run a whole test binary at once) then never
/// see another test's timeouts, nor lose the defaults configureGdal() sets only once.
class ScopedGdalConfig {
public:
    ScopedGdalConfig(const char* key, const char* value) : key_(key) {
        globe::configureGdal();
        if (const char* old = CPLGetConfigOption(key, nullptr)) previous_ = old;
        CPLSetConfigOption(key, value);
    }
    ~ScopedGdalConfig() { CPLSetConfigOption(key_.c_str(), previous_ ? previous_->c_str() : nullptr); }
    ScopedGdalConfig(const ScopedGdalConfig&) = delete;
    ScopedGdalConfig& operator=(const ScopedGdalConfig&) = delete;

private:
    std::string key_;
    std::optional<std::string> previous_;
};

}  // namespace orbis::test
