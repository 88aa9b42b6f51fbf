#pragma once
// The scene key "auth" of a layer whose source is a server (terrain imagery or elevation from a
// WMS, a vector layer from a WFS): the environment variables that hold its HTTP credentials,
//   "auth": {"basicEnv": "ORBIS_WMS_USERPWD"}    the variable holds "user:password"
//   "auth": {"headerEnv": "ORBIS_WMS_HEADER"}    the variable holds one header, "Name: value"
// A scene file names the variables only: the credentials never reach it, and a saved scene
// writes back the same names.

#include "engine/scene/JsonReader.h"
#include "globe/GdalSetup.h"

#include <string>

namespace orbis::layers {

/// Reads `r`'s "auth" object (absent: no credentials). A variable that is not set or not well
/// formed fails the key, naming the variable, never its value.
inline globe::HttpAuth readHttpAuth(scene::JsonReader& r, const std::string& file, const std::string& path) {
    globe::HttpAuth auth;
    const nlohmann::json* object = r.object("auth");
    if (!object) return auth;
    scene::JsonReader a(*object, file, path + "/auth");
    auth.basicEnv = a.string("basicEnv", std::string()).value_or("");
    auth.headerEnv = a.string("headerEnv", std::string()).value_or("");
    if (auto done = a.finish(); !done) {
        const std::string prefix = file + ": " + path + "/auth/", m = done.message();
        r.fail("auth", m.rfind(prefix, 0) == 0 ? m.substr(prefix.size()) : m);
        return auth;
    }
    if (!auth.any()) r.fail("auth", "name \"basicEnv\" (a variable holding user:password) or \"headerEnv\" (one holding \"Name: value\")");
    else if (auto ok = globe::checkHttpAuth(auth); !ok) r.fail("auth", ok.message());
    return auth;
}

}  // namespace orbis::layers
